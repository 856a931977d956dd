#pragma once
// A deterministic, seeded synthetic DEM for a scene, standing in for the paper's 5000 x 5000
// DEM over 100 x 100 km (§9) when no real elevation data is at hand. Hilly terrain (value
// noise, a few hundred metres of relief, rising inland from the extent border) with a valley
// carved along every river of the scene, so that rivers run downhill on it:
//
//   1. terrain: octaves of cubic B-spline value noise plus an inland rise;
//   2. river beds: every river curve is sampled densely; walking the river network from its
//      sources downstream, the bed follows the terrain under the valley floor but never rises
//      and drops at least kMinBedSlope; a node's bed is the lowest of its incoming curves' ends,
//      and each incoming curve is tilted to end exactly there, so beds strictly decrease from
//      sources to outlets and every curve meeting at a node has the node's height;
//   3. valleys: a flat floor around each river curve at its bed height, wide enough to hold the
//      whole interpolation stencil of the Dem, and walls rising with a fixed slope until they
//      meet the terrain (a cone propagation over the grid, linear in the number of cells);
//   4. correction: the Dem is sampled along every river; where it rises (another river's valley
//      passing close by can dip a floor), the beds downstream are lowered and the valleys are
//      made again, a few times at most.
//
// Rivers are the curves of the scene's layers of kind LayerKind::Rivers, oriented downstream
// (start node upstream). Curves on a cycle of the river network are carved with the beds they
// have when the network walk stops; nothing is guaranteed for them.
//
// The same scene and parameters always give a bit-identical Dem (std::mt19937_64 output only,
// no implementation-defined distributions, a fixed order of floating-point operations).

#include <cstdint>

#include "model/graph.h"
#include "raster/dem.h"

namespace lacet {

struct SyntheticDemParams {
    std::uint64_t seed = 1;
    // Samples per side for a 100 km extent (the paper's 5000, i.e. 20 m cells). A scene of
    // another size gets the same cell size: round(resolution * side / 100 km) samples per side,
    // at least 2. Lower it for a coarser, faster Dem. Must be >= 1.
    int resolution = 5000;
};

// Throws std::invalid_argument for resolution < 1 or an empty scene extent.
Dem makeSyntheticDem(const Scene& scene, const SyntheticDemParams& params);

}  // namespace lacet
