// `lacet check incremental`: random edits on a synthetic scene; after each, the incrementally
// updated quadtree is compared with a rebuild from scratch. Exits non-zero on any mismatch.
#include <iostream>
#include <map>
#include <random>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "bench/bench_util.h"
#include "model/quadtree_compare.h"
#include "model/random_edits.h"
#include "model/synthetic_scene.h"
#include "model/validate.h"

namespace lacet::app {
namespace {

struct CheckOptions {
    std::uint64_t seed = 1;
    std::size_t curves = 10000;
    int edits = 100;
    int depth = 12;
    int viewEvery = 10;
    bool json = false;
};

int run(const CheckOptions& o) {
    using namespace lacet::bench;
    Scene s = makeSyntheticScene({o.seed, o.curves});
    std::mt19937_64 rng(o.seed * 7919 + 1);
    const double side = s.extent.size().x;
    auto viewer = [&] {
        return glm::dvec3(s.extent.min.x + uniform01(rng) * side, s.extent.min.y + uniform01(rng) * side,
                          2.0 + uniform01(rng) * 50.0);
    };
    Quadtree qt(s);
    qt.refineForViewer(viewer(), 2.8, o.depth);
    std::size_t applied = 0, mismatches = 0, quadsCompared = 0;
    std::map<std::string, std::size_t> byKind;
    std::vector<std::string> details;
    std::vector<double> updateMs, rebuildMs;
    for (int i = 0; i < o.edits; ++i) {
        if (i % o.viewEvery == o.viewEvery - 1) qt.refineForViewer(viewer(), 2.8, o.depth);
        const RandomEdit e = applyRandomEdit(s, rng, side * 0.01);
        if (e.changeset.empty()) continue;
        ++applied;
        ++byKind[std::string(toString(e.kind))];
        auto t0 = Clock::now();
        qt.update(e.changeset);
        updateMs.push_back(msSince(t0));
        t0 = Clock::now();
        Quadtree rebuilt(s);
        rebuilt.copyStructureOf(qt);
        rebuildMs.push_back(msSince(t0));
        const QuadtreeDiff diff = compareQuadtrees(qt, rebuilt, 5);
        quadsCompared += diff.quadsCompared;
        mismatches += diff.mismatches;
        for (const auto& d : diff.details)
            if (details.size() < 20) details.push_back("edit " + std::to_string(i) + " (" + std::string(toString(e.kind)) + "): " + d);
    }
    const bool valid = validate(s).empty();
    const nlohmann::json out = {{"seed", o.seed},
                                {"curves", count(s).curves},
                                {"depth", o.depth},
                                {"edits", applied},
                                {"edits_by_kind", byKind},
                                {"quads_compared", quadsCompared},
                                {"mismatches", mismatches},
                                {"mismatch_details", details},
                                {"scene_valid", valid},
                                {"update_median_ms", median(updateMs)},
                                {"rebuild_median_ms", median(rebuildMs)}};
    if (o.json) std::cout << out.dump(2) << "\n";
    else
        std::cout << applied << " edits, " << quadsCompared << " quad comparisons, " << mismatches << " mismatches\n";
    return mismatches == 0 && valid ? 0 : 2;
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
    inc->add_flag("--json", o->json, "Print JSON");
    inc->callback([o] {
        if (const int rc = run(*o); rc != 0) throw CLI::RuntimeError(rc);
    });
}

}  // namespace lacet::app
