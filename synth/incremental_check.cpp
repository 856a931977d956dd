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

namespace {

// Restores every element of `s` that differs from `to` (and the slot counts): the scene becomes
// `to` element for element, without reallocating what did not change.
void restoreScene(Scene& s, const Scene& to) {
    for (std::size_t l = 0; l < s.layers.size() && l < to.layers.size(); ++l) {
        Layer& cur = s.layers[l];
        const Layer& was = to.layers[l];
        const auto restore = [](auto& now, const auto& before) {
            for (std::size_t i = 0; i < now.size() && i < before.size(); ++i)
                if (!(now[i] == before[i])) now[i] = before[i];
            if (now.size() > before.size()) now.resize(before.size());
            for (std::size_t i = now.size(); i < before.size(); ++i) now.push_back(before[i]);
        };
        restore(cur.nodes, was.nodes);
        restore(cur.curves, was.curves);
        restore(cur.areas, was.areas);
    }
}

Changeset reversed(const Changeset& c) {
    Changeset back;
    back.removed = c.added;
    back.added = c.removed;
    back.normalize();
    return back;
}

}  // namespace

IncrementalCheckReport checkIncremental(Scene& s, const IncrementalCheckParams& p) {
    std::mt19937_64 rng(p.seed);
    // The sample's own generator: the same seed gives the same edits with or without --sample, so
    // that a mismatch a sample finds late is found at its edit by the full check. Undo and redo
    // draw from theirs for the same reason.
    std::mt19937_64 sampleRng(p.seed ^ 0x9e3779b97f4a7c15ULL);
    std::mt19937_64 undoRng(p.seed ^ 0xc2b2ae3d27d4eb4fULL);
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
    // UPDATE of `changeset`, then the comparison with a rebuild; false on a mismatch.
    const auto updateAndCompare = [&](const Changeset& changeset, const std::string& label) {
        auto t0 = std::chrono::steady_clock::now();
        qt.update(changeset);
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
        const std::size_t compared = r.edits + r.undos + r.redos;
        const bool full = p.sample == 0 || (p.fullEvery > 0 && compared % std::size_t(p.fullEvery) == 0);
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
            if (r.details.size() < p.maxDetails) r.details.push_back(label + ": " + d);
        return diff.mismatches == 0;
    };
    for (int i = 0; i < p.edits; ++i) {
        if (i % p.viewEvery == p.viewEvery - 1) qt.refineForViewer(viewer(), view);
        const bool undo = p.undoChance > 0.0 && uniform01(undoRng) < p.undoChance;
        std::optional<Scene> before;
        if (undo) before = s;
        const RandomEdit e = applyRandomEdit(s, rng, p.reach);
        if (e.changeset.empty()) continue;
        ++r.edits;
        ++r.byKind[e.kind];
        const std::string label = "edit " + std::to_string(i) + " (" + std::string(toString(e.kind)) + ")";
        bool same = updateAndCompare(e.changeset, label);
        if (undo && (same || !p.stopAtFirstMismatch)) {
            const bool redo = uniform01(undoRng) < p.redoChance;
            std::optional<Scene> after;
            if (redo) after = s;
            restoreScene(s, *before);
            ++r.undos;
            same = updateAndCompare(reversed(e.changeset), label + " undone") && same;
            if (redo && (same || !p.stopAtFirstMismatch)) {
                restoreScene(s, *after);
                ++r.redos;
                same = updateAndCompare(e.changeset, label + " redone") && same;
            }
        }
        if (!same && p.stopAtFirstMismatch) break;
    }
    r.bridgesAtEnd = bridgesBefore;
    r.ringArcsAtEnd = ringsBefore;
    return r;
}

}  // namespace lacet
