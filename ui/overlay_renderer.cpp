#include "ui/overlay_renderer.h"

#include <glm/gtc/type_ptr.hpp>

namespace lacet::ui {
namespace {

const char* kOverlayVertex = R"(#version 410 core
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec4 aColour;
layout(location = 2) in float aSize;
uniform mat4 uViewProj;
out vec4 vColour;
void main() {
    vColour = aColour;
    gl_PointSize = aSize;
    gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

const char* kOverlayFragment = R"(#version 410 core
in vec4 vColour;
uniform int uPoints;
out vec4 oColour;
void main() {
    if (uPoints != 0) {
        vec2 d = gl_PointCoord - vec2(0.5);
        float r = dot(d, d);
        if (r > 0.25) discard;
        oColour = r > 0.12 ? vec4(0.0, 0.0, 0.0, 1.0) : vColour;  // a dark rim
    } else {
        oColour = vColour;
    }
}
)";

}  // namespace

OverlayRenderer::OverlayRenderer() : program_("overlay", kOverlayVertex, kOverlayFragment) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    const GLsizei stride = 8 * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(7 * sizeof(float)));
    glBindVertexArray(0);
}

OverlayRenderer::~OverlayRenderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void OverlayRenderer::clear() {
    lines_.clear();
    points_.clear();
    linePos_.clear();
    pointPos_.clear();
}

void OverlayRenderer::line(glm::dvec3 a, glm::dvec3 b, glm::vec4 c) {
    for (const glm::dvec3& p : {a, b}) {
        linePos_.push_back(p);
        lines_.insert(lines_.end(), {0.0f, 0.0f, 0.0f, c.r, c.g, c.b, c.a, 1.0f});
    }
}

void OverlayRenderer::point(glm::dvec3 p, glm::vec4 c, float sizePx) {
    pointPos_.push_back(p);
    points_.insert(points_.end(), {0.0f, 0.0f, 0.0f, c.r, c.g, c.b, c.a, sizePx});
}

void OverlayRenderer::draw(glm::dvec3 eye, const glm::dmat4& viewProj) {
    auto relative = [&](std::vector<float>& v, const std::vector<glm::dvec3>& pos) {
        for (std::size_t k = 0; k < pos.size(); ++k) {
            const glm::dvec3 r = pos[k] - eye;
            v[8 * k] = float(r.x), v[8 * k + 1] = float(r.y), v[8 * k + 2] = float(r.z);
        }
    };
    relative(lines_, linePos_);
    relative(points_, pointPos_);
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(glm::mat4(viewProj)));
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    if (!lines_.empty()) {
        glUniform1i(program_.uniform("uPoints"), 0);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines_.size() * sizeof(float)), lines_.data(), GL_STREAM_DRAW);
        glDrawArrays(GL_LINES, 0, GLsizei(lines_.size() / 8));
    }
    if (!points_.empty()) {
        glUniform1i(program_.uniform("uPoints"), 1);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(points_.size() * sizeof(float)), points_.data(), GL_STREAM_DRAW);
        glDrawArrays(GL_POINTS, 0, GLsizei(points_.size() / 8));
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

}  // namespace lacet::ui
