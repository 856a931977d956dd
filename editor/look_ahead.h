#pragma once
// The live loop's policy for one frame of the window (§8), apart from any window: the viewer the
// quadtree is refined for (the camera's ground position and height above the displayed ground),
// the viewer predicted a little later on the camera's path (tiles are prefetched for it), and the
// share of the frame's budget that subdivisions may take.
//
// Prediction: the camera's move since the previous frame, continued for `framesAhead` frames
// (half a second at 60 frames per second by default); no prediction while the camera stands still
// (it moved less than `stillFraction` of its height above the ground) or on the first frame.
//
// Order of calls: next() once a frame, with the camera's position and its height above the ground.

#include <optional>

#include <glm/vec3.hpp>

namespace lacet {

struct LookAheadParams {
    double framesAhead = 30.0;     // frames, > 0
    double stillFraction = 1e-3;   // of the height above the ground (m per m): a smaller move is standing still
    double refineShare = 0.5;      // of the frame's production budget, [0, 1]: what subdivisions may take
};

struct FrameViewers {
    glm::dvec3 viewer{0.0};               // x, y, height above the ground (metres)
    std::optional<glm::dvec3> predicted;  // the same, framesAhead frames later
};

class LookAhead {
public:
    explicit LookAhead(LookAheadParams params = {}) : params_(params) {}
    // The viewers of this frame, for a camera at `eye` (scene metres) `height` metres above the
    // displayed ground (>= 1).
    FrameViewers next(glm::dvec3 eye, double height);
    // The refinement budget of a frame whose production budget is `frameBudgetMs` (0: none, the
    // tree refined completely).
    double refineBudgetMs(double frameBudgetMs) const { return params_.refineShare * frameBudgetMs; }
    // Forgets the last position (a jump: no prediction from it).
    void reset() { lastEye_.reset(); }

private:
    LookAheadParams params_;
    std::optional<glm::dvec3> lastEye_;
};

}  // namespace lacet
