#include "ui/object_renderer.h"

#include <cstddef>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace lacet::ui {
namespace {

const char* kObjectVertex = R"(#version 410 core
layout(location = 0) in vec3 aPos;     // relative to the mesh's origin (m)
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aColour;  // sRGB, normalized
uniform mat4 uViewProj;
uniform vec3 uOrigin;                  // the mesh's origin minus the eye (m)
out vec3 vNormal;
out vec3 vColour;
void main() {
    vNormal = aNormal;
    vColour = aColour.rgb;
    gl_Position = uViewProj * vec4(aPos + uOrigin, 1.0);
}
)";

const char* kObjectFragment = R"(#version 410 core
in vec3 vNormal;
in vec3 vColour;
uniform vec3 uSun;
out vec4 oColor;
void main() {
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing) n = -n;  // both faces lit: the winding's normal, seen from either side
    oColor = vec4(vColour * (0.4 + 0.6 * max(dot(n, uSun), 0.0)), 1.0);  // Lambert + ambient, as the terrain
}
)";

}  // namespace

ObjectRenderer::ObjectRenderer() : program_("objects", kObjectVertex, kObjectFragment) {}

ObjectRenderer::~ObjectRenderer() { reset(); }

void ObjectRenderer::release(GpuMesh& g) {
    glDeleteBuffers(1, &g.ibo);
    glDeleteBuffers(1, &g.vbo);
    glDeleteVertexArrays(1, &g.vao);
    g = {};
}

void ObjectRenderer::reset() {
    for (auto& [key, g] : gpu_) release(g);
    gpu_.clear();
}

ObjectRenderer::GpuMesh& ObjectRenderer::upload(const QuadKey& key, const CachedTile& tile) {
    GpuMesh& g = gpu_[key];
    g.lastFrame = frame_;
    if (g.vao && g.version == tile.version) return g;
    if (!g.vao) {
        glGenVertexArrays(1, &g.vao);
        glGenBuffers(1, &g.vbo);
        glGenBuffers(1, &g.ibo);
    }
    g.version = tile.version;
    ++stats_.uploads;
    const ObjectMesh& m = tile.objects;
    glBindVertexArray(g.vao);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m.vertices.size() * sizeof(ObjectVertex)), m.vertices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(m.indices.size() * sizeof(std::uint32_t)), m.indices.data(), GL_STATIC_DRAW);
    const GLsizei stride = sizeof(ObjectVertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ObjectVertex, position)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ObjectVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, stride, reinterpret_cast<const void*>(offsetof(ObjectVertex, colour)));
    glBindVertexArray(0);
    g.count = GLsizei(m.indices.size());
    return g;
}

void ObjectRenderer::draw(const EditSession& session, const Camera& camera, double aspect, glm::dvec2 clip, glm::vec3 sun) {
    stats_ = {};
    ++frame_;
    const glm::dvec3 eye = camera.position();
    const Frustum frustum = camera.frustum(aspect, clip);
    const glm::dmat4 viewProj = camera.projection(aspect, clip) * camera.view();
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(glm::mat4(viewProj)));
    glUniform3fv(program_.uniform("uSun"), 1, glm::value_ptr(glm::normalize(sun)));
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    for (const DrawItem& item : session.plan().items) {
        if (!item.objects) continue;  // the plan carries each tile's objects once
        const ObjectMesh& m = *item.objects;
        const glm::dvec3 origin = m.origin - eye;
        if (!frustum.mayIntersect(origin + glm::dvec3(m.lo), origin + glm::dvec3(m.hi))) {
            ++stats_.culled;
            continue;
        }
        const GpuMesh& g = upload(item.tileKey, *item.tile);
        glUniform3f(program_.uniform("uOrigin"), float(origin.x), float(origin.y), float(origin.z));
        glBindVertexArray(g.vao);
        glDrawElements(GL_TRIANGLES, g.count, GL_UNSIGNED_INT, nullptr);
        ++stats_.meshes;
        stats_.triangles += std::size_t(g.count) / 3;
    }
    glBindVertexArray(0);
    // Release the copies of tiles the session dropped and of meshes not drawn for a while.
    for (auto it = gpu_.begin(); it != gpu_.end();) {
        const CachedTile* t = session.tile(it->first);
        if (!t || t->objects.empty() || frame_ - it->second.lastFrame > 600) {
            release(it->second);
            it = gpu_.erase(it);
        } else {
            ++it;
        }
    }
    stats_.gpuMeshes = gpu_.size();
}

}  // namespace lacet::ui
