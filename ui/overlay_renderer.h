#pragma once
// Draws the editing overlay over the terrain (Fig. 13): control polygons as lines, on-curve
// vertices, control points and nodes as round points of their own colours, and the road being
// drawn. Positions are given in scene metres and drawn camera-relative.

#include <vector>

#include <epoxy/gl.h>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "ui/gl_program.h"

namespace lacet::ui {

class OverlayRenderer {
public:
    OverlayRenderer();
    ~OverlayRenderer();
    OverlayRenderer(const OverlayRenderer&) = delete;
    OverlayRenderer& operator=(const OverlayRenderer&) = delete;

    void clear();
    void line(glm::dvec3 a, glm::dvec3 b, glm::vec4 colour);
    void point(glm::dvec3 p, glm::vec4 colour, float sizePx);
    // Draws what was added, over everything (no depth test).
    void draw(glm::dvec3 eye, const glm::dmat4& viewProj);
    std::size_t points() const { return points_.size() / 8; }

private:
    GlProgram program_;
    GLuint vao_ = 0, vbo_ = 0;
    std::vector<float> lines_, points_;  // x y z r g b a size (relative to eye_ when drawn)
    std::vector<glm::dvec3> linePos_, pointPos_;
};

}  // namespace lacet::ui
