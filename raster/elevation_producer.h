#pragma once
// The elevation producer (§5.2): for one quad, the DEM resampled on the tile grid (z_o), the
// footprint of its roads, rivers and lakes (z_e, b), combined with MAX so overlaps stay
// continuous (z_e follows the larger b; for equal b, the nearer axis), the modified height
// z_m = b z_e + (1 - b) z_o filtered by a 3x3 Gaussian where b > 0, and the height at half
// resolution z_c for level transitions.
//
// Footprints: a curve of a Roads or Rivers layer narrower than 2 delta is skipped (it would not
// show after filtering, Fig. 8); the others are drawn with b = 1 within w/2 + 2 sqrt(2) delta of
// their axis (the paper's sqrt(2) delta for bilinear interpolation, and as much again for the 3x3
// filter, so the road's own width is never mixed with the terrain: roads stay level across),
// falling smoothly to 0 at wf/2 + 2 sqrt(2) delta, and z_e = z(u) from the ancestor's
// z-profile. Each refined segment is drawn as a capsule (its rectangle and the discs at its
// ends), whose footprint is evaluated exactly from the distance to the segment: the union over
// a polyline is the footprint of the distance to the polyline, so sharp turns and hairpins wider
// than their radius have no spike and no gap. Lakes: b = 1 and z_e = the lake level inside,
// falling to 0 at wf outside the real border (not the closing curves of clipped areas). River
// areas (areas of a Rivers layer) likewise, but z_e is the z-profile of their river (the axial
// curve and the river on through the area) at its nearest point, so the water descends with
// the river; without an axial curve, flat as a lake. Bridges and tunnels (kBridge, kTunnel) have
// no footprint: the terrain under a deck and over a tunnel stays as it is.
//
// Thread safety: produce() may run for many quads at once; it only reads the quadtree and the
// DEM, and asks the CurveDataCache (which is thread-safe) for u and z-profiles. `cancel` (may be
// null) is checked between the elements drawn (model/cancel.h).

#include <atomic>
#include <vector>

#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/dem.h"
#include "raster/elevation_tile.h"
#include "model/cancel.h"

namespace lacet {

// The tile's resolution and border are the quadtree's grid (quadtree.params():
// TileGrid::elevationResolution and elevationBorder), so that the clipping margins match what
// this reads.
struct ElevationParams {
    std::vector<bool> hiddenLayers;  // layers leaving no footprint (index: LayerId; missing: shown)
};

struct ElevationCounters {
    std::atomic<std::size_t> tiles{0};
    std::atomic<std::size_t> curvesDrawn{0};
    std::atomic<std::size_t> curvesSkippedThin{0};  // w < 2 delta: no z-profile asked
    std::atomic<std::size_t> curvesOnStructures{0};  // bridges and tunnels: no footprint
    std::atomic<std::size_t> lakesDrawn{0};
};

// The river curves a river area's water follows (`area.axial` must name a curve): its axial curve,
// and the curves of the axial curve's class joined to them at nodes inside the area (the area's
// root loops, their on-curve vertices), in id order, bridges and tunnels and area borders left
// out; the river through a long river area is split into several curves at its confluences, and
// beyond its axial curve's ends the area follows the river on rather than stay level. `nodes`:
// the nodes inside the area the walk looked at (every curve at them was considered). What the
// area's tiles read of its layer, whatever quad they are in (io/scene_region.h loads it).
struct AxialRiver {
    std::vector<ElementId> curves, nodes;
};
AxialRiver axialRiver(const Layer& layer, const Area& area);

ElevationTile produceElevation(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData,
                               const Dem& dem, const ElevationParams& params, ElevationCounters* counters = nullptr,
                               const CancelFlag* cancel = nullptr);

}  // namespace lacet
