// `lacet bench flyover`: the paper's flight (§9.1, paperFlight below) through the window-less
// session: from 5000 m above the scene down to 5 m above a road, a camera (1280 x 800, 52
// degrees vertical field of view) looking ahead along the path, the quadtree refined each frame
// with the default ViewParams (its K reported) and the missing tiles of the leaves in the view frustum made nearest first; per
// frame, the update time (refinement and production), the tiles made and the cache size. Run with no budget (every tile of the view made
// each frame) and with a per-frame budget (the rest left pending, shown coarser by a renderer),
// each without and with prefetching: the viewer `prefetchFrames` frames ahead on the path is
// given to the session, which makes that viewer's tiles with the budget left. With a pyramid
// (§7, issue 15: `--pyramid`), each budget is flown without and with it instead: the quads above
// the pyramid's first vector level read their appearance from it. A scene file with a vector
// budget (`--vector-budget`, issue 23) is read lazily (editor/lazy_forest.h): the levels down to
// the part level once, each part the view wants as it goes.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

#include <glm/geometric.hpp>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "editor/adaptive_quality.h"
#include "editor/camera.h"
#include "editor/edit_session.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_reader.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {

// The paper's flight (§9.1): 73 s at 60 frames per second, 2000 km/h at 5000 m above the ground,
// slowing with altitude to 60 km/h at 8 m, then 8 -> 5 m at 60 -> 90 km/h (car view along the
// road). The speed between is a power of the altitude through those two points; the paper gives
// no more of its profile. The altitude falls exponentially to 8 m over the first 80 % of the
// time. About 9.3 km in all. `frames` sets how many frames the 73 s are cut into: fewer frames
// fly the same path faster (600: 7.3 times the paper's speed).
struct FlightPath {
    std::vector<double> along, altitude;  // per frame: metres flown, height above the ground
};

FlightPath paperFlight(int frames, double startAltitude, double endAltitude) {
    constexpr double kSeconds = 73.0, kDescent = 0.8;  // of the time
    constexpr double kTopSpeed = 2000.0 / 3.6, kLowSpeed = 60.0 / 3.6, kEndSpeed = 90.0 / 3.6;  // m/s
    const double low = std::max(endAltitude, std::min(8.0, startAltitude));
    // The speed's power of the altitude (0 when the flight starts that low already).
    const double exponent = low < startAltitude ? std::log(kLowSpeed / kTopSpeed) / std::log(low / startAltitude) : 0.0;
    FlightPath path;
    const double dt = kSeconds / double(std::max(1, frames - 1));
    double s = 0.0;
    for (int f = 0; f < frames; ++f) {
        const double t = double(f) / double(std::max(1, frames - 1));  // of the flight
        double h, v;
        if (t <= kDescent) {
            h = startAltitude * std::pow(low / startAltitude, t / kDescent);
            v = kTopSpeed * std::pow(h / startAltitude, exponent);
        } else {
            const double u = (t - kDescent) / (1.0 - kDescent);
            h = low + (endAltitude - low) * u;
            v = kLowSpeed + (kEndSpeed - kLowSpeed) * u;
        }
        if (f > 0) s += v * dt;
        path.along.push_back(s);
        path.altitude.push_back(h);
    }
    return path;
}

// The error the z-profiles' DEM level leaves (DemStreamParams::profileSpacing): the profiles of
// the root road and river curves with a vertex within 2 km of the path, made from that level and
// from the finest, compared sample by sample (every sample of every profile).
nlohmann::json profileError(const EditSession& session, const FlyoverBenchOptions& o, Vec2 from, Vec2 to) {
    const SceneDocument& doc = session.document();
    const DemLodLayout& L = session.demStream()->layout();
    const auto t0 = Clock::now();
    DemStream coarse(doc.demLod, {.budgetMiB = 512.0, .background = false, .profileSpacing = o.demProfileSpacingM});
    DemStream fine(doc.demLod, {.budgetMiB = 512.0, .background = false, .profileSpacing = L.cell});
    const CurveDataCache a(session.quadtree(), coarse.heights(), session.params().profiles);
    const CurveDataCache b(session.quadtree(), fine.heights(), session.params().profiles);
    const Box near{glm::min(from, to) - 2000.0, glm::max(from, to) + 2000.0};
    std::vector<double> diffs;
    std::size_t curves = 0;
    double worst = 0.0;
    for (LayerId l = 0; l < doc.scene.layers.size(); ++l) {
        const LayerKind kind = doc.scene.layers[l].kind;
        if (kind != LayerKind::Roads && kind != LayerKind::Rivers) continue;
        const auto& cs = doc.scene.layers[l].curves;
        for (ElementId id = 0; id < cs.size(); ++id) {
            if (!cs[id].alive || cs[id].vertices.empty()) continue;
            if (std::none_of(cs[id].vertices.begin(), cs[id].vertices.end(), [&](const Vertex& v) { return near.contains(v.p); }))
                continue;
            const ZProfile& za = a.zProfile(l, id);
            const ZProfile& zb = b.zProfile(l, id);
            if (za.z.size() != zb.z.size()) continue;
            ++curves;
            for (std::size_t k = 0; k < za.z.size(); ++k) {
                diffs.push_back(std::abs(za.z[k] - zb.z[k]));
                worst = std::max(worst, diffs.back());
            }
        }
    }
    double sum = 0.0;
    for (double d : diffs) sum += d;
    return {{"profile_spacing_m", o.demProfileSpacingM},
            {"profile_level_cell_m", L.levelCell(coarse.profileLevel())},
            {"against_cell_m", L.cell},
            {"curves", curves},
            {"samples", diffs.size()},
            {"mean_abs_m", diffs.empty() ? 0.0 : sum / double(diffs.size())},
            {"p99_abs_m", diffs.empty() ? 0.0 : quantile(diffs, 0.99)},
            {"max_abs_m", worst},
            {"seconds", msSince(t0) / 1000.0}};
}

nlohmann::json benchFlyover(const FlyoverBenchOptions& o) {
    if (o.frames < 2) throw std::invalid_argument("bench flyover: --frames must be 2 or more");
    // Unpaced frames leave background work no time between them: the flight ends (a frame that
    // makes nothing takes microseconds) before the root's first subdivision arrives, and measures
    // nothing.
    if (o.fps <= 0.0 && o.backgroundMs > 0.0)
        throw std::invalid_argument("bench flyover: --fps 0 (unpaced) needs --background-ms 0: unpaced frames give the "
                                    "background threads no time between them, and the flight would end before their work arrives");
    SceneDocument doc;
    const bool lazy = !o.scene.empty() && o.vectorBudgetMiB > 0.0;
    LazyParams lazyParams;
    lazyParams.partLevel = o.partLevel;
    lazyParams.partQuadM = o.partQuadM;
    lazyParams.vectorBudgetMiB = o.vectorBudgetMiB;
    lazyParams.topElevationOnly = !o.pyramid.empty();
    std::string storedChecksum;
    std::size_t lazyCurves = 0;
    if (o.vectorBudgetMiB < 0.0 || (o.vectorBudgetMiB > 0.0 && o.scene.empty()))
        throw std::invalid_argument("bench flyover: --vector-budget needs --scene and must be > 0");
    if (lazy && o.pyramid == "auto") throw std::invalid_argument("bench flyover: --vector-budget takes a pyramid file, not auto");
    if (lazy) {
        // What the top tree reads (the session reads it again: the flight's path needs the DEM).
        LazyTop top = LazyForest::readTop(o.scene, lazyParams, RefineParams{});
        doc = std::move(top.doc);
        storedChecksum = top.stats.checksum;
        lazyCurves = top.stats.sceneCurves;
        if (doc.scene.layers.size() <= kRoadsLayer || !doc.dem)
            throw std::invalid_argument("bench flyover: " + o.scene + " has no DEM or no roads layer " + std::to_string(kRoadsLayer));
    } else if (!o.scene.empty()) {
        doc = loadScene(o.scene);
        if (doc.scene.layers.size() <= kRoadsLayer || !doc.dem)
            throw std::invalid_argument("bench flyover: " + o.scene + " has no DEM or no roads layer " + std::to_string(kRoadsLayer));
    } else {
        doc.scene = makeSyntheticScene({o.seed, o.curves});
        doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    }
    const double loadedRss = peakRssMiB();
    const FlightPath path = paperFlight(o.frames, o.startAltitude, o.endAltitude);
    const double length = path.along.back();
    // From above the centre to a road point the path's length away.
    const Vec2 start = doc.scene.extent.center();
    Vec2 end = start;
    double best = 1e300;
    // Read lazily, the roads within the path's length of the start (the same road point as with
    // the whole scene: any farther is worse).
    SceneDocument near;
    if (lazy) {
        SceneRegionOptions filter;
        filter.dem = false;
        near = loadSceneRegion(o.scene, Box{start - Vec2(length + 1000.0), start + Vec2(length + 1000.0)}, RefineParams{},
                               LazyParams{lazyParams}.level(doc.scene.extent), nullptr, filter);
    }
    for (const Curve& c : (lazy ? near : doc).scene.layers[kRoadsLayer].curves) {
        if (!c.alive || c.vertices.empty()) continue;
        const Vec2 p = c.vertices[c.vertices.size() / 2].p;
        const double d = std::abs(glm::length(p - start) - length);
        if (d < best) best = d, end = p;
    }
    const Vec2 direction = glm::length(end - start) > 0.0 ? glm::normalize(end - start) : Vec2(0.0, 1.0);
    // A scene too small for the path: the same flight, shortened to end above its road.
    const double scale = length > 0.0 ? std::min(1.0, glm::length(end - start) / length) : 1.0;
    auto viewerAt = [&](int f) {
        const std::size_t i = std::size_t(std::clamp(f, 0, o.frames - 1));
        const Vec2 p = start + direction * (path.along[i] * scale);
        return glm::dvec3(p.x, p.y, path.altitude[i]);
    };
    // The camera looks ahead along the path, steeply from high up, nearly level near the ground.
    const glm::dvec2 zRange = frustumHeightRange(*doc.dem);
    const double aspect = 1280.0 / 800.0;
    const std::size_t curveCount = lazy ? lazyCurves : count(doc.scene).curves;
    near = SceneDocument();
    // The ground under the camera: the DEM in memory of the session's document (the last run takes
    // the document itself, so a large scene is not held twice).
    auto cameraAt = [&](int f, const Dem& ground) {
        const glm::dvec3 v = viewerAt(f);
        const double span = std::log(o.startAltitude / o.endAltitude);
        const double high = span > 0.0 ? std::clamp(std::log(v.z / o.endAltitude) / span, 0.0, 1.0) : 1.0;
        Camera c;
        c.fly = true;
        c.flyPosition = glm::dvec3(v.x, v.y, ground.sample({v.x, v.y}) + v.z);
        c.yaw = std::atan2(direction.x, direction.y);
        c.pitch = 0.2 + (1.0 - 0.2) * high;  // radians below the horizon
        return c;
    };
    nlohmann::json runs = nlohmann::json::array();
    struct Run {
        double budget;
        bool prefetch, cull;
        double refineBudget;
        std::size_t cacheTiles = SessionParams{}.cacheTiles;
        bool pyramid = false;
        // What the run is (--runs picks them): the plain flight, with prefetching, with a refine
        // budget, with the paper's cache of 784 tiles, without culling, with a pyramid.
        std::string name() const {
            if (!cull) return "no-culling";
            if (refineBudget > 0.0) return "refine-budget";
            if (cacheTiles != SessionParams{}.cacheTiles) return "cache-784";
            return prefetch ? "prefetch" : pyramid ? "pyramid" : "plain";
        }
    };
    // The pyramid: given, or built for the scene into a temporary file removed at the end.
    std::shared_ptr<PyramidReader> pyramid;
    nlohmann::json pyramidJson;
    struct Remove {
        std::string path;
        ~Remove() {
            if (!path.empty()) std::filesystem::remove(path);
        }
    } temporary;
    if (!o.pyramid.empty()) {
        std::string file = o.pyramid;
        if (o.pyramid == "auto") {
            if (!(o.pyramidQuadM > 0.0)) throw std::invalid_argument("bench flyover: --pyramid-quad must be > 0");
            int maxLevel = 0;
            while (doc.scene.extent.size().x / double(1 << maxLevel) > o.pyramidQuadM * (1.0 + 1e-9) && maxLevel < 12) ++maxLevel;
            file = temporary.path =
                (std::filesystem::temp_directory_path() / ("lacet_flyover_" + std::to_string(::getpid()) + ".pyramid.gpkg")).string();
            PyramidParams params;
            params.maxLevel = maxLevel;
            params.vectorLevels = 1;
            const PyramidStats f = buildPyramid(doc, file, params, /*force=*/true, nullptr);
            pyramidJson = {{"built", true}, {"max_level", maxLevel}, {"quads", f.quads}, {"build_seconds", f.wallSeconds},
                           {"file_mib", double(std::filesystem::file_size(file)) / (1024.0 * 1024.0)}};
        }
        if (lazy) {  // the top part is not the whole scene: the file's stored checksum
            pyramid = std::make_shared<PyramidReader>(file, doc.scene.extent, doc.georeference.valid ? doc.georeference.crsWkt : std::string(),
                                                      storedChecksum);
            const int partLevel = lazyParams.level(doc.scene.extent);
            if (pyramid->vectorLevel() <= partLevel)
                throw std::invalid_argument("bench flyover: the pyramid's appearance is made from vector data from level " +
                                            std::to_string(pyramid->vectorLevel()) + ", not below the part level " +
                                            std::to_string(partLevel) + ": choose --part-level below it");
        } else {
            pyramid = std::make_shared<PyramidReader>(file, doc);
        }
        pyramidJson["file"] = o.pyramid == "auto" ? std::string("(temporary)") : file;
        pyramidJson["vector_level"] = pyramid->vectorLevel();
        pyramidJson["levels_read"] = {pyramid->minLevel(), pyramid->vectorLevel() - 1};
        pyramidJson["encoding"] = pyramid->encoding();
    }
    std::vector<Run> plan;
    if (!o.scene.empty())  // a scene file (its DEM streamed, if it is a tree): each budget once, or without and with its pyramid
        for (double budget : o.budgetsMs)
            for (const bool with : pyramid && !lazy ? std::vector<bool>{false, true} : std::vector<bool>{bool(pyramid)})
                plan.push_back({budget, false, true, 0.0, SessionParams{}.cacheTiles, with});
    else if (pyramid)  // each budget without and with the pyramid, nothing else
        for (double budget : o.budgetsMs)
            for (const bool with : {false, true}) plan.push_back({budget, false, true, 0.0, SessionParams{}.cacheTiles, with});
    for (double budget : pyramid || !o.scene.empty() ? std::vector<double>{} : o.budgetsMs)
        for (const bool prefetch : {false, true}) plan.push_back({budget, prefetch, true, 0.0});
    if (!pyramid && o.scene.empty()) {
        for (double budget : o.budgetsMs)  // half of the budget for subdivisions, the rest deferred
            if (budget > 0.0) plan.push_back({budget, false, true, 0.5 * budget});
        // The paper's 784 tiles: fewer than the flight's views need, so the farthest quads stand in
        // for their children (editor/cache_fit.h). What the smaller budget costs.
        for (double budget : o.budgetsMs) plan.push_back({budget, false, true, 0.0, 784});
        plan.push_back({0.0, false, false, 0.0});  // for comparison: every leaf of the view, no culling
    }
    if (!o.runs.empty())
        std::erase_if(plan, [&](const Run& r) { return std::find(o.runs.begin(), o.runs.end(), r.name()) == o.runs.end(); });
    const ViewParams view = [&] {
        ViewParams v;
        v.K = o.K;
        return v;
    }();
    // What K costs on screen: the texels of the leaves in view magnified, in screen pixels a
    // texel at the leaf's nearest point (its size / resolution seen at viewDistance, the 800
    // pixels of the window's height spanning the camera's vertical field of view).
    const double focalPixels = 800.0 / (2.0 * std::tan(0.5 * Camera{}.fovY));
    const double resolution = double(RefineParams{}.resolution);
    for (const Run& run : plan) {
        const double budget = run.budget;
        const bool prefetch = run.prefetch;
        SessionParams params;
        params.view = view;
        params.refineBudgetMs = run.refineBudget;
        params.backgroundMs = o.backgroundMs;
        params.cacheTiles = run.cacheTiles;
        params.demStream.budgetMiB = o.demBudgetMiB;
        params.demStream.profileSpacing = o.demProfileSpacingM;
        const auto opening = Clock::now();
        const std::unique_ptr<EditSession> owned =
            lazy ? std::make_unique<EditSession>(o.scene, lazyParams, params)
                 : std::make_unique<EditSession>(&run == &plan.back() ? std::move(doc) : SceneDocument(doc), params);
        EditSession& session = *owned;
        const double openMs = msSince(opening);
        const Dem& ground = *session.document().dem;
        std::optional<AdaptiveQuality> adaptive;
        if (o.adaptiveTargetMs > 0.0) adaptive.emplace(view.K, AdaptiveQualityParams{.targetMs = o.adaptiveTargetMs});
        std::size_t demFallbackFrames = 0, demFallbackTiles = 0, demRemade = 0, demHeldPeak = 0, partsArrived = 0;
        double kMin = view.K, kSum = 0.0;
        if (run.pyramid) session.setPyramid(pyramid);
        std::vector<double> ms, tiles, refine, produce, texelMagnification;
        std::size_t fromPyramid = 0, pyramidFailed = 0, backgroundStarted = 0, backgroundTaken = 0, backgroundDropped = 0,
                    backgroundSubdivisions = 0;
        std::size_t cachePeak = 0, pendingFrames = 0, prefetched = 0, deferredFrames = 0, replacedFrames = 0, replacedMax = 0;
        double replacedSum = 0.0, viewSum = 0.0;
        const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.fps > 0.0 ? 1.0 / o.fps : 0.0));
        Clock::time_point frameStart{};
        for (int f = 0; f < o.frames; ++f) {
            // Paced: a frame begins a period after the last one began, or at once when that one
            // took longer (no catching up); the rest of the period is the window's (drawing, vsync).
            if (o.fps > 0.0 && f > 0) std::this_thread::sleep_until(frameStart + period);
            frameStart = Clock::now();
            const Camera cam = cameraAt(f, ground);
            const QuadVisibility visible =
                run.cull ? frustumVisibility(cam, aspect, Camera::clipRange(viewerAt(f).z), zRange) : QuadVisibility{};
            const auto t0 = Clock::now();
            const FrameReport r = session.frame(viewerAt(f), budget, visible,
                                                prefetch ? std::optional<glm::dvec3>(viewerAt(f + o.prefetchFrames)) : std::nullopt);
            ms.push_back(msSince(t0));
            double pixelsPerTexel = 0.0;  // the largest of the frame's leaves in view
            session.quadtree().forEachQuad([&](const Quad& q) {
                if (!q.isLeaf() || (visible && !visible(q))) return;
                const double d = std::max(Quadtree::viewDistance(q, viewerAt(f)), 1e-3);
                pixelsPerTexel = std::max(pixelsPerTexel, q.bounds.size().x / resolution * focalPixels / d);
            });
            texelMagnification.push_back(pixelsPerTexel);
            if (adaptive) {
                kSum += adaptive->K();
                const double k = adaptive->onFrame(ms.back(), r.pending == 0);
                if (k != session.params().view.K) session.setK(k);
                kMin = std::min(kMin, k);
            }
            demFallbackFrames += r.demFallbacks > 0;
            demFallbackTiles += r.demFallbacks;
            demRemade += r.demRemade;
            partsArrived += r.partsArrived;
            if (const DemStream* d = session.demStream()) demHeldPeak = std::max(demHeldPeak, d->stats().held);
            tiles.push_back(double(r.produced));
            refine.push_back(r.refineMs);
            produce.push_back(r.produceMs);
            cachePeak = std::max(cachePeak, r.cached);
            fromPyramid += r.fromPyramid;
            backgroundStarted += r.backgroundStarted;
            backgroundTaken += r.backgroundTaken;
            backgroundDropped += r.backgroundDropped;
            backgroundSubdivisions += r.backgroundSubdivisions;
            pyramidFailed += r.pyramidFailed;
            pendingFrames += r.pending > 0;
            prefetched += r.prefetched;
            deferredFrames += r.refineDeferred;
            replacedFrames += r.replaced > 0;
            replacedMax = std::max(replacedMax, r.replaced);
            replacedSum += double(r.replaced);
            viewSum += double(r.viewQuads);
        }
        double sum = 0.0, tileSum = 0.0;
        for (double v : ms) sum += v;
        for (double v : tiles) tileSum += v;
        // The first frame subdivides the tree from the root down (a scene's opening, not flight).
        const std::vector<double> flight(ms.begin() + 1, ms.end()), flightRefine(refine.begin() + 1, refine.end());
        double flightSum = 0.0, refineSum = 0.0;
        for (double v : flight) flightSum += v;
        for (double v : flightRefine) refineSum += v;
        // The slowest flight frames, and where their time went.
        std::vector<std::size_t> order(ms.size() - 1);
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i + 1;
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ms[a] > ms[b]; });
        nlohmann::json worst = nlohmann::json::array();
        for (std::size_t i = 0; i < std::min<std::size_t>(3, order.size()); ++i) {
            const std::size_t f = order[i];
            worst.push_back({{"frame", f}, {"ms", ms[f]}, {"refine_ms", refine[f]}, {"produce_ms", produce[f]}, {"tiles", tiles[f]}});
        }
        nlohmann::json dem;
        if (const DemStream* d = session.demStream()) {
            const DemStreamStats st = d->stats();
            const DemLodLayout& L = d->layout();
            dem = {{"budget_mib", o.demBudgetMiB},
                   {"grid", {L.width, L.height}},
                   {"cell_m", L.cell},
                   {"levels", L.levels},
                   {"block_side", L.blockSide},
                   {"blocks_loaded", st.loaded},
                   {"blocks_loaded_sync_for_profiles", st.loadedSync},
                   {"profile_level", d->profileLevel()},
                   {"profile_level_cell_m", L.levelCell(d->profileLevel())},
                   {"blocks_evicted", st.evicted},
                   {"requests_refused_by_budget", st.refused},
                   {"blocks_failed", st.failed},
                   {"blocks_held_peak", demHeldPeak},
                   {"blocks_held_peak_mib", double(demHeldPeak) * double(L.blockSide) * double(L.blockSide) * 4.0 / 1048576.0},
                   {"load_ms", st.loadMs},
                   {"windows", st.windows},
                   {"windows_from_coarser_block", st.fallbacks},
                   {"frames_with_tiles_from_coarser_block", demFallbackFrames},
                   {"tiles_from_coarser_block", demFallbackTiles},
                   {"tiles_remade_when_finer_blocks_arrived", demRemade}};
        }
        nlohmann::json lazyJson;
        if (const LazyForest* f = session.lazyForest()) {
            const LazyStats& st = f->stats();
            lazyJson = {{"vector_budget_mib", o.vectorBudgetMiB}, {"part_level", st.partLevel},
                        {"part_quad_m", doc.scene.extent.size().x / double(std::int64_t(1) << st.partLevel)},
                        {"top_mib", st.topMiB}, {"top_elevation_only", lazyParams.topElevationOnly},
                        {"parts_read", st.partsRead}, {"parts_evicted", st.partsEvicted}, {"parts_refused", st.partsRefused},
                        {"parts_held_peak", st.partsHeldPeak}, {"parts_peak_mib", st.peakMiB},
                        {"largest_part_mib", st.largestPartMiB}, {"read_ms_total", st.readMs},
                        {"slowest_read_ms", st.slowestReadMs}, {"last_error", st.lastError}};
        }
        nlohmann::json profileJson;
        if (o.profileError && session.demStream()) profileJson = profileError(session, o, start, end);
        nlohmann::json adaptiveJson;
        if (adaptive)
            adaptiveJson = {{"target_ms", o.adaptiveTargetMs}, {"K_min", kMin}, {"K_mean", kSum / double(ms.size())},
                            {"lowered", adaptive->lowered()}, {"raised", adaptive->raised()}};
        runs.push_back({{"run", run.name()},
                        {"budget_ms", budget},
                        {"dem_stream", dem},
                        {"lazy", lazyJson},
                        {"session_open_ms", openMs},
                        {"tiles_remade_when_parts_arrived", partsArrived},
                        {"profile_error", profileJson},
                        {"adaptive_K", adaptiveJson},
                        {"peak_rss_mib_so_far", peakRssMiB()},
                        {"pyramid", run.pyramid},
                        {"pyramid_tiles_read", fromPyramid},
                        {"pyramid_tiles_failed", pyramidFailed},
                        {"background", {{"slower_than_ms", o.backgroundMs}, {"tiles_begun", backgroundStarted},
                                        {"tiles_taken", backgroundTaken}, {"subdivisions_begun", backgroundSubdivisions},
                                        {"dropped", backgroundDropped}}},
                        {"slowest_frames", worst},
                        {"first_frame_ms", ms.front()},
                        {"flight_mean_ms", flightSum / double(flight.size())},
                        {"flight_median_ms", median(flight)},
                        {"flight_p99_8_ms", quantile(flight, 0.998)},
                        {"flight_refine_mean_ms", refineSum / double(flight.size())},
                        {"flight_refine_max_ms", quantile(flightRefine, 1.0)},
                        {"prefetch", prefetch},
                        {"frustum_culling", run.cull},
                        {"refine_budget_ms", run.refineBudget},
                        {"prefetched_tiles", prefetched},
                        {"frames", ms.size()},
                        {"mean_ms", sum / double(ms.size())},
                        {"median_ms", median(ms)},
                        {"p99_8_ms", quantile(ms, 0.998)},
                        {"max_ms", quantile(ms, 1.0)},
                        {"tiles_per_frame_mean", tileSum / double(ms.size())},
                        {"tiles_per_frame_max", quantile(tiles, 1.0)},
                        {"cache_peak_tiles", cachePeak},
                        {"cache_tiles", run.cacheTiles},
                        {"view_leaves_mean", viewSum / double(ms.size())},
                        {"screen_pixels_per_texel",  // of each frame's most magnified leaf in view
                         {{"frame_median", median(texelMagnification)}, {"frame_max", quantile(texelMagnification, 1.0)}}},
                        {"frames_with_replaced_leaves", replacedFrames},
                        {"replaced_leaves_mean", replacedSum / double(ms.size())},
                        {"replaced_leaves_max", replacedMax},
                        {"frames_with_pending_tiles", pendingFrames},
                        {"frames_with_deferred_subdivisions", deferredFrames}});
    }
    return {{"curves", curveCount},
            {"K", view.K},
            {"appearance_resolution", RefineParams{}.resolution},
            {"path", {{"from_altitude_m", o.startAltitude}, {"to_altitude_m", o.endAltitude}, {"length_m", length * scale},
                      {"seconds_at_60_fps", double(o.frames - 1) / 60.0}, {"times_the_papers_speed", 73.0 * 60.0 / double(o.frames - 1)},
                      {"end_to_road_m", std::abs(glm::length(end - start) - length * scale)}}},
            {"prefetch_frames_ahead", o.prefetchFrames},
            {"runs", runs},
            {"pyramid", pyramidJson},
            {"scene", o.scene.empty() ? std::string("(synthetic)") : o.scene},
            {"peak_rss_mib_after_loading", loadedRss},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
