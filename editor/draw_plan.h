#pragma once
// What a frame shows (§8 of the paper: the terrain is drawn leaf by leaf with each quad's
// textures, an ancestor's while a quad's own are being made): the one place that decides which
// tile stands for each leaf. The session (EditSession::plan()) makes the plan from the tree and
// the tiles frame() left; the renderer uploads and draws it and decides nothing; the height shown at a point
// (EditSession::displayedHeight, what picks and the overlay stand on) reads the same plan.
//
// A plan lists every leaf of the quadtree, the view's and the others (culled, or beyond the view),
// with the tile that stands for it: its own, else its nearest ancestor's that the cache holds
// (none before the first tile is made). A leaf is drawn when it passes the frame's visibility test
// and some tile stands for it; drawn with its own tile it geomorphs towards its parent (the K
// rule, model/view_params.h), with an ancestor's it does not. Its skirt (the band hung below its
// edges so that no crack shows between neighbours drawn at different levels) reaches a fraction
// of its size plus the slope times the coarsest sample spacing of an ancestor's tile drawn in the
// frame, which can stand that far below a neighbour's edge.
//
// The plan holds quad keys, bounds and pointers to the session's tiles, not pointers to quads:
// it stays valid across edits (which mark tiles dirty and keep them) until the next frame, and a
// change of refinement parameters (which drops every tile) clears it.

#include <cstdint>
#include <functional>
#include <tuple>
#include <vector>

#include "model/quadtree.h"
#include "model/types.h"
#include "raster/appearance_producer.h"
#include "raster/elevation_producer.h"
#include "raster/object_meshes.h"

namespace lacet {

using QuadKey = std::tuple<int, std::uint32_t, std::uint32_t>;  // level, x, y
QuadKey keyOf(const Quad& q);

struct CachedTile {
    AppearanceTile appearance;
    ElevationTile elevation;
    ObjectMesh objects;  // the quad's bridges and trees (§5.3), made with its elevation tile
    bool dirty = false;
    std::uint64_t lastUsed = 0;
    std::uint64_t version = 0;  // changes each time the tile is made (for GPU copies)
    // With a streamed DEM (io/dem_stream.h): the level its DEM window was cut from and the one
    // it wanted (-1: the DEM in memory whole); the tile is remade when finer blocks arrive.
    int demLevel = -1, demWanted = -1;
    // The appearance's texels as the window uploads them: stride x stride RGBA (the water mask in
    // alpha), uniform tiles expanded (raster/appearance_producer.h: tileTexels).
    std::vector<std::uint8_t> texels() const { return tileTexels(appearance); }
};

// How far skirts hang below the leaves' edges.
struct SkirtParams {
    double sizeFraction = 0.03;  // of the leaf's side (m per m), for the gaps between its own samples and a neighbour's
    // Metres of skirt per metre of the coarsest ancestor tile's sample spacing drawn in the frame:
    // a neighbour drawn with a coarser surface can stand below this leaf's edge by its slope over
    // one of its samples (slopes up to 2, 63 degrees).
    double slope = 2.0;
};

struct DrawItem {
    QuadKey leaf;                      // the leaf
    Box bounds;                        // its square (metres)
    QuadKey tileKey;                   // the quad whose tile stands for it (the leaf or an ancestor; the leaf when none does)
    const CachedTile* tile = nullptr;  // that tile; nullptr: none yet (not drawn)
    bool visible = false;              // passed the frame's visibility test
    double skirt = 0.0;                // metres below the edges
    // The objects (bridges, trees: §5.3) of the tile standing for it, on the first drawn item of
    // each tile only (a tile standing for several leaves has its objects drawn once); nullptr on
    // the others and where the tile has none.
    const ObjectMesh* objects = nullptr;
    bool ownTile() const { return tile && tileKey == leaf; }
    bool drawn() const { return visible && tile; }
};

struct DrawPlan {
    std::vector<DrawItem> items;  // every leaf, in the tree's order (depth first, children in order: Z-order)
    // The mesh each leaf is drawn with: a grid of gridCells x gridCells cells over its square (the
    // tile grid's elevation resolution, one vertex per sample) and its skirt; then the object
    // meshes (bridges, trees: §5.3) the items carry.
    int gridCells = 0;
    double coarsestAncestorDelta = 0.0;  // the largest sample spacing of an ancestor's tile drawn (m)
    std::size_t drawn = 0, fallback = 0, missing = 0, culled = 0;  // leaves drawn, drawn with an ancestor's tile, visible without a tile, not visible

    // The item of the leaf over `p` (outside the root: of a leaf along its nearest edge; nullptr:
    // an empty plan): the descent the tree makes, as a Z-order code, then a binary search.
    const DrawItem* itemAt(Vec2 p) const;
    void clear() { *this = DrawPlan{}; }

    // For itemAt: the root's square, the deepest leaf's level (at most ViewParams::kMaxLevel), and
    // each item's first Z-order code at that level (ascending).
    Box rootBounds;
    int deepest = 0;
    std::vector<std::uint64_t> zStart;
};

// The plan for `tree`: every leaf with the tile `tileOf` finds for it or its nearest ancestor,
// visible when `visible` (empty: every leaf) says so, with its skirt and its grid (the tree's
// elevation resolution).
DrawPlan makeDrawPlan(const Quadtree& tree, const std::function<const CachedTile*(const QuadKey&)>& tileOf,
                      const std::function<bool(const Quad&)>& visible, const SkirtParams& skirt);
// The same for a forest (editor/quad_forest.h): its quads as resolved.
class QuadForest;
DrawPlan makeDrawPlan(const QuadForest& forest, const std::function<const CachedTile*(const QuadKey&)>& tileOf,
                      const std::function<bool(const Quad&)>& visible, const SkirtParams& skirt);

}  // namespace lacet
