#include "synth/incremental_check.h"

#include <optional>

#include "model/graph_step.h"

#include <chrono>
#include <random>

#include <glm/vec3.hpp>

#include "model/quadtree_compare.h"
#include "model/view_params.h"
#include "model/work_clock.h"

namespace lacet {

IncrementalCheckReport checkIncremental(Scene& s, const IncrementalCheckParams& p) {
    std::mt19937_64 rng(p.seed);
    // The sample's own generator: the same seed gives the same edits with or without --sample, so
    // that a mismatch a sample finds late is found at its edit by the full check.
    std::mt19937_64 sampleRng(p.seed ^ 0x9e3779b97f4a7c15ULL);
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
        const bool full = p.sample == 0 || (p.fullEvery > 0 && r.edits % std::size_t(p.fullEvery) == 0);
        QuadtreeDiff diff;
        if (full) {
            rebuilt.copyStructureOf(qt);
            r.rebuildMs.push_back(msSince(t0));
            diff = compareQuadtrees(qt, rebuilt, p.detailsPerEdit);
            ++r.fullComparisons;
        } else {
            std::vector<const Quad*> quads;
            qt.forEachQuad([&](const Quad& q) { quads.push_back(&q); });
            for (std::size_t k = 0; k < p.sample; ++k) {
                const Quad& q = *quads[std::size_t(uniform01(sampleRng) * double(quads.size())) % quads.size()];
                const QuadtreeDiff d = compareQuads(q, rebuilt.reach(q.level, q.tx, q.ty), p.detailsPerEdit);
                diff.quadsCompared += d.quadsCompared;
                diff.mismatches += d.mismatches;
                diff.details.insert(diff.details.end(), d.details.begin(), d.details.end());
            }
            r.rebuildMs.push_back(msSince(t0));
        }
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
