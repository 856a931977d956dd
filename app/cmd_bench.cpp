// `lacet bench update|accuracy|producers|texture-accuracy|edit|flyover|pyramid`: benchmark tasks printing their figures as JSON.
#include <iostream>

#include "app/commands.h"
#include "bench/tasks.h"

namespace lacet::app {

void addBenchCommand(CLI::App& app) {
    CLI::App* bench = app.add_subcommand("bench", "Benchmarks printing JSON figures");
    bench->require_subcommand(1);

    struct UpdateOptions {
        std::vector<std::size_t> curves{10000, 100000, 600000};
        std::uint64_t seed = 1;
        int moves = 60;
        double altitude = 10.0;
        bool json = true;
    };
    auto u = std::make_shared<UpdateOptions>();
    CLI::App* update = bench->add_subcommand("update", "UPDATE time of one control-point move against scene size");
    update->add_option("--curves", u->curves, "Curve counts (same density; the first and last give the ratio)")->delimiter(',');
    update->add_option("--seed", u->seed, "Random seed");
    update->add_option("--moves", u->moves, "Control-point moves measured per scene");
    update->add_option("--altitude", u->altitude, "Viewer height above the moved point (m)");
    update->add_flag("--json", u->json, "Print JSON (the only format)");
    update->callback([u] { std::cout << bench::benchUpdate(u->curves, u->seed, u->moves, u->altitude).dump(2) << "\n"; });

    struct AccuracyOptions {
        std::vector<double> tolerances{0.125, 0.25, 0.5, 1.0, 2.0, 4.0};
        std::size_t curves = 10000;
        std::uint64_t seed = 1;
        bool json = true;
    };
    auto a = std::make_shared<AccuracyOptions>();
    CLI::App* accuracy = bench->add_subcommand("accuracy", "Refinement tolerance: time, vertices, error left");
    accuracy->add_option("--tolerances", a->tolerances, "Tolerances in texels")->delimiter(',');
    accuracy->add_option("--curves", a->curves, "Curves of the synthetic scene");
    accuracy->add_option("--seed", a->seed, "Random seed");
    accuracy->add_flag("--json", a->json, "Print JSON (the only format)");
    accuracy->callback([a] { std::cout << bench::benchAccuracy(a->tolerances, a->curves, a->seed).dump(2) << "\n"; });

    auto p = std::make_shared<bench::ProducerBenchOptions>();
    auto pJson = std::make_shared<bool>(true);
    CLI::App* producers = bench->add_subcommand("producers", "Time per quad of the appearance and elevation producers; 2 threads against 1");
    producers->add_option("--scene", p->scene, "Scene file (lacet import) instead of the synthetic scene");
    producers->add_option("--curves", p->curves, "Curves of the synthetic scene (600000: the paper's scale)");
    producers->add_option("--seed", p->seed, "Random seed");
    producers->add_option("--dem-resolution", p->demResolution, "DEM samples per 100 km");
    producers->add_option("--views", p->views, "Views above random roads");
    producers->add_option("--altitude", p->altitude, "Viewer height above the road (m)");
    producers->add_option("--max-level", p->view.maxLevel, "Deepest quadtree level");
    producers->add_option("--deep-level", p->deepLevel, "Quads of this level and deeper make the headline figures");
    producers->add_flag("--json", *pJson, "Print JSON (the only format)");
    producers->callback([p, pJson] { std::cout << bench::benchProducers(*p).dump(2) << "\n"; });

    auto e = std::make_shared<bench::EditBenchOptions>();
    auto eJson = std::make_shared<bool>(true);
    CLI::App* edit = bench->add_subcommand("edit", "Edit latency of the window-less session: a road control point and a field corner dragged");
    edit->add_option("--curves", e->curves, "Curves of the synthetic scene (600000: the paper's scale)");
    edit->add_option("--seed", e->seed, "Random seed");
    edit->add_option("--dem-resolution", e->demResolution, "DEM samples per 100 km");
    edit->add_option("--altitude", e->altitude, "Viewer height above the dragged point (m)");
    edit->add_option("--steps", e->steps, "Steps of each drag");
    edit->add_option("--repeats", e->repeats, "Drags of each kind (undone after each), their steps pooled");
    edit->add_flag("!--no-objects", e->objects, "Make no object meshes (bridges' decks, trees), to see what they cost");
    edit->add_option("--scene", e->scene, "A scene file read lazily (with --vector-budget) instead of the synthetic scene");
    edit->add_option("--vector-budget", e->vectorBudgetMiB, "With --scene: MiB of vector data held (editor/lazy_forest.h)");
    edit->add_option("--part-level", e->partLevel, "With --scene: the level of the quads read as one part (-1: at most 5 km wide)");
    edit->add_flag("--save", e->save,
                   "With --scene: a drag kept and saved into the file, then undone and saved again (the file's content as it was): "
                   "the save's cost");
    edit->add_option("--pyramid", e->pyramid, "With --scene: its pyramid (the levels above the parts read from it)");
    edit->add_flag("--json", *eJson, "Print JSON (the only format)");
    edit->callback([e, eJson] { std::cout << bench::benchEdit(*e).dump(2) << "\n"; });

    auto fo = std::make_shared<bench::FlyoverBenchOptions>();
    auto foJson = std::make_shared<bool>(true);
    CLI::App* flyover = bench->add_subcommand("flyover", "A flight from 5000 m down to a road through the window-less session");
    flyover->add_option("--curves", fo->curves, "Curves of the synthetic scene (600000: the paper's scale)");
    flyover->add_option("--seed", fo->seed, "Random seed");
    flyover->add_option("--frames", fo->frames, "Frames of the flight");
    flyover->add_option("--runs", fo->runs, "Only these runs: plain, prefetch, refine-budget, cache-784, no-culling, pyramid")
        ->delimiter(',')
        ->check(CLI::IsMember({"plain", "prefetch", "refine-budget", "cache-784", "no-culling", "pyramid"}));
    flyover->add_option("--fps", fo->fps, "Frames a second the flight is paced at, as a window's (0: unpaced, with --background-ms 0)")->check(CLI::NonNegativeNumber);
    flyover->add_option("--k", fo->K, "The subdivision factor K of the flight (§8; quads closer than K times their size are subdivided)")
        ->check(CLI::PositiveNumber);
    flyover->add_option("--budgets", fo->budgetsMs, "Production budgets per frame (ms; 0: no budget)")->delimiter(',');
    flyover->add_option("--prefetch-frames", fo->prefetchFrames, "How far ahead (frames) the prefetching viewer is");
    flyover->add_option("--pyramid", fo->pyramid,
                        "Fly each budget without and with this pyramid of the synthetic scene ('auto': build one into a temporary file)");
    flyover->add_option("--pyramid-quad", fo->pyramidQuadM, "With --pyramid auto: the side (m) of the deepest level's quads, made from vector data")
        ->check(CLI::PositiveNumber);
    flyover->add_option("--scene", fo->scene, "A scene file to fly over instead of the synthetic scene (its DEM streamed when it is a LOD tree)");
    flyover->add_option("--dem-budget", fo->demBudgetMiB, "Memory of a streamed DEM's blocks (MiB)")->check(CLI::PositiveNumber);
    flyover->add_option("--dem-profile-spacing", fo->demProfileSpacingM,
                        "The streamed DEM level the z-profiles read: the coarsest with samples at most this far apart (m)")
        ->check(CLI::PositiveNumber);
    flyover->add_flag("--profile-error", fo->profileError,
                      "With a streamed DEM: the z-profiles near the path from --dem-profile-spacing's level against the finest (m)");
    flyover->add_option("--background-ms", fo->backgroundMs,
                        "Quads whose tiles are estimated to take longer (ms) are made on a background thread (0: in the frames)")
        ->check(CLI::NonNegativeNumber);
    flyover->add_option("--adaptive", fo->adaptiveTargetMs, "Adapt K to this update time per frame (ms; 0: K fixed)")->check(CLI::NonNegativeNumber);
    flyover->add_option("--vector-budget", fo->vectorBudgetMiB,
                        "With --scene: read its vector data lazily within this many MiB (0: load it whole)")->check(CLI::NonNegativeNumber);
    flyover->add_option("--part-level", fo->partLevel, "With --vector-budget: the level of the quads read as one part (-1: from --part-quad)");
    flyover->add_option("--part-quad", fo->partQuadM, "With --vector-budget: the widest part quad (m), when --part-level is -1")
        ->check(CLI::PositiveNumber);
    flyover->add_flag("--json", *foJson, "Print JSON (the only format)");
    flyover->callback([fo, foJson] { std::cout << bench::benchFlyover(*fo).dump(2) << "\n"; });

    struct TextureAccuracyOptions {
        std::size_t curves = 10000;
        std::uint64_t seed = 1;
        int views = 2;
        bool json = true;
    };
    auto ta = std::make_shared<TextureAccuracyOptions>();
    CLI::App* texture = bench->add_subcommand("texture-accuracy", "Producer accuracy knobs: time and error left");
    texture->add_option("--curves", ta->curves, "Curves of the synthetic scene");
    texture->add_option("--seed", ta->seed, "Random seed");
    texture->add_option("--views", ta->views, "Views above roads whose quads are measured");
    texture->add_flag("--json", ta->json, "Print JSON (the only format)");
    texture->callback([ta] { std::cout << bench::benchTextureAccuracy(ta->curves, ta->seed, ta->views).dump(2) << "\n"; });

    auto po = std::make_shared<bench::PyramidBenchOptions>();
    auto pjson = std::make_shared<bool>(true);
    CLI::App* pyramid = bench->add_subcommand("pyramid", "A scene's pyramid build: threads, encodings, mipmap error");
    pyramid->add_option("--scene", po->scene, "Scene file")->required();
    pyramid->add_option("--min-level", po->minLevel, "First level");
    pyramid->add_option("--max-level", po->maxLevel, "Last level");
    pyramid->add_option("--encoding", po->encoding, "Encoding of the thread runs");
    pyramid->add_option("--threads", po->threads, "Thread counts, e.g. 1,2")->delimiter(',');
    pyramid->add_option("--encodings", po->encodings, "Encodings to compare, e.g. png:1,jpeg:90,webp:90")->delimiter(',');
    pyramid->add_flag("--mip-error", po->mipError, "Also the error of mipmapped levels against levels made from vector data");
    pyramid->add_option("--vector-levels", po->vectorLevels,
                        "With --mip-error: the counts of deepest levels made from vector data compared, e.g. 1,2,3 (default 1)")
        ->delimiter(',');
    pyramid->add_flag("--edit-road", po->editRoad, "Also: one road moved 20 m, pyramid update against a rebuild (tiles remade, equality)");
    pyramid->add_flag("--json", *pjson, "Print JSON (the only format)");
    pyramid->callback([po] { std::cout << bench::benchPyramid(*po).dump(2) << "\n"; });
}

}  // namespace lacet::app
