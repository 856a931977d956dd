// `lacet synth`: generates a synthetic scene, optionally its view-refined quadtree, and prints
// a summary (text, or JSON with --json).
#include <algorithm>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iostream>
#include <limits>
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
    // With --dem-side: the largest side (samples) of the in-memory base DEM the fine one is made from;
    // a scene whose --dem-resolution grid is larger gets coarser base cells. 8192: 0.25 GiB of
    // heights; 38.6 m cells at 6M curves, where the base's rivers still run downhill within its
    // tolerance (synth/synthetic_dem.h: cells of 20 to 40 m).
    int baseDemMaxSide = 8192;
    int demSide = 0;        // > 0: a DEM of this many samples a side, written out of core (FineSyntheticDem)
    double altitude = 0.0;  // > 0: build the quadtree for a viewer this high above the centre
    ViewParams view;
};

// What a layer holds alive, counted a part at a time.
struct LayerTally {
    std::size_t nodes = 0, curves = 0, areas = 0, controls = 0;
    void add(const Layer& l) {
        for (const auto& n : l.nodes) nodes += n.alive;
        for (const auto& c : l.curves) {
            if (!c.alive) continue;
            ++curves;
            for (const auto& v : c.vertices) controls += !v.onCurve;
        }
        for (const auto& a : l.areas) areas += a.alive;
    }
};

// A fields part of the streamed save: about 1% of the paper's dataset (a few MiB in memory).
constexpr std::size_t kPartCurves = 8192;

// The lod DEM of --dem-side beside the output (its rows made in batches on every core, written in
// order) into doc.demLod, and its figures; `lodFile` is set once it is written.
nlohmann::json writeFineDem(const SynthOptions& o, SceneDocument& doc, RemoveFileOnExit& lodFile) {
    using namespace lacet::bench;
    const auto t0 = Clock::now();
    const Dem base = std::move(*doc.dem);
    doc.dem.reset();
    const FineSyntheticDem fine(doc.scene, base, {.side = o.demSide, .seed = o.seed});
    const DemLodLayout layout = DemLodLayout::make(o.demSide, o.demSide, fine.cell(), fine.topLeft());
    const std::string lodPath = uniqueDemLodPath(o.out);  // a new name: never a file found there
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
    const double demMs = msSince(t0);
    doc.dem = std::move(lod.coarse);
    doc.demLod = std::make_shared<const DemLodFile>(lodFile.path);
    return {{"dem_side", o.demSide}, {"cell_m", layout.cell}, {"levels", layout.levels}, {"block_side", layout.blockSide},
            {"tiles", lod.tiles}, {"tile_bytes", lod.bytes}, {"lod_file_bytes", std::filesystem::file_size(lodFile.path)},
            {"in_memory_level", lod.coarseLevel}, {"in_memory_grid", {doc.dem->width(), doc.dem->height()}},
            {"write_s", lod.ms / 1000.0}, {"dem_s", demMs / 1000.0}};
}

void run(const SynthOptions& o) {
    using namespace lacet::bench;
    auto t0 = Clock::now();
    SyntheticSceneParts parts({o.seed, o.curves});
    SceneDocument doc;
    doc.scene = parts.takeScene();
    // With --out alone, the fields (nearly all of the curves) are made while the file is written, a
    // part at a time, and never held whole: memory follows the other layers and the DEM, not the
    // scene (issue 23). The quadtree of --view-altitude needs the whole scene in memory.
    const bool streamed = !o.out.empty() && o.altitude <= 0.0;
    std::vector<LayerTally> tally(doc.scene.layers.size());
    for (std::size_t l = 0; l < tally.size(); ++l) tally[l].add(doc.scene.layers[l]);
    const auto addFields = [&](Layer&& part) {
        tally[kFieldsLayer].add(part);
        appendLayerPart(doc.scene.layers[kFieldsLayer], std::move(part));
    };
    if (!streamed) {
        parts.fields(addFields, std::numeric_limits<std::size_t>::max());
        validateOrThrow(doc.scene);
    }
    const double synthMs = msSince(t0);
    const Scene& s = doc.scene;
    nlohmann::json out = {{"seed", o.seed}, {"extent_m", {s.extent.min.x, s.extent.min.y, s.extent.max.x, s.extent.max.y}},
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
        t0 = Clock::now();
        // From the rivers: the fields need not be made yet.
        int resolution = o.demResolution;
        if (o.demSide > 0)
            resolution = std::min(resolution, int(std::floor(double(o.baseDemMaxSide) * 100000.0 / s.extent.size().x)));
        doc.dem = makeSyntheticDem(s, {o.seed, std::max(resolution, 1)});
        const nlohmann::json baseSamples = {doc.dem->width(), doc.dem->height()};
        double demMs = msSince(t0);
        // The lod DEM's file, beside the output, once written: removed after the save (also when it
        // fails).
        RemoveFileOnExit lodFile;
        nlohmann::json lodJson;
        if (o.demSide > 0) {
            lodJson = writeFineDem(o, doc, lodFile);
            lodJson["base_dem_samples"] = baseSamples;
            demMs = lodJson["dem_s"].get<double>() * 1000.0;
        }
        t0 = Clock::now();
        if (streamed)
            saveSceneStreamed(o.out, doc, kFieldsLayer, [&](const std::function<void(Layer&&)>& sink) {
                parts.fields([&](Layer&& part) {
                    tally[kFieldsLayer].add(part);
                    sink(std::move(part));
                }, kPartCurves);
            });
        else
            saveScene(o.out, doc);
        const double saveMs = msSince(t0);
        out["scene_file"] = {{"path", o.out}, {"bytes", std::filesystem::file_size(o.out)}, {"dem_ms", demMs},
                             {"dem_samples", {doc.dem->width(), doc.dem->height()}}, {"save_ms", saveMs},
                             {"fields_made_while_saving", streamed}};
        if (streamed) out["scene_file"]["part_curves"] = kPartCurves;
        if (!streamed) {
            // The scene is in memory anyway: read it back whole, as a check and a figure.
            t0 = Clock::now();
            const SceneDocument back = loadScene(o.out);
            out["scene_file"]["load_ms"] = msSince(t0);
            out["scene_file"]["curves_loaded"] = count(back.scene).curves;
        }
        if (!lodJson.is_null()) out["scene_file"]["dem_lod"] = lodJson;
    }
    nlohmann::json layers = nlohmann::json::array();
    LayerTally total;
    for (std::size_t l = 0; l < tally.size(); ++l) {
        const LayerTally& t = tally[l];
        layers.push_back({{"name", s.layers[l].name}, {"kind", toString(s.layers[l].kind)}, {"nodes", t.nodes},
                          {"curves", t.curves}, {"areas", t.areas}, {"control_points", t.controls}});
        total.nodes += t.nodes, total.curves += t.curves, total.areas += t.areas, total.controls += t.controls;
    }
    out["nodes"] = total.nodes;
    out["curves"] = total.curves;
    out["areas"] = total.areas;
    out["control_points"] = total.controls;
    out["nodes_and_control_points"] = total.nodes + total.controls;
    out["layers"] = layers;
    out["peak_rss_mib"] = peakRssMiB();
    if (o.json) {
        std::cout << out.dump(2) << "\n";
        return;
    }
    std::cout << "Synthetic scene (seed " << o.seed << "): " << total.curves << " curves, " << total.areas << " areas, "
              << total.nodes << " nodes, " << total.controls << " control points, "
              << s.extent.size().x / 1000.0 << " km wide, generated in " << synthMs << " ms"
              << (streamed ? " (the fields while saving)" : "") << "\n";
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
    cmd->add_option("--out", o->out, "Also save the scene and its synthetic DEM as a scene file (GeoPackage), the fields made while it is written (with --view-altitude: made whole, saved, loaded back)");
    cmd->add_option("--dem-resolution", o->demResolution, "Synthetic DEM samples per 100 km (with --out)");
    cmd->add_option("--dem-side", o->demSide,
                    "With --out: a DEM of this many samples a side over the scene (e.g. 20480: 5 m cells over 100 km), the "
                    "--dem-resolution DEM plus fine detail, written out of core as a LOD tree")
        ->check(CLI::Range(2, kMaxLodDemSide));
    cmd->add_option("--base-dem-max-side", o->baseDemMaxSide,
                    "With --dem-side: the largest side (samples) of the in-memory DEM the fine one is made from (coarser "
                    "cells beyond: memory)")
        ->check(CLI::Range(2, kMaxLodDemSide));
    cmd->callback([o] { run(*o); });
}

}  // namespace lacet::app
