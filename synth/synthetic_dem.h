#pragma once
// A deterministic, seeded synthetic DEM for a scene, standing in for the paper's 5000 x 5000
// DEM over 100 x 100 km (§9) when no real elevation data is at hand: hills whose valleys hold
// the rivers of the scene, so that rivers run downhill on it.
//
//   1. valley lines: along every river, heights rising upstream from the outlets, steeply for
//      narrow rivers and gently for wide ones;
//   2. terrain: hillsides rising from the valley lines at a fixed slope up to a plateau (ridges
//      form between rivers), plus value noise that fades in away from the rivers;
//   3. river beds: walking the network from the sources downstream, each bed follows the lowest
//      terrain under its valley floor, never rises, drops at least a minimal slope and at most a
//      maximal one (steeper ground is cut into); every curve meeting at a node has the node's
//      height there;
//   4. valleys: a floor level across each river at its bed, as wide as the river plus a margin
//      and at least as wide as the Dem's interpolation stencil, ramping gently where floors
//      meet at confluences, and walls rising at a fixed slope until they meet the terrain. A
//      wall does not cut into another river's floor: where a deep valley passes close to a
//      higher river, that river's floor is kept and the ground steps down at its edge.
//
// What holds: with cells of 20 m (the default) to 40 m, the Dem sampled along any river curve,
// walked downstream, never rises above its lowest value upstream by more than about 0.3 m (the
// Catmull-Rom interpolant overshoots a little where a bed's slope changes; measured over the
// paper-scale scenes of seeds 1..5 and small scenes); the error grows with the cell size (about
// 0.7 m at 100 m cells, where floors are at least 325 m wide each side).
// Rivers are the curves of the scene's layers of kind LayerKind::Rivers, oriented downstream
// (start node upstream); nothing is guaranteed for curves on a cycle of the river network.
// A scene without rivers gets a plateau with noise. Runs in O(cells + river samples): the full
// paper-scale Dem takes about 2 s on one core.
//
// The same scene and parameters always give a bit-identical Dem (std::mt19937_64 output only,
// no implementation-defined distributions, a fixed order of floating-point operations).

#include <cstdint>

#include "model/graph.h"
#include "raster/dem.h"

namespace lacet {

struct SyntheticDemParams {
    std::uint64_t seed = 1;  // of the noise; the rivers come from the scene
    // Samples per side for a 100 km extent (the paper's 5000, i.e. 20 m cells). A scene of
    // another size gets the same cell size: round(resolution * side / 100 km) samples per side,
    // at least 2. Lower it for a coarser, faster Dem. Must be >= 1.
    int resolution = 5000;
};

// Throws std::invalid_argument for resolution < 1, an empty scene extent, or 2^32 samples or more.
Dem makeSyntheticDem(const Scene& scene, const SyntheticDemParams& params);

}  // namespace lacet
