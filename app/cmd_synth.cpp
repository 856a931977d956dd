// `lacet synth`: generates a synthetic scene, optionally its view-refined quadtree, and prints
// a summary (text, or JSON with --json).
#include <algorithm>
#include <exception>
#include <filesystem>
#include <iostream>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bench/bench_util.h"
#include "io/dem_import_lod.h"
#include "io/dem_lod.h"
#include "io/scene_file.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "model/validate.h"
#include "synth/fine_synthetic_dem.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::app {
namespace {

struct SynthOptions {
    std::uint64_t seed = 1;
    std::size_t curves = 10000;
    bool json = false;
    std::string out;         // a scene file to write (with the synthetic DEM)
    int demResolution = 5000;
    int demSide = 0;        // > 0: a DEM of this many samples a side, written out of core (FineSyntheticDem)
    double altitude = 0.0;  // > 0: build the quadtree for a viewer this high above the centre
    ViewParams view;
};

nlohmann::json layerCounts(const Scene& s) {
    nlohmann::json layers = nlohmann::json::array();
    for (const Layer& l : s.layers) {
        std::map<std::string, std::size_t> classes;
        std::size_t nodes = 0, curves = 0, areas = 0, controls = 0;
        for (const auto& n : l.nodes) nodes += n.alive;
        for (const auto& c : l.curves) {
            if (!c.alive) continue;
            ++curves;
            for (const auto& v : c.vertices) controls += !v.onCurve;
        }
        for (const auto& a : l.areas) areas += a.alive;
        layers.push_back({{"name", l.name}, {"kind", toString(l.kind)}, {"nodes", nodes}, {"curves", curves},
                          {"areas", areas}, {"control_points", controls}});
    }
    return layers;
}

void run(const SynthOptions& o) {
    using namespace lacet::bench;
    auto t0 = Clock::now();
    const Scene s = makeSyntheticScene({o.seed, o.curves});
    const double synthMs = msSince(t0);
    validateOrThrow(s);
    const SceneCounts c = count(s);
    nlohmann::json out = {{"seed", o.seed},
                          {"extent_m", {s.extent.min.x, s.extent.min.y, s.extent.max.x, s.extent.max.y}},
                          {"nodes", c.nodes},
                          {"curves", c.curves},
                          {"areas", c.areas},
                          {"control_points", c.controlPoints},
                          {"nodes_and_control_points", c.nodes + c.controlPoints},
                          {"layers", layerCounts(s)},
                          {"generate_ms", synthMs}};
    if (o.altitude > 0.0) {
        t0 = Clock::now();
        GraphStep qtStep(s);
        Quadtree qt(s, {}, &qtStep);
        const Vec2 centre = s.extent.center();
        qt.refineForViewer({centre.x, centre.y, o.altitude}, o.view);
        const double buildMs = msSince(t0);
        std::map<int, std::size_t> quads, pieces;
        qt.forEachQuad([&](const Quad& q) {
            ++quads[q.level];
            for (const auto& l : q.layers) pieces[q.level] += l.nodes.size() + l.curves.size() + l.areas.size();
        });
        nlohmann::json levels = nlohmann::json::array();
        for (const auto& [level, n] : quads) levels.push_back({{"level", level}, {"quads", n}, {"ancestor_buckets", pieces[level]}});
        out["quadtree"] = {{"viewer_altitude_m", o.altitude}, {"K", o.view.K}, {"quads", qt.quadCount()},
                           {"depth", qt.depth()}, {"build_ms", buildMs}, {"levels", levels}};
    }
    if (!o.out.empty()) {
        SceneDocument doc;
        doc.scene = s;
        t0 = Clock::now();
        doc.dem = makeSyntheticDem(s, {o.seed, o.demResolution});
        double demMs = msSince(t0);
        // The lod DEM's file, beside the output, once written: removed after the save (also when it
        // fails).
        RemoveFileOnExit lodFile;
        nlohmann::json lodJson;
        if (o.demSide > 0) {
            t0 = Clock::now();
            const Dem base = std::move(*doc.dem);
            doc.dem.reset();
            const FineSyntheticDem fine(s, base, {.side = o.demSide, .seed = o.seed});
            const DemLodLayout layout = DemLodLayout::make(o.demSide, o.demSide, fine.cell(), fine.topLeft());
            const std::string lodPath = uniqueDemLodPath(o.out);  // a new name: never a file found there
            // Rows made in batches on every core, written in order.
            constexpr int kBatch = 32;
            const int threads = int(std::max(1u, std::thread::hardware_concurrency()));
            std::vector<float> batch(std::size_t(kBatch) * std::size_t(o.demSide));
            int first = -kBatch;
            DemLodOutput lod = writeDemLodFile(lodPath, layout, [&](int t, std::span<float> row) {
                if (t >= first + kBatch) {
                    first = t;
                    const int rows = std::min(kBatch, o.demSide - first);
                    // A worker's exception (fine.row() throws, e.g. bad_alloc) is kept, the first one
                    // rethrown here after every worker is joined: none escapes a thread (terminate).
                    std::vector<std::thread> workers;
                    std::mutex failedMutex;
                    std::exception_ptr failed;
                    for (int w = 0; w < threads; ++w)
                        workers.emplace_back([&, w] {
                            try {
                                for (int k = w; k < rows; k += threads)
                                    fine.row(first + k,
                                             std::span<float>(batch).subspan(std::size_t(k) * std::size_t(o.demSide), std::size_t(o.demSide)));
                            } catch (...) {
                                const std::lock_guard lock(failedMutex);
                                if (!failed) failed = std::current_exception();
                            }
                        });
                    for (std::thread& w : workers) w.join();
                    if (failed) std::rethrow_exception(failed);
                }
                const auto from = batch.begin() + std::ptrdiff_t(std::size_t(t - first) * std::size_t(o.demSide));
                std::copy(from, from + o.demSide, row.begin());
            });
            lodFile.path = lodPath;  // written (writeDemLodFile removes it when it fails)
            demMs = msSince(t0);
            doc.dem = std::move(lod.coarse);
            doc.demLod = std::make_shared<const DemLodFile>(lodFile.path);
            lodJson = {{"dem_side", o.demSide}, {"cell_m", layout.cell}, {"levels", layout.levels}, {"block_side", layout.blockSide},
                       {"tiles", lod.tiles}, {"tile_bytes", lod.bytes}, {"lod_file_bytes", std::filesystem::file_size(lodFile.path)},
                       {"in_memory_level", lod.coarseLevel}, {"in_memory_grid", {doc.dem->width(), doc.dem->height()}},
                       {"write_s", lod.ms / 1000.0}, {"dem_s", demMs / 1000.0}};
        }
        t0 = Clock::now();
        saveScene(o.out, doc);
        const double saveMs = msSince(t0);
        t0 = Clock::now();
        const SceneDocument back = loadScene(o.out);
        const double loadMs = msSince(t0);
        out["scene_file"] = {{"path", o.out}, {"bytes", std::filesystem::file_size(o.out)}, {"dem_ms", demMs},
                             {"dem_samples", {doc.dem->width(), doc.dem->height()}}, {"save_ms", saveMs}, {"load_ms", loadMs},
                             {"curves_loaded", count(back.scene).curves}};
        if (!lodJson.is_null()) out["scene_file"]["dem_lod"] = lodJson;
    }
    out["peak_rss_mib"] = peakRssMiB();
    if (o.json) {
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << "Synthetic scene (seed " << o.seed << "): " << c.curves << " curves, " << c.areas << " areas, "
              << c.nodes << " nodes, " << c.controlPoints << " control points, "
              << s.extent.size().x / 1000.0 << " km wide, generated in " << synthMs << " ms\n";
    for (const auto& l : out["layers"])
        std::cout << "  " << l["name"].get<std::string>() << ": " << l["curves"] << " curves, " << l["areas"]
                  << " areas, " << l["nodes"] << " nodes\n";
    if (out.contains("quadtree")) {
        const auto& q = out["quadtree"];
        std::cout << "Quadtree for a viewer " << o.altitude << " m above the centre (K = " << o.view.K << "): " << q["quads"]
                  << " quads, depth " << q["depth"] << ", built in " << q["build_ms"] << " ms\n";
        for (const auto& l : q["levels"])
            std::cout << "  level " << l["level"] << ": " << l["quads"] << " quads, " << l["ancestor_buckets"] << " clipped elements\n";
    }
    if (out.contains("scene_file")) std::cout << "Scene file: " << out["scene_file"].dump() << "\n";
    std::cout << "Peak memory: " << out["peak_rss_mib"] << " MiB\n";
}

}  // namespace

void addSynthCommand(CLI::App& app) {
    auto o = std::make_shared<SynthOptions>();
    CLI::App* cmd = app.add_subcommand("synth", "Generate a synthetic scene and print its counts");
    cmd->add_option("--seed", o->seed, "Random seed");
    cmd->add_option("--curves", o->curves, "Target number of curves (600000 = the paper's dataset)");
    cmd->add_option("--view-altitude", o->altitude, "Also build the quadtree for a viewer this high (m) above the centre");
    cmd->add_option("--K", o->view.K, "Subdivision factor: split quads closer than K times their size");
    cmd->add_option("--max-level", o->view.maxLevel, "Deepest quadtree level");
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->add_option("--out", o->out, "Also save the scene and its synthetic DEM as a scene file (GeoPackage), then load it back");
    cmd->add_option("--dem-resolution", o->demResolution, "Synthetic DEM samples per 100 km (with --out)");
    cmd->add_option("--dem-side", o->demSide,
                    "With --out: a DEM of this many samples a side over the scene (e.g. 20480: 5 m cells over 100 km), the "
                    "--dem-resolution DEM plus fine detail, written out of core as a LOD tree")
        ->check(CLI::Range(2, kMaxLodDemSide));
    cmd->callback([o] { run(*o); });
}

}  // namespace lacet::app
