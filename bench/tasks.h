#pragma once
// Benchmark tasks behind `lacet bench ...`: each runs and returns its figures as JSON.

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

namespace lacet::bench {

// UPDATE cost against scene size (§6): for each curve count, a synthetic scene at the paper's
// density, a quadtree refined for a viewer `altitude` metres above a road (K = 2.8), and `moves`
// moves of one control point of that road. Reports the median UPDATE time, a rebuild's time, and
// clip-and-refine time per quad by depth.
nlohmann::json benchUpdate(const std::vector<std::size_t>& curves, std::uint64_t seed, int moves, double altitude);

// Refinement tolerance against time, vertices and the error left (max distance between the drawn
// polyline and the exact curve, by dense sampling), for tolerances in texels.
nlohmann::json benchAccuracy(const std::vector<double>& tolerancesTexels, std::size_t curves, std::uint64_t seed);

}  // namespace lacet::bench
