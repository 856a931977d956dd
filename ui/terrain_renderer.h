#pragma once
// Draws the terrain of an editing session (§8): one flat grid per leaf quad of the view-refined
// quadtree, displaced in the vertex shader by its elevation texture (z_m, morphing to z_c as the
// leaf nears the distance where it would merge into its parent, so a level change neither pops
// nor leaves a step) and coloured by its appearance texture: Lambert shading for the ground, and
// Fresnel reflection of the sky where the appearance's water mask says water (the water path
// runs only on tiles that hold water, and in them only where the mask is set).
//
// What is drawn is the session's draw plan (editor/draw_plan.h), decided once by the session:
// each leaf with the tile that stands for it (an ancestor's while its own is being made) and the
// reach of its skirt, the vertical strip hanging from its border so that where two neighbours of
// different levels or tiles do not meet exactly, no background shows through. The renderer adds
// only what the GPU needs: uploads, and leaving out leaves whose tile's box is outside the frustum.
//
// Textures live on the GPU per tile (RG32F z_m, z_c; RGBA8 appearance with mipmaps), copied again
// when the session remakes the tile, and released with it.

#include <map>

#include <epoxy/gl.h>
#include <glm/vec3.hpp>

#include "editor/edit_session.h"
#include "editor/camera.h"
#include "ui/gl_program.h"

namespace lacet::ui {

struct TerrainStats {
    std::size_t drawn = 0;     // leaves drawn
    std::size_t culled = 0;    // leaves outside the frustum (the session's test, or their tile's box)
    std::size_t fallback = 0;  // leaves drawn with an ancestor's tile
    std::size_t missing = 0;   // leaves with no tile and no ancestor tile (not drawn)
    std::size_t uploads = 0;   // tiles copied to the GPU this frame
    std::size_t gpuTiles = 0;
};

struct TerrainView {
    const Camera* camera = nullptr;
    int width = 0, height = 0;
    glm::dvec2 clip{1.0, 1e5};
    double heightAboveGround = 100.0;  // the viewer's height for the K rule (as EditSession::frame)
};

class TerrainRenderer {
public:
    TerrainRenderer();
    ~TerrainRenderer();
    TerrainRenderer(const TerrainRenderer&) = delete;
    TerrainRenderer& operator=(const TerrainRenderer&) = delete;

    void draw(const EditSession& session, const TerrainView& view);
    // Releases every GPU tile (a new session).
    void reset();

    const TerrainStats& stats() const { return stats_; }
    glm::vec3 sun{0.4f, -0.3f, 0.866f};
    bool wireframe = false;

private:
    struct GpuTile {
        GLuint elevation = 0, appearance = 0;
        std::uint64_t version = 0;
        bool water = false;
        float zmin = 0.0f, zmax = 0.0f;
        std::uint64_t lastFrame = 0;
    };
    const GpuTile* upload(const QuadKey& key, const CachedTile& tile);
    void buildGrid(int n);

    GlProgram program_;
    GLuint vao_ = 0, vbo_ = 0, ibo_ = 0;
    GLsizei indexCount_ = 0;
    int gridN_ = 0;
    std::map<QuadKey, GpuTile> gpu_;
    std::uint64_t frame_ = 0;
    TerrainStats stats_;
};

}  // namespace lacet::ui
