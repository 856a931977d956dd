// `lacet bench producers`: time per quad of the appearance and elevation producers on a
// synthetic scene at the paper's scale, at the deepest levels of views near the ground, one
// thread; and the throughput of two threads against one.
#include <algorithm>
#include <map>
#include <random>
#include <set>

#include <tbb/task_arena.h>

#include "model/graph_step.h"
#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "io/scene_file.h"
#include "raster/dem_height_field.h"
#include "raster/parallel_producers.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

nlohmann::json stats(const std::vector<double>& ms) {
    return {{"quads", ms.size()}, {"median_ms", median(ms)}, {"p99_ms", quantile(ms, 0.99)}, {"max_ms", quantile(ms, 1.0)}};
}

// Viewpoints `altitude` metres above on-curve points of random roads.
std::vector<glm::dvec3> roadViews(const Scene& s, int count, double altitude, std::uint64_t seed) {
    const Layer& roads = s.layers[kRoadsLayer];
    std::mt19937_64 rng(seed);
    std::vector<glm::dvec3> out;
    while (int(out.size()) < count && !roads.curves.empty()) {
        const Curve& c = roads.curves[std::size_t(uniform01(rng) * double(roads.curves.size())) % roads.curves.size()];
        const Vec2 p = c.vertices[c.vertices.size() / 2].p;
        out.push_back({p.x, p.y, altitude});
    }
    return out;
}

// What a quad holds, per layer kind: curves (their pieces' on-curve vertices), areas (their
// pieces, those covering the quad, their loops' vertices): what the slowest tiles are made of.
nlohmann::json contents(const Quad& q, const Scene& scene) {
    nlohmann::json out = nlohmann::json::object();
    for (LayerId l = 0; l < q.layers.size(); ++l) {
        std::size_t curves = q.layers[l].curves.size(), vertices = 0, areas = 0, covering = 0, areaVertices = 0;
        for (const auto& [id, pieces] : q.layers[l].curves)
            for (const ClippedCurve& piece : pieces) vertices += piece.s.size();
        for (const auto& [id, pieces] : q.layers[l].areas)
            for (const ClippedArea& piece : pieces) {
                ++areas;
                covering += piece.coversQuad;
                for (const ClippedLoop& loop : piece.loops) areaVertices += loop.vertices.size();
            }
        if (curves + areas == 0) continue;
        nlohmann::json& k = out[std::string(toString(scene.layers[l].kind))];
        if (k.is_null()) k = nlohmann::json::object();
        if (curves) k["curves"] = k.value("curves", 0) + curves, k["curve_vertices"] = k.value("curve_vertices", 0) + vertices;
        if (areas) {
            k["area_pieces"] = k.value("area_pieces", 0) + areas;
            k["covering_quad"] = k.value("covering_quad", 0) + covering;
            k["area_vertices"] = k.value("area_vertices", 0) + areaVertices;
        }
    }
    return out;
}

}  // namespace

nlohmann::json benchProducers(const ProducerBenchOptions& o) {
    auto t0 = Clock::now();
    SceneDocument doc;
    if (!o.scene.empty()) doc = loadScene(o.scene);
    else doc.scene = makeSyntheticScene({o.seed, o.curves});
    if (!doc.dem && !o.scene.empty()) throw std::invalid_argument(o.scene + ": the scene file holds no DEM");
    const Scene& scene = doc.scene;
    const double synthMs = msSince(t0);
    t0 = Clock::now();
    if (!doc.dem) doc.dem = makeSyntheticDem(scene, {o.seed, o.demResolution});
    const Dem& dem = *doc.dem;
    const double demMs = msSince(t0);
    const DemHeightField heights(dem);
    GraphStep qtStep(scene);
    Quadtree qt(scene, {}, &qtStep);
    CurveDataCache data(qt, heights);
    const AppearanceParams ap;
    const ElevationParams ep;

    std::map<int, std::vector<double>> appearanceCold, appearanceWarm, elevationCold, elevationWarm;
    std::vector<double> appearanceDeep, elevationDeep, appearanceDeepCold, elevationDeepCold;
    double oneThreadMs = 0.0, twoThreadsMs = 0.0;
    std::size_t deepQuads = 0, uniformDeep = 0;
    std::vector<std::pair<double, nlohmann::json>> slowest;  // the deep quads' slowest appearance tiles (warm)
    AppearanceCounters counters;
    tbb::task_arena one(1), two(2);
    for (const glm::dvec3& view : roadViews(scene, o.views, o.altitude, o.seed)) {
        qt.refineForViewer(view, o.view);
        std::vector<const Quad*> quads;
        qt.forEachQuad([&](const Quad& q) {
            if (q.level >= o.minLevel) quads.push_back(&q);
        });
        // One thread, each quad alone: cold (curve data computed on demand), then warm.
        one.execute([&] {
            for (const Quad* q : quads) {
                const bool deep = q->level >= o.deepLevel;
                auto t = Clock::now();
                const AppearanceTile tile = produceAppearance(*q, qt, data, dem, ap, &counters);
                const double aCold = msSince(t);
                t = Clock::now();
                produceElevation(*q, qt, data, dem, ep);
                const double eCold = msSince(t);
                t = Clock::now();
                produceAppearance(*q, qt, data, dem, ap);
                const double aWarm = msSince(t);
                t = Clock::now();
                produceElevation(*q, qt, data, dem, ep);
                const double eWarm = msSince(t);
                appearanceCold[q->level].push_back(aCold);
                elevationCold[q->level].push_back(eCold);
                appearanceWarm[q->level].push_back(aWarm);
                elevationWarm[q->level].push_back(eWarm);
                if (deep) {
                    ++deepQuads;
                    uniformDeep += tile.uniform;
                    appearanceDeep.push_back(aWarm);
                    slowest.push_back({aWarm, {{"ms", aWarm}, {"level", q->level}, {"uniform", tile.uniform}, {"holds", contents(*q, scene)}}});
                    std::sort(slowest.begin(), slowest.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
                    if (slowest.size() > 8) slowest.pop_back();
                    elevationDeep.push_back(eWarm);
                    appearanceDeepCold.push_back(aCold);
                    elevationDeepCold.push_back(eCold);
                }
            }
        });
        // Throughput: all the quads of the view, both producers, with one and two threads (warm).
        const auto all = [&] {
            produceAppearanceTiles(quads, qt, data, dem, ap);
            produceElevationTiles(quads, qt, data, dem, ep);
        };
        for (int rep = 0; rep < 3; ++rep) {
            t0 = Clock::now();
            one.execute(all);
            oneThreadMs += msSince(t0);
            t0 = Clock::now();
            two.execute(all);
            twoThreadsMs += msSince(t0);
        }
    }
    nlohmann::json byLevel = nlohmann::json::array();
    for (const auto& [level, ms] : appearanceWarm)
        byLevel.push_back({{"level", level},
                           {"quad_size_m", scene.extent.size().x / double(1u << level)},
                           {"appearance_warm", stats(ms)},
                           {"appearance_cold", stats(appearanceCold[level])},
                           {"elevation_warm", stats(elevationWarm[level])},
                           {"elevation_cold", stats(elevationCold[level])}});
    const SceneCounts c = count(scene);
    return {{"scene", {{"file", o.scene}, {"curves", c.curves}, {"areas", c.areas}, {"extent_km", scene.extent.size().x / 1000.0},
                       {"synth_ms", synthMs}, {"dem_samples_per_side", dem.width()}, {"dem_ms", demMs}}},
            {"views", o.views},
            {"viewer_altitude_m", o.altitude},
            {"K", o.view.K},
            {"appearance_resolution", qt.params().resolution},
            {"elevation_samples_per_side", qt.params().elevationResolution + 1},
            {"deepest_levels_from", o.deepLevel},
            {"deep", {{"quads", deepQuads},
                      {"uniform_quads", uniformDeep},
                      {"appearance_ms_one_thread", stats(appearanceDeep)},
                      {"elevation_ms_one_thread", stats(elevationDeep)},
                      {"appearance_cold_ms_one_thread", stats(appearanceDeepCold)},
                      {"elevation_cold_ms_one_thread", stats(elevationDeepCold)},
                      {"slowest_appearance", [&] {
                           nlohmann::json a = nlohmann::json::array();
                           for (const auto& [ms, j] : slowest) a.push_back(j);
                           return a;
                       }()}}},
            {"throughput", {{"one_thread_ms", oneThreadMs}, {"two_threads_ms", twoThreadsMs},
                            {"speedup", twoThreadsMs > 0.0 ? oneThreadMs / twoThreadsMs : 0.0}}},
            {"by_level", byLevel},
            {"curve_data", {{"z_profiles", data.counters().zProfiles.load()}, {"u_tables", data.counters().arcLengthTables.load()}}},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
