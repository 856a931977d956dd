#pragma once
// What a scene's bridges do to the terrain and the water (issue 14), measured on the whole scene:
// - under every deck, over the water of every river it spans, the elevation (z_m at a quadtree
//   level) equals the elevation produced from the scene without the bridged roads: the river bed
//   is untouched;
// - the deck's underside (the road surface less the graph step's deck thickness) clears the
//   water of every river it spans by the graph step's clearance, at every z-profile sample over
//   that river's footprint.
// The points under a deck are sampled every `step` metres along it, on its axis and a quarter of
// its width to each side, where they lie within the river's half width of its axis. `lacet check
// bridges` prints the report, of the scene read whole or by parts (BridgeCheck).

#include <chrono>
#include <cstddef>
#include <functional>

#include "model/graph.h"
#include "model/graph_step.h"
#include "raster/dem.h"
#include "raster/dem_source.h"

namespace lacet {

struct BridgeCheckParams {
    int level = 7;            // quadtree level of the elevation tiles compared (>= 0)
    double step = 1.0;        // m between the points sampled along a deck (> 0)
    GraphStepParams graph;    // the graph step the scene is built with
};

struct BridgeCheckReport {
    std::size_t bridges = 0, importedBridges = 0, riverSpans = 0;
    // The graph step's counters; by parts (BridgeCheck below) none: a crossing near a part's
    // border is found in each part that reads it.
    bool graphCounters = true;
    std::size_t crossingsFound = 0, flaggedRiverCrossings = 0, bridgedCrossings = 0, culverts = 0, proceduralBridges = 0;
    // Clearance over the water, at the deck's z-profile samples over each river span's footprint.
    std::size_t deckSamples = 0, deckSamplesBelowClearance = 0;
    double leastClearance = 0.0;  // m (infinity when no deck spans a river)
    // The river bed under the decks: z_m with and without the bridged roads.
    std::size_t bedPoints = 0, bedPointsDiffering = 0, tilesCompared = 0;
    double largestBedDifference = 0.0;  // m
    double ms = 0.0;
    bool passed() const { return deckSamplesBelowClearance == 0 && bedPointsDiffering == 0; }
};

BridgeCheckReport checkBridges(const Scene& scene, const Dem& dem, const BridgeCheckParams& params = {});
// The same on any DEM source (a streamed DEM's windows at the level each tile needs).
BridgeCheckReport checkBridges(const Scene& scene, const DemSource& dem, const BridgeCheckParams& params = {});

// The same summed over parts of a scene (io/scene_parts.h): add() each part (a scene read for a
// quad of level params.level or coarser) with `owns`, which holds for each point of the scene in
// exactly one part; a bridge counts (its spans and deck samples) in the part owning its road's
// first vertex, a point under a deck in the part owning the point. Then finish().
class BridgeCheck {
public:
    explicit BridgeCheck(BridgeCheckParams params = {});
    void add(const Scene& part, const DemSource& dem, const std::function<bool(Vec2)>& owns);
    BridgeCheckReport finish();

private:
    BridgeCheckParams params_;
    BridgeCheckReport r_;
    std::size_t parts_ = 0;
    std::chrono::steady_clock::time_point t0_;
};

}  // namespace lacet
