#include "editor/look_ahead.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace lacet {

FrameViewers LookAhead::next(glm::dvec3 eye, double height) {
    FrameViewers out;
    out.viewer = glm::dvec3(eye.x, eye.y, height);
    const glm::dvec3 velocity = lastEye_ ? eye - *lastEye_ : glm::dvec3(0.0);
    lastEye_ = eye;
    if (glm::length(velocity) > params_.stillFraction * height) {
        const glm::dvec3 ahead = eye + velocity * params_.framesAhead;
        out.predicted = glm::dvec3(ahead.x, ahead.y, std::max(1.0, height + (ahead.z - eye.z)));
    }
    return out;
}

}  // namespace lacet
