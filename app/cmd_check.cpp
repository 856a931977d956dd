// `lacet check incremental`: random edits on a synthetic scene; after each, the incrementally
// updated quadtree is compared with a rebuild from scratch. Exits non-zero on any mismatch. With
// `--lazy`: edits of the scene read lazily against edits of it whole, tile for tile.
// `lacet check bridges`: a scene's decks clear the water and leave the river bed as it is
// (raster/bridge_check.h); exits non-zero when they do not, or when no bridge spans a river.
// `lacet check rivers`: river profiles and nodes against the DEM (raster/river_check.h); exits
// non-zero when a river rises downstream, or when the scene has no river.
// `lacet check heights`: a pyramid's elevation tiles against the DEM level their quads need
// (pyramid/pyramid_height_check.h); exits non-zero when a tile agrees best with another level, or
// when no tile decided.
// `lacet check fit`: the Hausdorff distance between a scene's curves and the GIS sources they
// were imported from, per layer (io/fit_check.h). Exits non-zero when anything is farther than
// the tolerance.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bench/bench_util.h"
#include "editor/edit_session.h"
#include "editor/lazy_edit_check.h"
#include "io/dem_stream.h"
#include "io/fit_check.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "io/scene_parts.h"
#include "model/validate.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_height_check.h"
#include "raster/bridge_check.h"
#include "raster/river_check.h"
#include "synth/incremental_check.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::app {
namespace {

struct CheckOptions {
    std::uint64_t seed = 1;
    std::size_t curves = 10000;
    int edits = 100;
    int depth = 12;
    int viewEvery = 10;
    std::size_t sample = 0;        // quads compared after each edit (0: all, the whole tree rebuilt)
    int fullEvery = 0;             // with --sample: every quad compared every this many edits
    double undoChance = 0.0;       // each edit undone (then redone half the time) with this probability
    bool json = false;
    bool lazy = false;             // edits of the scene read lazily against the whole scene's
    double vectorBudgetMiB = 512.0;
    int partLevel = -1;
    int saveEvery = 8;             // with --lazy: the lazy edits saved into the file every this many edits (0: never)
};

// `--lazy`: the synthetic scene saved into a temporary file, edited through a session reading it
// lazily and one holding it whole (editor/lazy_edit_check.h); exits non-zero on any mismatch, or
// when nothing was compared.
int runLazy(const CheckOptions& o) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({o.seed, o.curves});
    doc.dem = makeSyntheticDem(doc.scene, {o.seed, 5000});
    struct Remove {
        std::string path;
        ~Remove() { std::filesystem::remove(path); }
    } file{(std::filesystem::temp_directory_path() / ("lacet_check_lazy_" + std::to_string(::getpid()) + ".gpkg")).string()};
    saveScene(file.path, doc);
    const std::size_t curves = count(doc.scene).curves;
    doc = SceneDocument();
    SessionParams params;
    params.view.maxLevel = o.depth;
    params.cacheTiles = 1u << 20;  // every tile made stays to be compared
    EditSession whole(loadScene(file.path), params);
    LazyParams lazy;
    lazy.vectorBudgetMiB = o.vectorBudgetMiB;
    lazy.partLevel = o.partLevel;
    lazy.background = false;  // deterministic: a part is read in the frame that wants it
    EditSession session(file.path, lazy, params);
    const LazyEditCheckReport r = checkLazyEdits(session, whole, {.seed = o.seed * 7919 + 1, .edits = o.edits, .saveEvery = o.saveEvery});
    const LazyStats& st = session.lazyForest()->stats();
    const nlohmann::json out = {{"seed", o.seed},
                                {"curves", curves},
                                {"depth", o.depth},
                                {"lazy", {{"vector_budget_mib", o.vectorBudgetMiB}, {"part_level", st.partLevel}, {"parts_read", st.partsRead},
                                          {"parts_renewed", st.partsRenewed}, {"parts_updated_in_place", st.partsUpdated},
                                          {"parts_moved_in_memory", st.partsMoved}, {"parts_grown_in_memory", st.partsGrown},
                                          {"top_reads", r.topReads}}},
                                {"edits", r.edits},
                                {"commands", r.commands},
                                {"refused_by_both", r.refused},
                                {"refused_by_one", r.refusedDifferently},
                                {"undos", r.undos},
                                {"redos", r.redos},
                                {"tiles_compared", r.tilesCompared},
                                {"mismatches", r.mismatches},
                                {"mismatch_details", r.details},
                                {"lazy_command_median_ms", bench::median(r.lazyMs)},
                                {"lazy_command_p95_ms", bench::quantile(r.lazyMs, 0.95)},
                                {"whole_command_median_ms", bench::median(r.wholeMs)},
                                {"saves", r.saves},
                                {"save_median_ms", bench::median(r.saveMs)}};
    if (o.json) std::cout << out.dump(2) << "\n";
    else
        std::cout << r.edits << " edits of a scene read lazily (" << r.commands << " commands, " << r.undos << " undos, " << r.redos
                  << " redos, " << r.saves << " saves), " << r.tilesCompared << " tiles compared with the whole scene's, " << r.mismatches << " mismatches\n";
    if (r.edits == 0 || r.tilesCompared == 0) {
        std::cerr << "lacet check incremental --lazy: nothing was compared\n";
        return 2;
    }
    return r.mismatches == 0 ? 0 : 2;
}

int run(const CheckOptions& o) {
    Scene s = makeSyntheticScene({o.seed, o.curves});
    const auto t0 = std::chrono::steady_clock::now();
    const IncrementalCheckReport r = checkIncremental(s, {.seed = o.seed * 7919 + 1, .edits = o.edits, .maxLevel = o.depth,
                                                          .viewEvery = o.viewEvery, .reach = s.extent.size().x * 0.01,
                                                          .viewerHeight = 2.0, .viewerHeightRange = 50.0,
                                                          .sample = o.sample, .fullEvery = o.fullEvery,
                                                          .undoChance = o.undoChance, .detailsPerEdit = 5, .maxDetails = 20});
    const double wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::map<std::string, std::size_t> byKind;
    for (const auto& [kind, n] : r.byKind) byKind[std::string(toString(kind))] = n;
    const bool valid = validate(s).empty();
    const nlohmann::json out = {{"seed", o.seed},
                                {"curves", count(s).curves},
                                {"depth", o.depth},
                                {"edits", r.edits},
                                {"edits_by_kind", byKind},
                                {"undo_chance", o.undoChance},
                                {"undos", r.undos},
                                {"redos", r.redos},
                                {"sample", o.sample},
                                {"full_every", o.fullEvery},
                                {"full_comparisons", r.fullComparisons},
                                {"quads_compared", r.quadsCompared},
                                {"mismatches", r.mismatches},
                                {"mismatch_details", r.details},
                                {"scene_valid", valid},
                                {"graph_step", {{"edits_adding_bridges", r.editsAddingBridges},
                                                {"edits_removing_bridges", r.editsRemovingBridges},
                                                {"edits_adding_roundabout_arcs", r.editsAddingRings},
                                                {"edits_removing_roundabout_arcs", r.editsRemovingRings},
                                                {"bridges_at_end", r.bridgesAtEnd},
                                                {"roundabout_arcs_at_end", r.ringArcsAtEnd}}},
                                {"update_median_ms", bench::median(r.updateMs)},
                                {"rebuild_median_ms", bench::median(r.rebuildMs)},
                                {"wall_s", wallS}};
    if (o.json) std::cout << out.dump(2) << "\n";
    else
        std::cout << r.edits << " edits (" << r.undos << " undone, " << r.redos << " of them redone; " << r.editsAddingBridges << " adding bridges, " << r.editsRemovingBridges
                  << " removing some, " << r.editsAddingRings << " adding roundabout arcs, " << r.editsRemovingRings
                  << " removing some), " << r.quadsCompared << " quad comparisons, " << r.mismatches << " mismatches\n";
    return r.mismatches == 0 && valid ? 0 : 2;
}

struct FitOptions {
    std::string scene;
    std::vector<std::string> sources;
    std::string mapping;
    FitCheckParams params;
    bool json = false;
};

int runFit(const FitOptions& o) {
    const SceneDocument doc = loadScene(o.scene);
    const FeatureMapping mapping = o.mapping.empty() ? defaultMapping() : loadMapping(o.mapping);
    VectorData data;
    data.dedupOsmIds = o.sources.size() > 1;
    for (const std::string& path : o.sources) readVectors(path, mapping, data);
    if (!data.fileErrors.empty()) {
        std::string why;
        for (const std::string& e : data.fileErrors) why += "\n  " + e;
        throw std::runtime_error("check fit: a source could not be read whole, nothing was checked:" + why);
    }
    const FitCheckReport r = checkFit(doc, data, mapping, o.params);
    if (o.json) {
        std::cout << r.json().dump(2) << "\n";
    } else {
        std::cout << "Fit of " << o.scene << " against its sources (tolerance " << o.params.tolerance << " m, measured within "
                  << o.params.precision << " m):\n";
        for (const FitCheckLayer& l : r.layers)
            std::cout << "  " << l.name << ": " << l.curves << " curves (" << l.vertices << " vertices, " << l.onCurveVertices
                      << " on-curve), curve to source <= " << l.curveToSourceUpper << " m, source to curve <= "
                      << l.sourceToCurveUpper << " m; over the tolerance: " << l.curvesOver << " curves, " << l.sourcesOver
                      << " sources\n";
        std::cout << "  sources outside the scene (not measured): " << r.sourcesOutside << "; " << r.ms / 1000.0 << " s\n";
    }
    return r.passed() ? 0 : 2;
}

// How a check read the scene: whole, or by parts (io/scene_parts.h).
struct VectorsOptions {
    // "region": the scene read a square of at most partQuad metres at a time, within
    // vectorBudgetMiB; "whole": read into memory once. The same report.
    std::string vectors = "region";
    double partQuad = 5000.0;
    double vectorBudgetMiB = 2048.0;

    void add(CLI::App* cmd) {
        cmd->add_option("--vectors", vectors,
                        "region (default): the scene read a square of at most --part-quad metres at a time (memory follows the "
                        "part); whole: read into memory once. The same report")
            ->check(CLI::IsMember({"region", "whole"}));
        cmd->add_option("--part-quad", partQuad, "With --vectors region: the widest part read (m; 5000)")->check(CLI::PositiveNumber);
        cmd->add_option("--vector-budget", vectorBudgetMiB, "With --vectors region: MiB of vector data one part may hold (2048)")
            ->check(CLI::PositiveNumber);
    }
};

nlohmann::json partsJson(const ScenePartsRead& p) {
    return {{"reads", p.reads},
            {"part_level", p.level},
            {"largest_part_mib", toMiB(p.largestBytes)},
            {"read_ms", p.ms},
            {"whole_scene_no_feature_index", p.wholeScene}};
}

struct BridgesOptions {
    std::string scene;
    BridgeCheckParams params;
    double demBudgetMiB = DemStreamParams{}.budgetMiB;  // a streamed DEM's blocks held at once
    VectorsOptions read;
    bool json = false;
};

int runBridges(const BridgesOptions& o) {
    BridgeCheckReport r;
    std::optional<ScenePartsRead> parts;
    if (o.read.vectors == "whole") {
        const SceneDocument doc = loadScene(o.scene);
        if (!doc.dem) throw std::runtime_error(o.scene + ": the scene has no DEM: bridges cannot be checked against the terrain");
        r = checkBridges(doc.scene, *batchDemSource(doc, o.demBudgetMiB), o.params);
    } else {
        // Parts no smaller than the tiles compared (a tile holding a point is the part's).
        const Box extent = loadSceneExtent(o.scene);
        const double tile = extent.size().x / double(std::int64_t(1) << o.params.level);
        BridgeCheck check(o.params);
        parts = forEachScenePart(o.scene, std::max(o.read.partQuad, tile), o.read.vectorBudgetMiB, o.demBudgetMiB,
                                 [&](const SceneDocument& part, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
                                     check.add(part.scene, dem, owns);
                                 });
        r = check.finish();
    }
    const auto counter = [&](std::size_t v) { return r.graphCounters ? nlohmann::json(v) : nlohmann::json(nullptr); };
    nlohmann::json out = {
        {"scene", o.scene},
        {"level", o.params.level},
        {"bridges", r.bridges},
        {"imported_bridges", r.importedBridges},
        {"procedural_bridges", r.proceduralBridges},
        {"crossings", {{"found", counter(r.crossingsFound)}, {"imported_bridges_over_rivers", counter(r.flaggedRiverCrossings)},
                       {"unflagged_bridged", counter(r.bridgedCrossings)}, {"culverts", counter(r.culverts)}}},
        {"river_spans", r.riverSpans},
        {"clearance", {{"knob_m", o.params.graph.clearance}, {"deck_samples", r.deckSamples},
                       {"samples_below", r.deckSamplesBelowClearance},
                       {"least_m", r.deckSamples ? nlohmann::json(r.leastClearance) : nlohmann::json(nullptr)}}},
        {"river_bed", {{"points_under_decks", r.bedPoints}, {"points_differing", r.bedPointsDiffering},
                       {"largest_difference_m", r.largestBedDifference}, {"tiles", r.tilesCompared}}},
        {"vectors", o.read.vectors},
        {"ms", r.ms},
        {"passed", r.passed()}};
    if (parts) out["parts"] = partsJson(*parts);
    if (o.json) std::cout << out.dump(2) << "\n";
    else
        std::cout << r.bridges << " bridges (" << r.importedBridges << " imported, " << r.proceduralBridges << " made), " << r.riverSpans
                  << " river spans: deck clearance >= " << r.leastClearance << " m at " << r.deckSamples << " samples ("
                  << r.deckSamplesBelowClearance << " below " << o.params.graph.clearance << " m); river bed under the decks: "
                  << r.bedPoints << " points, " << r.bedPointsDiffering << " differ from the scene without the bridged roads (largest "
                  << r.largestBedDifference << " m)\n";
    if (r.riverSpans == 0) {
        std::cerr << o.scene << ": no bridge spans a river: nothing was checked\n";
        return 3;
    }
    return r.passed() ? 0 : 2;
}

struct RiversOptions {
    std::string scene;
    double demBudgetMiB = DemStreamParams{}.budgetMiB;  // a streamed DEM's blocks held at once
    VectorsOptions read;
    bool json = false;
};

nlohmann::json quantilesJson(const Quantiles& q, double over) {
    return {{"count", q.count}, {"p01_m", q.p01}, {"p05_m", q.p05}, {"median_m", q.median}, {"p95_m", q.p95}, {"p99_m", q.p99}, {"max_m", q.max}, {"min_m", q.min},
            {"fraction_over_" + std::to_string(int(over * 100.0)) + "_cm", q.fractionOver}};
}

int runRivers(const RiversOptions& o) {
    RiverCheckReport r;
    std::optional<ScenePartsRead> parts;
    if (o.read.vectors == "whole") {
        const SceneDocument doc = loadScene(o.scene);
        if (!doc.dem) throw std::runtime_error(o.scene + ": the scene has no DEM: rivers cannot be checked against the terrain");
        r = checkRivers(doc.scene, *batchDemSource(doc, o.demBudgetMiB));
    } else {
        RiverCheck check;
        parts = forEachScenePart(o.scene, o.read.partQuad, o.read.vectorBudgetMiB, o.demBudgetMiB,
                            [&](const SceneDocument& part, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
                                check.add(part.scene, dem, owns);
                            });
        r = check.finish();
    }
    nlohmann::json out = {{"scene", o.scene},
                          {"river_curves", r.curves},
                          {"profile_above_dem", quantilesJson(r.profileAboveDem, r.over)},
                          {"nodes_above_dem", quantilesJson(r.nodesAboveDem, r.over)},
                          {"rising_samples", r.risingSamples},
                          {"vectors", o.read.vectors},
                          {"ms", r.ms}};
    if (parts) out["parts"] = partsJson(*parts);
    if (o.json) std::cout << out.dump(2) << "\n";
    else
        std::cout << r.curves << " river curves: profile above the DEM median " << r.profileAboveDem.median << " m, p95 "
                  << r.profileAboveDem.p95 << " m, max " << r.profileAboveDem.max << " m over " << r.profileAboveDem.count
                  << " samples; nodes above the DEM max " << r.nodesAboveDem.max << " m; " << r.risingSamples << " rising samples\n";
    if (r.curves == 0) {
        std::cerr << o.scene << ": the scene has no river: nothing was checked\n";
        return 3;
    }
    return r.risingSamples == 0 ? 0 : 2;
}

struct HeightsOptions {
    std::string scene, pyramid;
    PyramidHeightCheckParams params;
    bool json = false;
};

int runHeights(const HeightsOptions& o) {
    const std::string path = o.pyramid.empty() ? defaultPyramidPath(o.scene) : o.pyramid;
    const PyramidHeightCheck c = checkPyramidHeights(o.scene, path, o.params);
    nlohmann::json out = c.json();
    out["scene"] = o.scene;
    out["pyramid"] = path;
    if (o.json) std::cout << out.dump(2) << "\n";
    else {
        std::cout << "level " << c.level << ": " << c.tilesChecked << " elevation tiles (" << c.cells << " cells) against "
                  << (c.streamed ? "the DEM tree's levels" : "the DEM in memory") << "; the quads need level " << c.neededLevel
                  << (c.neededLevel == c.demLevels - 1 ? " (the finest)" : "") << "\n";
        for (const HeightLevelMatch& l : c.levels)
            std::cout << "  DEM level " << l.demLevel << " (" << l.cellM << " m): " << l.cellsWithin << " cells within "
                      << c.toleranceM << " m, median " << l.medianM << " m, p90 " << l.p90M << " m; best for " << l.tilesBest
                      << " tiles\n";
        std::cout << "  " << c.tilesUndecided << " tiles undecided, " << c.tilesMissing << " missing\n";
    }
    if (c.tilesElsewhere() > 0)
        std::cerr << path << ": " << c.tilesElsewhere() << " elevation tile(s) of level " << c.level
                  << " agree best with another DEM level than the " << c.neededLevel << " their quads need\n";
    else if (!c.passed())
        std::cerr << path << ": no tile of level " << c.level << " told the DEM levels apart: nothing was proven\n";
    return c.passed() ? 0 : 2;
}

}  // namespace

void addCheckCommand(CLI::App& app) {
    CLI::App* check = app.add_subcommand("check", "Check invariants");
    check->require_subcommand(1);
    auto o = std::make_shared<CheckOptions>();
    CLI::App* inc = check->add_subcommand("incremental", "Incremental UPDATE equals a rebuild after every random edit");
    inc->add_option("--seed", o->seed, "Random seed (scene and edits)");
    inc->add_option("--curves", o->curves, "Target number of curves of the synthetic scene");
    inc->add_option("--edits", o->edits, "Number of random edits");
    inc->add_option("--depth", o->depth, "Deepest quadtree level around the random viewpoints");
    inc->add_option("--view-every", o->viewEvery, "Move the viewer every this many edits");
    inc->add_option("--sample", o->sample,
                    "Quads compared after each edit, drawn at random and each rebuilt alone along its path (0: every quad, the whole "
                    "tree rebuilt; the default)");
    inc->add_option("--full-every", o->fullEvery, "With --sample: every quad compared every this many edits (0: never)")
        ->check(CLI::Range(0, 1 << 30));
    inc->add_option("--undo", o->undoChance,
                    "Undo each edit with this probability after its comparison, then redo half of those, each compared too "
                    "(0 to 1; 0: none, the default)")
        ->check(CLI::Range(0.0, 1.0));
    inc->add_flag("--json", o->json, "Print JSON");
    inc->add_flag("--lazy", o->lazy, "Edits of the scene read lazily (saved into a temporary file) against edits of the whole scene, tile for tile");
    inc->add_option("--vector-budget", o->vectorBudgetMiB, "With --lazy: MiB of vector data the lazy session holds");
    inc->add_option("--save-every", o->saveEvery,
                    "With --lazy: save the lazy edits into the file every this many edits and when all is undone, the file then "
                    "summing to the whole scene (0: never)");
    inc->add_option("--part-level", o->partLevel, "With --lazy: the level of the quads read as one part (-1: quads of at most 5 km)");
    inc->callback([o] {
        if (const int rc = o->lazy ? runLazy(*o) : run(*o); rc != 0) throw CLI::RuntimeError(rc);
    });

    auto b = std::make_shared<BridgesOptions>();
    CLI::App* bridges = check->add_subcommand(
        "bridges", "Under every bridge the river bed is as without the bridged road, and every deck clears the water");
    bridges->add_option("scene", b->scene, "Scene file (from lacet import or the editor)")->required();
    bridges->add_option("--level", b->params.level, "Quadtree level of the elevation tiles compared")->check(CLI::Range(0, 20));
    bridges->add_option("--step", b->params.step, "Metres between the points sampled along a deck")->check(CLI::Range(0.05, 100.0));
    bridges->add_option("--dem-budget", b->demBudgetMiB, "MiB of a streamed DEM's blocks held at once (a scene with a DEM LOD tree)");
    b->read.add(bridges);
    bridges->add_flag("--json", b->json, "Print JSON");
    bridges->callback([b] {
        if (const int rc = runBridges(*b); rc != 0) throw CLI::RuntimeError(rc);
    });

    auto rv = std::make_shared<RiversOptions>();
    CLI::App* rivers = check->add_subcommand("rivers", "River profiles and node heights against the DEM, and whether a river rises");
    rivers->add_option("scene", rv->scene, "Scene file (from lacet import or the editor)")->required();
    rivers->add_option("--dem-budget", rv->demBudgetMiB, "MiB of a streamed DEM's blocks held at once (a scene with a DEM LOD tree)");
    rv->read.add(rivers);
    rivers->add_flag("--json", rv->json, "Print JSON");
    rivers->callback([rv] {
        if (const int rc = runRivers(*rv); rc != 0) throw CLI::RuntimeError(rc);
    });

    auto h = std::make_shared<HeightsOptions>();
    CLI::App* heights = check->add_subcommand(
        "heights", "A pyramid's elevation tiles were made from the DEM level their quads need (the finest for deep quads)");
    heights->add_option("scene", h->scene, "Scene file the pyramid was built from")->required();
    heights->add_option("--pyramid", h->pyramid, "Pyramid file (default: SCENE.pyramid.gpkg)");
    heights->add_option("--level", h->params.level, "Pyramid level checked (default: its deepest)")->check(CLI::Range(0, 30));
    heights->add_option("--tiles", h->params.tiles, "Tiles of the level checked, spread evenly (64)")->check(CLI::Range(1, kMaxHeightCheckTiles));
    heights->add_option("--tolerance", h->params.toleranceM, "A cell agrees with a DEM level within this (m; 0.001)")
        ->check(CLI::Range(1e-9, 1000.0));
    heights->add_option("--dem-budget", h->params.demBudgetMiB, "MiB of a streamed DEM's blocks held at once")
        ->check(CLI::PositiveNumber);
    heights->add_flag("--json", h->json, "Print JSON");
    heights->callback([h] {
        if (const int rc = runHeights(*h); rc != 0) throw CLI::RuntimeError(rc);
    });

    auto f = std::make_shared<FitOptions>();
    CLI::App* fit = check->add_subcommand("fit", "Hausdorff distance between a scene's curves and their GIS sources, per layer");
    fit->add_option("scene", f->scene, "Scene file (from lacet import)")->required();
    fit->add_option("--source", f->sources, "The vector files it was imported from")->required();
    fit->add_option("--mapping", f->mapping, "The mapping file of the import (default: the OSM mapping)");
    fit->add_option("--tolerance", f->params.tolerance, "Fit tolerance to check against (m)")->check(CLI::Range(0.0, kMaxFitTolerance));
    fit->add_option("--precision", f->params.precision, "Precision of the measure (m)")->check(CLI::Range(1e-6, 10.0));
    fit->add_flag("--json", f->json, "Print JSON");
    fit->callback([f] {
        if (const int rc = runFit(*f); rc != 0) throw CLI::RuntimeError(rc);
    });
}

}  // namespace lacet::app
