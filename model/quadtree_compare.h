#pragma once
// Compares two quadtrees quad by quad: structure, and in every quad and layer the same ancestors
// with bitwise-identical pieces (geometry, flags, parent indices: so CREATEDFROM is the same).
// "Incremental equals rebuild" is checked with it.

#include <string>
#include <vector>

#include "model/quadtree.h"

namespace lacet {

struct QuadtreeDiff {
    std::size_t quadsCompared = 0;
    std::size_t mismatches = 0;
    std::vector<std::string> details;  // the first few mismatches, readable
};

QuadtreeDiff compareQuadtrees(const Quadtree& a, const Quadtree& b, std::size_t maxDetails = 10);
// The same for two quads alone (their graphs, not their children): a sampled comparison.
QuadtreeDiff compareQuads(const Quad& a, const Quad& b, std::size_t maxDetails = 10);

}  // namespace lacet
