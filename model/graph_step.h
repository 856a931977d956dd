#pragma once
// The graph step of SUBDIVIDE (Alg. 4.1, §4.3, Fig. 5): bridges where roads cross rivers, and
// roundabouts at the junctions that ask for one. It is the ProceduralStep every quadtree of a
// scene is built with (the editor, lacet render, lacet check, the benchmarks).
//
// Bridges. A road curve is cut into road and bridge pieces (procedural curves) where it crosses a
// river curve of a Rivers layer, unless the road says kNoBridge (a ford) or kTunnel. Crossings are
// found with exact predicates (CGAL) between the two curves flattened within
// `crossingTolerance`: no sampled distance decides whether two curves cross. A bridge covers the
// part of the road whose footprint would touch the river's, plus `abutmentLength` on each side;
// crossings whose bridges would overlap make one bridge with several spans. A curve imported as a
// bridge (kBridge) stays one curve, a bridge over every river and road it crosses (BridgeSpan).
// A road ending on a river (a junction over it) is bridged from its end node: the decks of the
// roads at that junction meet at the node's height.
//
// Roundabouts. Delegated to model/roundabouts.h: a road ending at a roundabout node is trimmed at
// the ring and carries the ring's arc to the next road.
//
// Cost. The step indexes the river curves' segments in cells, and the road curves' boxes once a
// river exists (or an imported bridge looks for roads under it), updated with each changeset; a
// road whose control hull meets no river segment's cell is not flattened. A scene with no river
// curve, no kBridge curve and no roundabout node does no per-curve work (the counters prove it).

#include <atomic>
#include <memory>
#include <unordered_map>
#include <vector>

#include "model/procedural.h"

namespace lacet {

struct GraphStepParams {
    double crossingTolerance = 0.05;  // m, flattening of curves for the exact crossing test, > 0
    double abutmentLength = 12.0;     // m along the road beyond the river's footprint, each side, >= 0
    double clearance = 5.0;           // m, the deck's underside above the crossed water (used by the z-profile)
    double deckThickness = 1.2;       // m, the deck's height under its road surface (used by the z-profile)
    bool bridges = true;              // make procedural bridges at unflagged crossings
    // m: an unflagged road crosses a river narrower than this (w) on a culvert, as roads cross
    // streams and ditches: no bridge, the road's footprint stays (an imported bridge spans any; a
    // river area's border, the water's edge, is always bridged).
    double minBridgedRiverWidth = 3.0;
    void validate() const;            // throws std::invalid_argument naming the knob
};

struct GraphStepCounters {
    std::atomic<std::size_t> curvesExpanded{0};   // root curves expand() was asked about
    std::atomic<std::size_t> crossingsTested{0};  // segment pairs given to the exact predicate
    std::atomic<std::size_t> crossingsFound{0};   // road-river crossings (and imported bridges' road crossings)
    std::atomic<std::size_t> flaggedCrossings{0};   // of those, on imported bridges (kBridge), over rivers
    std::atomic<std::size_t> flaggedRoadCrossings{0};  // imported bridges over roads
    std::atomic<std::size_t> importedBridgesOverRivers{0};  // imported bridges spanning a river
    std::atomic<std::size_t> bridgedCrossings{0};   // on unflagged roads, bridged by the step
    std::atomic<std::size_t> culverts{0};           // on unflagged roads, rivers below minBridgedRiverWidth
    std::atomic<std::size_t> bridgesMade{0};      // procedural bridges (not counting imported ones)
    std::atomic<std::size_t> importedBridges{0};  // kBridge curves expanded with their spans
    std::atomic<std::size_t> roundaboutRoads{0};  // road curves trimmed at a ring
    void reset();
};

class GraphStep : public ProceduralStep {
public:
    explicit GraphStep(const Scene& scene, GraphStepParams params = {});
    ~GraphStep() override;

    bool expand(const Scene& scene, LayerId layer, ElementId id, std::vector<ProceduralCurve>& out) const override;
    void update(const Scene& scene, const Changeset& changeset, std::vector<ElementRef>& out) override;

    const GraphStepParams& params() const { return params_; }
    const GraphStepCounters& counters() const { return counters_; }
    GraphStepCounters& counters() { return counters_; }

private:
    struct Index;
    void indexRoads(const Scene& scene) const;  // once: the first river, or an imported bridge
    GraphStepParams params_;
    std::unique_ptr<Index> index_;
    mutable GraphStepCounters counters_;
};

// The part of a spline (vertices as in Curve) between parameters s0 <= s1 (on-curve vertex k at
// s = k): exact sub-pieces by de Casteljau, first and last vertices on-curve.
std::vector<Vertex> subSpline(std::span<const Vertex> vertices, double s0, double s1);

}  // namespace lacet
