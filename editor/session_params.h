#pragma once
// The knobs of an editing session (editor/edit_session.h) and of its live loop
// (editor/tile_loop.h), each with its unit: the refinement and view, the tile cache, the frame's
// budgets and the clock they are read on, the producers', the graph step's, the objects', the
// z-profiles' and a streamed DEM's.

#include <cstddef>

#include "editor/draw_plan.h"
#include "io/dem_stream.h"
#include "model/clip_and_refine.h"
#include "model/curve_data.h"
#include "model/graph_step.h"
#include "model/view_params.h"
#include "model/work_clock.h"
#include "raster/appearance_producer.h"
#include "raster/elevation_producer.h"
#include "raster/object_meshes.h"

namespace lacet {

// SessionParams::backgroundMs of the interactive editor and of the benchmarks that measure it
// (ms). On the paper's flight (lacet bench flyover, 60 frames a second, 2 cores) 1 ms left a
// tenth of the paper's 10 ms budget to each tile in the frames and gave the lowest mean and
// p99.8 of 0, 1 and 4 ms; the frames keep making the many small tiles, so the view still
// progresses when the machine has no idle time for the background threads.
inline constexpr double kInteractiveBackgroundMs = 1.0;

struct SessionParams {
    RefineParams refine;
    ViewParams view;  // the K rule (§8) and the deepest level
    // Tile pairs (appearance + elevation) the cache holds: the quads shown and their ancestors'
    // (editor/cache_fit.h). The paper's caches held 784 elevation and 500 appearance textures for
    // views that needed up to 708 and 482; on its flight our views need up to about 1,120 pairs
    // (frustum of 1280 x 800 at 52 degrees), which 1,200 holds; `lacet bench flyover` also flies
    // with 784, where the farthest quads stand in for their children.
    std::size_t cacheTiles = 1200;
    // Time a frame may spend subdividing (ms; 0: unlimited): past it, subdivisions wait for the
    // next frames, nearest first, and the leaves stay coarser meanwhile.
    double refineBudgetMs = 0.0;
    // With a frame budget: a quad whose tiles are estimated (editor/production_estimate.h) to take
    // longer than this (ms) is made on a background thread, one quad a thread, over as many frames
    // as it takes, its nearest ancestor's tile shown meanwhile (editor/tile_loop.h): a coarse quad
    // of thousands of elements no longer stalls a frame. 0: every tile made within the frames (the
    // order of what is made does not depend on threads: tests). The editor and the benchmarks use
    // kInteractiveBackgroundMs.
    double backgroundMs = 0.0;
    // Quads whose tiles are made in the background at once, each on a thread of its own (0: as
    // many as the machine has cores; at idle priority they take only what the frames leave).
    std::size_t backgroundThreads = 0;
    // The clock the frame's budgets (production and refinement) are read on: the machine's, or a
    // stepped one (model/work_clock.h) so that what a budget lets through does not depend on the
    // machine's speed (tests, scripts). The commands' reported times are always the machine's.
    WorkClock clock = realClock();
    AppearanceParams appearance;
    ElevationParams elevation;
    SkirtParams skirt;  // how far the draw plan's skirts hang (editor/draw_plan.h)
    GraphStepParams graph;     // bridges and roundabouts (model/graph_step.h)
    // Bridges' and trees' meshes (raster/object_meshes.h), made with each elevation tile; its
    // deckThickness is taken from `graph` (the deck the z-profiles make room for).
    ObjectParams objects;
    ZProfileParams profiles;   // z-profiles (model/curve_data.h)
    // A streamed DEM (the document's demLod, io/dem_stream.h): the memory budget, and the DEM
    // samples a quad's tiles need across its side (the level each window is cut from: the
    // coarsest whose spacing is at most the quad's size over this; io/dem_stream.h: quadDemNeed).
    DemStreamParams demStream;
    double demSamplesPerQuad = kDemSamplesPerQuad;
};

}  // namespace lacet
