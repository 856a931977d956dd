#include "synth/incremental_check.h"

#include <optional>

#include "model/graph_step.h"

#include <chrono>
#include <random>

#include <glm/vec3.hpp>

#include "model/quadtree_compare.h"
#include "model/view_params.h"

namespace lacet {
namespace {

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

IncrementalCheckReport checkIncremental(Scene& s, const IncrementalCheckParams& p) {
    std::mt19937_64 rng(p.seed);
    const ViewParams view{.maxLevel = p.maxLevel};
    auto viewer = [&] {
        return glm::dvec3(s.extent.min.x + uniform01(rng) * s.extent.size().x,
                          s.extent.min.y + uniform01(rng) * s.extent.size().y,
                          p.viewerHeight + uniform01(rng) * p.viewerHeightRange);
    };
    std::optional<GraphStep> step;
    if (!p.procedural) step.emplace(s);
    Quadtree qt(s, {}, p.procedural ? p.procedural : &*step);
    qt.refineForViewer(viewer(), view);
    IncrementalCheckReport r;
    std::size_t bridgesBefore = qt.proceduralCount(kBridge), ringsBefore = qt.proceduralCount(kRoundabout);
    for (int i = 0; i < p.edits; ++i) {
        if (i % p.viewEvery == p.viewEvery - 1) qt.refineForViewer(viewer(), view);
        const RandomEdit e = applyRandomEdit(s, rng, p.reach);
        if (e.changeset.empty()) continue;
        ++r.edits;
        ++r.byKind[e.kind];
        auto t0 = std::chrono::steady_clock::now();
        qt.update(e.changeset);
        r.updateMs.push_back(msSince(t0));
        const std::size_t bridges = qt.proceduralCount(kBridge), rings = qt.proceduralCount(kRoundabout);
        r.editsAddingBridges += bridges > bridgesBefore;
        r.editsRemovingBridges += bridges < bridgesBefore;
        r.editsAddingRings += rings > ringsBefore;
        r.editsRemovingRings += rings < ringsBefore;
        bridgesBefore = bridges;
        ringsBefore = rings;
        t0 = std::chrono::steady_clock::now();
        std::optional<GraphStep> freshStep;
        if (!p.procedural) freshStep.emplace(s);
        Quadtree rebuilt(s, {}, p.procedural ? p.procedural : &*freshStep);
        rebuilt.copyStructureOf(qt);
        r.rebuildMs.push_back(msSince(t0));
        const QuadtreeDiff diff = compareQuadtrees(qt, rebuilt, p.detailsPerEdit);
        r.quadsCompared += diff.quadsCompared;
        r.mismatches += diff.mismatches;
        for (const auto& d : diff.details)
            if (r.details.size() < p.maxDetails)
                r.details.push_back("edit " + std::to_string(i) + " (" + std::string(toString(e.kind)) + "): " + d);
        if (diff.mismatches && p.stopAtFirstMismatch) break;
    }
    r.bridgesAtEnd = bridgesBefore;
    r.ringArcsAtEnd = ringsBefore;
    return r;
}

}  // namespace lacet
