#pragma once
// Benchmark tasks behind `lacet bench ...`: each runs and returns its figures as JSON.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/lazy_forest.h"
#include "editor/session_params.h"
#include "io/dem_stream.h"
#include "model/view_params.h"

namespace lacet::bench {

// UPDATE cost against scene size (§6): for each curve count, a synthetic scene at the paper's
// density, a quadtree refined for a viewer `altitude` metres above a road (ViewParams{}), and `moves`
// moves of one control point of that road. Reports the median UPDATE time, a rebuild's time, and
// clip-and-refine time per quad by depth.
nlohmann::json benchUpdate(const std::vector<std::size_t>& curves, std::uint64_t seed, int moves, double altitude);

// Refinement tolerance against time, vertices and the error left (max distance between the drawn
// polyline and the exact curve, by dense sampling), for tolerances in texels.
nlohmann::json benchAccuracy(const std::vector<double>& tolerancesTexels, std::size_t curves, std::uint64_t seed);

// Producer speed (§8): per-quad time of the appearance (256 x 256) and elevation (25 x 25)
// producers, one thread, at the deepest levels of `views` views `altitude` metres above roads
// (K as in the paper), cold (curve data computed on demand) and warm; and the throughput of two
// threads against one over the same quads.
struct ProducerBenchOptions {
    std::string scene;         // a scene file (lacet import) instead of the synthetic scene
    std::size_t curves = 600000;
    std::uint64_t seed = 1;
    int demResolution = 5000;  // DEM samples per 100 km (the paper: 5000 x 5000 over 100 km)
    int views = 8;
    double altitude = 5.0;     // metres above the road
    ViewParams view{.maxLevel = 16};
    int minLevel = 8;          // quads timed
    int deepLevel = 12;        // "deepest levels": quads of this level and deeper
};
nlohmann::json benchProducers(const ProducerBenchOptions& options);

// The producers' accuracy knobs: anti-aliasing samples and appearance resolution (time per
// tile, PSNR against a high-accuracy reference), z-profile sample spacing (time, max z_m error
// against 0.5 m) and kernel radius (time, how far roads depart from the DEM).
nlohmann::json benchTextureAccuracy(std::size_t curves, std::uint64_t seed, int views);

// Edit latency of the window-less editing session: a road control point and then a field corner
// dragged in `steps` steps in a fixed view `altitude` m above the road, `repeats` times each
// (undone in between); per step, the time from the command to every dirty tile of the view made
// again, and the tiles made.
struct EditBenchOptions {
    std::size_t curves = 600000;
    std::uint64_t seed = 1;
    int demResolution = 5000;
    double altitude = 10.0;
    int steps = 60;
    int repeats = 3;  // drags of each kind, their steps pooled
    bool objects = true;  // false: no object meshes (bridges' decks, trees), to see what they cost
    // A scene file read lazily within `vectorBudgetMiB` (parts of `partLevel`, -1: at most 5 km
    // wide), with the `pyramid` of it (empty: none), instead of the synthetic scene.
    std::string scene, pyramid;
    double vectorBudgetMiB = 0.0;
    int partLevel = -1;
    // With `scene`: a drag kept and its edits saved into the file, then undone and saved again (the
    // file's content as before; io/scene_save_edits.h): what a save costs.
    bool save = false;
};
nlohmann::json benchEdit(const EditBenchOptions& options);

// A flight from `startAltitude` down to `endAltitude` above a road (§9.1) through the session:
// update time per frame (mean, median, p99.8), tiles made per frame and the cache peak, for each
// per-frame production budget (0: every tile of the view each frame), without and with
// prefetching, and with half the budget for subdivisions (the rest deferred to later frames).
struct FlyoverBenchOptions {
    std::size_t curves = 600000;
    std::uint64_t seed = 1;
    int demResolution = 5000;
    int frames = 4381;  // 73 s at 60 frames per second, as in the paper
    // Frames a second the flight is paced at (a frame begins no sooner than 1/fps after the one
    // before, as a window's would: the background threads run between frames); 0: unpaced, each
    // frame right after the last (what a frame's own work costs, when no work is left to a thread:
    // with backgroundMs 0 only).
    double fps = 60.0;
    double K = ViewParams{}.K;  // the subdivision factor of the flight (§8), > 0
    // The runs flown (FlyoverBench's names: plain, prefetch, refine-budget, cache-784, no-culling,
    // pyramid); empty: all that apply.
    std::vector<std::string> runs;
    double startAltitude = 5000.0, endAltitude = 5.0;
    std::vector<double> budgetsMs{0.0, 10.0};
    int prefetchFrames = 25;  // how far ahead the predicted viewer is, in frames (the paper: 25)
    // With a pyramid (§7; issue 15): each budget flown without and with it, no other runs. A file
    // of this synthetic scene (lacet pyramid build), or "auto": built into a temporary file, its
    // deepest level the first whose quads are `pyramidQuadM` or smaller, made from vector data
    // (L = that level: the editor reads the levels above it).
    std::string pyramid;
    double pyramidQuadM = 2000.0;  // m, > 0
    // A scene file to fly over instead of the synthetic scene (issue 16): with a streamed DEM
    // (a scene whose DEM is a LOD tree, io/dem_lod.h) the session streams it within
    // `demBudgetMiB`, and each budget is flown once, nothing else.
    std::string scene;
    double demBudgetMiB = 512.0;
    double demProfileSpacingM = DemStreamParams{}.profileSpacing;  // the DEM level the z-profiles read (m)
    // After the flight over a streamed DEM: the z-profiles of the road and river curves near the
    // path made from that level against the same made from the finest level (metres).
    bool profileError = false;
    // Frame-rate-adaptive K (editor/adaptive_quality.h) aiming at this update time per frame (ms;
    // 0: K fixed).
    double adaptiveTargetMs = 0.0;
    // SessionParams::backgroundMs: slow quads' tiles made on a background thread (0: in the frames).
    double backgroundMs = kInteractiveBackgroundMs;
    // With `scene`: its vector data read lazily (editor/lazy_forest.h) within this many MiB (0: the
    // scene loaded whole), each part a quad of `partLevel` (-1: the first level of quads at most
    // `partQuadM` wide). With a pyramid file, the levels down to the part level read only what
    // elevation needs (their appearance is the pyramid's: its L must be deeper than the parts').
    double vectorBudgetMiB = 0.0;
    int partLevel = -1;
    double partQuadM = LazyParams{}.partQuadM;
};
nlohmann::json benchFlyover(const FlyoverBenchOptions& options);

// `lacet bench pyramid`: a scene's pyramid (pyramid/pyramid_build.h) built on each thread count
// (wall time, tiles a second, thread seconds by stage), with each encoding (time, bytes), and the
// error the mipmapped levels leave against the same levels made from vector data; with editRoad,
// the tiles an update remakes after one road's edit and its equality with a rebuild.
struct PyramidBenchOptions {
    std::string scene;
    int minLevel = 0, maxLevel = 7;
    std::string encoding = "jpeg:90";
    std::vector<int> threads{1, 2};
    std::vector<std::string> encodings;
    bool mipError = false;
    std::vector<int> vectorLevels;  // with mipError: the counts of levels made from vector data compared (empty: 1)
    bool editRoad = false;  // one road moved, then update against a rebuild
};
nlohmann::json benchPyramid(const PyramidBenchOptions& options);

}  // namespace lacet::bench
