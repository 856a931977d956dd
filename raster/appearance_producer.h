#pragma once
// The appearance producer (§5.1): for one quad, the colour and water mask (RGBm) of the ground,
// areas (lakes, fields, forests), rivers and roads, rasterized from the quad's clipped graph.
//
// Drawing order: areas of field, forest and other layers, then lakes, rivers, roads; within a
// layer by ancestor id, so the result does not depend on hash-map order. Each element is
// composited over what is below with its anti-aliased coverage.
// - Ground: colour by altitude and slope, from the DEM on a grid of `groundCells` per quad side
//   (fewer in small quads: cells of `groundCellMin` metres at least) aligned with the quad
//   (adjacent quads share its nodes), bilinear between.
// - Areas: interiors triangulated with CGAL's constrained Delaunay triangulation (contour, holes
//   and closing paths) and rasterized; coverage near the real border (not the closing paths)
//   from the exact distance to it, the box filter of edgeCoverage() on each side; a border strip
//   of width wf outside (banks, field margins, forest edges).
// - Curves: each texel near a curve takes the distance to its nearest refined segment (found
//   among the few that can be nearest in its block of texels, measured four texels at a time in
//   float in the block's frame: within about 1e-6 of the block's reach of the exact one), and
//   that segment gives the texel its (u, v), so the result is the band of the distance to the polyline: joins at sharp
//   turns and hairpins wider than their radius have no spike and no gap, ends get round caps
//   and junctions are the union of the roads' discs.
//   Rivers: water (mask 1) within w/2, banks to wf/2; a Rivers layer's areas are water, drawn
//   after its banks and before its water. Roads: asphalt within w/2; then, once all the roads of
//   the layer are down, markings: side lines, a dashed centre line from u, and stop lines from
//   the ancestor node's degree (model/junctions.h), yield lines where a road enters a roundabout's
//   ring (kYieldAtStart / kYieldAtEnd); markings stop at junctions, rings and bridge ends.
//   Bridges (kBridge) are not drawn: their decks are object meshes (raster/object_meshes.h) and
//   the river shows under them; a tunnel (kTunnel) is drawn only as its portals
//   (`tunnelPortalLength` at each end).
// - Uniform quads: when the last thing drawn covers the whole tile (an area surrounding the
//   quad, or a river whose one segment holds the tile within w/2), nothing is rasterized and the
//   tile stores only its SurfaceShade.
//
// Thread safety: as produceElevation(); per-thread scratch buffers are reused between calls.
// `cancel` (may be null) is checked between the elements drawn (model/cancel.h).

#include <atomic>
#include <vector>

#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/appearance_tile.h"
#include "raster/dem.h"
#include "model/cancel.h"

namespace lacet {

// Accuracy knobs of the appearance. The tile's resolution and border are the quadtree's grid
// (quadtree.params(): TileGrid::resolution, the one the refinement tolerance is measured in, and
// TileGrid::appearanceBorder, the one the quadtree clips for).
struct AppearanceParams {
    int samples = 1;                // supersampling, samples x samples per texel (1..8), each with analytic edge coverage
    double markingMinTexels = 0.5;  // texels: road markings narrower than this are not drawn, and u is not asked for
    int groundCells = 32;           // cells of the ground colour grid per quad side, >= 1
    double groundCellMin = 5.0;     // m: smallest cell of that grid (the colour varies at the DEM's
                                    // scale, 20 to 30 m; finer cells cost time and change nothing seen)
    bool detectUniform = true;      // false: rasterize uniform quads too (for tests)
    double tunnelPortalLength = 6.0; // m at each end of a tunnel drawn as its portal
    std::vector<bool> hiddenLayers; // layers not drawn (index: LayerId; missing: shown)
};

struct AppearanceCounters {
    std::atomic<std::size_t> tiles{0};
    std::atomic<std::size_t> uniformTiles{0};
    std::atomic<std::size_t> curvesDrawn{0};
    std::atomic<std::size_t> curvesWithMarkings{0};
    std::atomic<std::size_t> markingsBelowTexel{0};  // roads whose markings were skipped (no u asked)
    std::atomic<std::size_t> areaPieces{0};
    std::atomic<std::size_t> triangles{0};           // area interior triangles rasterized
    std::atomic<std::size_t> waterTexels{0};         // texels with a water mask > 0
};

AppearanceTile produceAppearance(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData,
                                 const Dem& dem, const AppearanceParams& params, AppearanceCounters* counters = nullptr,
                                 const CancelFlag* cancel = nullptr);

// The texels of a tile (stride * stride * 4 bytes): a copy of rgbm, or for a uniform tile the
// texels the producer would have drawn.
std::vector<std::uint8_t> tileTexels(const AppearanceTile& tile);

}  // namespace lacet
