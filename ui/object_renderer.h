#pragma once
// Draws the object meshes (§5.3: bridges, trees) the session's draw plan carries
// (DrawItem::objects, once per tile), lit like the terrain: Lambert with an ambient term, the
// terrain renderer's sun, both faces lit (a face seen from behind takes the opposite normal).
// Each mesh is drawn camera-relative (its quad's origin minus the eye, in doubles, then float),
// as the terrain is, so that vertices far from the scene's origin keep their precision.
//
// GPU copies: one vertex and index buffer per tile, uploaded once per tile version, released when
// the session drops the tile or when it has not been drawn for a while.

#include <map>

#include <epoxy/gl.h>
#include <glm/vec3.hpp>

#include "editor/camera.h"
#include "editor/edit_session.h"
#include "ui/gl_program.h"

namespace lacet::ui {

struct ObjectStats {
    std::size_t meshes = 0;     // meshes drawn
    std::size_t triangles = 0;  // triangles drawn
    std::size_t culled = 0;     // meshes outside the frustum
    std::size_t uploads = 0;    // meshes copied to the GPU this frame
    std::size_t gpuMeshes = 0;
};

class ObjectRenderer {
public:
    ObjectRenderer();
    ~ObjectRenderer();
    ObjectRenderer(const ObjectRenderer&) = delete;
    ObjectRenderer& operator=(const ObjectRenderer&) = delete;

    // Draws the plan's objects with the camera of the frame (`aspect`, `clip` as the terrain's)
    // and the sun direction (towards the sun, any length).
    void draw(const EditSession& session, const Camera& camera, double aspect, glm::dvec2 clip, glm::vec3 sun);
    // Releases every GPU mesh (a new session).
    void reset();

    const ObjectStats& stats() const { return stats_; }

private:
    struct GpuMesh {
        GLuint vao = 0, vbo = 0, ibo = 0;
        GLsizei count = 0;
        std::uint64_t version = 0;
        std::uint64_t lastFrame = 0;
    };
    GpuMesh& upload(const QuadKey& key, const CachedTile& tile);
    static void release(GpuMesh& g);

    GlProgram program_;
    std::map<QuadKey, GpuMesh> gpu_;
    std::uint64_t frame_ = 0;
    ObjectStats stats_;
};

}  // namespace lacet::ui
