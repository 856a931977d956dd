#include <map>
#include <optional>
#include <random>

#include <glm/geometric.hpp>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "model/graph_step.h"
#include "model/edits.h"
#include "model/quadtree.h"
#include "synth/random_edits.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

struct Target {
    ElementId curve = kNoElement;
    std::size_t vertex = 0;
};

// The road control point nearest the scene centre.
Target roadControlPointNearCentre(const Scene& s) {
    const Layer& roads = s.layers[kRoadsLayer];
    const Vec2 c = s.extent.center();
    Target best;
    double bestD = 1e300;
    for (ElementId id = 0; id < roads.curves.size(); ++id) {
        const auto& v = roads.curves[id].vertices;
        for (std::size_t i = 1; i + 1 < v.size(); ++i)
            if (!v[i].onCurve && glm::length(v[i].p - c) < bestD) {
                bestD = glm::length(v[i].p - c);
                best = {id, i};
            }
    }
    return best;
}

// Times the subdivision of every internal quad of `like` in a fresh tree, per child quad, by the
// level of the children made.
std::map<int, std::vector<double>> timeClipAndRefineByLevel(const Scene& s, const Quadtree& like) {
    GraphStep freshStep(s);
    Quadtree fresh(s, {}, &freshStep);
    std::map<int, std::vector<double>> byLevel;
    auto rec = [&](auto& self, Quad& q, const Quad& l) -> void {
        if (l.isLeaf()) return;
        const auto t0 = Clock::now();
        fresh.subdivide(q);
        byLevel[q.level + 1].push_back(msSince(t0) / 4.0);
        for (int k = 0; k < 4; ++k) self(self, *q.children[k], *l.children[k]);
    };
    rec(rec, fresh.root(), like.root());
    return byLevel;
}

// What the graph step costs (issue 14): on `s` (with its crossings and roundabouts) and on the
// same scene without rivers and roundabouts (nothing for the step to do), the root's subdivision
// (the quadtree's construction, which expands every root curve, plus the root's four children)
// with the step and without one, and the median UPDATE of `moves` random moves of a road control
// point near the centre, in a tree refined for a viewer above it, with and without the step.
nlohmann::json graphStepCost(const Scene& scene, Target target, int moves, double altitude, std::uint64_t seed) {
    Scene plain = scene;
    Layer& rivers = plain.layers[kRiversLayer];
    Layer empty;
    empty.name = rivers.name;
    empty.kind = rivers.kind;
    rivers = std::move(empty);
    for (Layer& l : plain.layers)
        for (Node& n : l.nodes) n.roundabout = 0.0f;
    nlohmann::json out;
    for (const bool crossings : {true, false}) {
        const Scene& base = crossings ? scene : plain;
        nlohmann::json row;
        for (const bool withStep : {true, false}) {
            std::vector<double> subdivideMs, updateMs;
            double indexMs = 0.0;
            for (int rep = 0; rep < 3; ++rep) {
                Scene s = base;
                auto t0 = Clock::now();
                std::optional<GraphStep> step;
                if (withStep) step.emplace(s);
                indexMs = msSince(t0);
                Quadtree qt(s, {}, withStep ? &*step : nullptr);
                qt.subdivide(qt.root());
                subdivideMs.push_back(msSince(t0));
                const Vec2 at = s.layers[kRoadsLayer].curves[target.curve].vertices[target.vertex].p;
                if (rep > 0) continue;
                qt.refineForViewer({at.x, at.y, altitude}, ViewParams{});
                std::mt19937_64 rng(seed);
                for (int i = 0; i < moves; ++i) {
                    const Vec2 p = at + Vec2(uniform01(rng) * 40.0 - 20.0, uniform01(rng) * 40.0 - 20.0);
                    const Changeset cs = moveVertex(s, kRoadsLayer, target.curve, target.vertex, p);
                    t0 = Clock::now();
                    qt.update(cs);
                    updateMs.push_back(msSince(t0));
                }
                if (withStep)
                    row["step_counters"] = {{"curves_expanded", step->counters().curvesExpanded.load()},
                                            {"crossings_tested", step->counters().crossingsTested.load()},
                                            {"bridges_made", step->counters().bridgesMade.load()},
                                            {"roads_at_roundabouts", step->counters().roundaboutRoads.load()}};
            }
            row[withStep ? "with_step" : "without_step"] = {{"root_subdivision_median_ms", median(subdivideMs)},
                                                            {"index_ms", indexMs},
                                                            {"update_median_ms", median(updateMs)}};
        }
        out[crossings ? "scene" : "scene_without_rivers_and_roundabouts"] = row;
    }
    return out;
}

}  // namespace

nlohmann::json benchUpdate(const std::vector<std::size_t>& curves, std::uint64_t seed, int moves, double altitude) {
    const ViewParams view;
    nlohmann::json runs = nlohmann::json::array();
    double firstMedian = 0.0, lastMedian = 0.0, lastRebuild = 0.0;
    nlohmann::json byDepth, graphStep;
    for (std::size_t run = 0; run < curves.size(); ++run) {
        const std::size_t n = curves[run];
        auto t0 = Clock::now();
        Scene s = makeSyntheticScene({seed, n});
        const double synthMs = msSince(t0);
        const Target target = roadControlPointNearCentre(s);
        const Vec2 at = s.layers[kRoadsLayer].curves[target.curve].vertices[target.vertex].p;
        t0 = Clock::now();
        GraphStep qtStep(s);
        Quadtree qt(s, {}, &qtStep);
        qt.refineForViewer({at.x, at.y, altitude}, view);
        const double buildMs = msSince(t0);
        std::mt19937_64 rng(seed);
        std::vector<double> updates;
        std::vector<double> changed;
        for (int i = 0; i < moves; ++i) {
            const Vec2 p = at + Vec2(uniform01(rng) * 40.0 - 20.0, uniform01(rng) * 40.0 - 20.0);
            const Changeset cs = moveVertex(s, kRoadsLayer, target.curve, target.vertex, p);
            t0 = Clock::now();
            const UpdateStats st = qt.update(cs);
            updates.push_back(msSince(t0));
            changed.push_back(double(st.changedQuads.size()));
        }
        t0 = Clock::now();
        {
            GraphStep rebuiltStep(s);
            Quadtree rebuilt(s, {}, &rebuiltStep);
            rebuilt.copyStructureOf(qt);
        }
        const double rebuildMs = msSince(t0);
        const double med = median(updates);
        if (runs.empty()) firstMedian = med;
        lastMedian = med;
        lastRebuild = rebuildMs;
        const SceneCounts c = count(s);
        runs.push_back({{"curves", c.curves},
                        {"areas", c.areas},
                        {"nodes_and_control_points", c.nodes + c.controlPoints},
                        {"extent_km", s.extent.size().x / 1000.0},
                        {"quads", qt.quadCount()},
                        {"depth", qt.depth()},
                        {"synth_ms", synthMs},
                        {"build_ms", buildMs},
                        {"update_median_ms", med},
                        {"update_p95_ms", quantile(updates, 0.95)},
                        {"update_max_ms", quantile(updates, 1.0)},
                        {"quads_changed_median", median(changed)},
                        {"rebuild_ms", rebuildMs},
                        {"peak_rss_mib", peakRssMiB()}});
        if (run + 1 == curves.size()) {
            graphStep = graphStepCost(s, target, moves, altitude, seed);
            for (const auto& [level, ms] : timeClipAndRefineByLevel(s, qt))
                byDepth.push_back({{"depth", level}, {"subdivisions", ms.size()}, {"median_ms_per_child_quad", median(ms)},
                                {"max_ms_per_child_quad", quantile(ms, 1.0)}});
        }
    }
    return {{"runs", runs},
            {"moves", moves},
            {"viewer_altitude_m", altitude},
            {"K", view.K},
            {"ratio", firstMedian > 0.0 ? lastMedian / firstMedian : 0.0},
            {"rebuild_speedup", lastMedian > 0.0 ? lastRebuild / lastMedian : 0.0},
            {"clip_and_refine_per_quad_by_depth", byDepth},
            {"graph_step_cost", graphStep},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
