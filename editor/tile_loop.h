#pragma once
// The live loop's tiles (§8; issue: the 3D editor): what EditSession::frame() does each frame
// for a quadtree and its curve data. It refines the tree for the viewer, chooses the quads shown
// within the cache (editor/cache_fit.h, §9.1), makes their missing and dirty tiles nearest first
// on TBB worker threads until the frame's budget is spent, then those of a predicted viewer
// (prefetching), evicts, and plans what is drawn (editor/draw_plan.h). The editing session
// (editor/edit_session.h) owns one, tells it which quads each edit changed, and passes its
// figures on; this is the one home of the cache and of what is loaded for the view.
//
// Tiles: one appearance and one elevation tile per quad (the latter with the quad's object meshes,
// §5.3: made in the same job, dirty and remade with it), cached by (level, x, y) with an LRU
// bound (`cacheTiles`); tiles of the current view, of their ancestors (shown while a leaf is
// made) and those made ahead for a predicted viewer that still wants them are not evicted. When
// the view's leaves and their ancestors are more than the cache holds, the farthest quads are
// shown instead of their children, so the cache never exceeds its bound. A tile is dirty when
// its quad's graph changed, or when it used a z-profile that an edit dropped (a river downstream
// of the edit); a dirty tile that the frame neither shows nor keeps as an ancestor's is dropped.
//
// The pyramid (§7, Fig. 10; pyramid/pyramid_reader.h): with one set, the appearance of a quad of
// a level below the pyramid's first vector level L is read from it instead of produced; a quad
// whose appearance an edit changed since the pyramid was made is produced live from then on (the
// loop records, per edit, the quads below L that changed, those holding a curve whose z-profile
// was dropped, the root, and for such a quad that is a leaf every quad below it). A tile the
// pyramid cannot give is produced live and counted. While a layer is hidden the pyramid (made
// with every layer) is not read.
//
// A streamed DEM (io/dem_stream.h): each quad's tiles read its window at the level it needs
// (tile_loop_dem.cpp); a shown tile made from a coarser level than it wanted is remade when
// the finer blocks arrive.
//
// Background tiles (tile_loop_background.cpp; SessionParams::backgroundMs, issue 24: no slow
// frame): with a frame budget, a quad whose tiles are estimated to take longer than the knob (a
// coarse quad of thousands of elements) is not made in the frame but on a background thread, one
// quad a thread (SessionParams::backgroundThreads), over as many frames as it takes; its nearest
// ancestor's tile is shown meanwhile and the frame that finds it done takes it into the cache. The
// thread reads the quad, its tree and curve data while frames go on: what could change them stops
// it first (quiesce(): an edit, a new tree, a layer shown or hidden; before a refinement that would
// merge the quad away, QuadForest::keeps), the producers checking its cancel flag between elements,
// so an edit waits for no tile; a quad whose vector data arrived since it began (a lazy part) is
// made again.
//
// Order of calls: setTree() (again after each new tree: it drops every tile), then frame() each
// frame and edited() after each edit's UPDATE.

#include <chrono>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "editor/background_subdivision.h"
#include "editor/background_work.h"
#include "editor/cache_fit.h"
#include "editor/draw_plan.h"
#include "editor/production_estimate.h"
#include "editor/quad_forest.h"
#include "editor/session_params.h"
#include "io/dem_stream.h"
#include "model/curve_data.h"
#include "model/quadtree.h"
#include "pyramid/pyramid_reader.h"
#include "raster/dem.h"
#include "raster/object_meshes.h"
#include "model/cancel.h"

namespace lacet {

struct FrameReport {
    std::size_t viewQuads = 0;       // leaves of the view-refined tree
    std::size_t produced = 0;        // tiles made this frame
    std::size_t pending = 0;         // view tiles still missing or dirty after the frame
    std::size_t cached = 0;
    std::size_t culled = 0;          // leaves outside the view (not produced)
    std::size_t prefetched = 0;      // tiles made for the predicted viewer
    std::size_t replaced = 0;        // view leaves shown with an ancestor's tile: the cache holds no more (§9.1)
    std::size_t shown = 0;           // quads shown: the view leaves, or ancestors in place of some
    std::size_t kept = 0;            // cached tiles the LRU may not evict: shown, their ancestors, made ahead
    bool refineDeferred = false;     // the refine budget left subdivisions for later frames
    double refineMs = 0.0, produceMs = 0.0;
    std::size_t fromPyramid = 0;     // appearance tiles read from the pyramid (of `produced` and `prefetched`)
    std::size_t pyramidFailed = 0;   // tiles the pyramid could not give (corrupt, missing, locked), made live
    std::size_t demFallbacks = 0;    // tiles made this frame from a coarser DEM block than they want (streamed DEM)
    std::size_t demRemade = 0;       // shown tiles marked dirty because the finer DEM blocks they wanted arrived
    std::size_t partsArrived = 0;    // tiles marked dirty because their quad's part arrived (editor/lazy_forest.h)
    // Background tiles (SessionParams::backgroundMs): a quad's tiles begun on the background
    // thread this frame, taken into the cache, and dropped (stopped, or done but stale).
    std::size_t backgroundStarted = 0, backgroundTaken = 0, backgroundDropped = 0;
    // Subdivisions begun on the background thread this frame (editor/background_subdivision.h;
    // dropped ones are counted in backgroundDropped).
    std::size_t backgroundSubdivisions = 0;
};

// What the pyramid saved the session so far (appearance tiles).
struct PyramidUse {
    std::size_t read = 0;     // read from the pyramid
    std::size_t failed = 0;   // the pyramid could not give them (corrupt, missing, locked): made live
    std::size_t touched = 0;  // below L but changed by an edit since the pyramid was made: made live
    std::size_t live = 0;     // made live in all (failed and touched included)
};

using QuadVisibility = std::function<bool(const Quad&)>;

class TileLoop {
public:
    // `params` (the session's, read at each call: K, the budgets and the hidden layers change
    // between frames), `scene`, `dem` (the DEM in memory; with a streamed one, its coarse level)
    // and `stream` (the streamed DEM; nullptr: none) must outlive the loop.
    TileLoop(const SessionParams& params, const Scene& scene, const Dem& dem, DemStream* stream);
    ~TileLoop();  // stops the background tiles (quiesce)
    TileLoop(const TileLoop&) = delete;
    TileLoop& operator=(const TileLoop&) = delete;

    // The tree and curve data the tiles are made from (both must outlive their use); drops every
    // tile and the plan.
    void setTree(Quadtree& tree, const CurveDataCache& data);
    // The same for a forest (editor/quad_forest.h: a scene read lazily), which must outlive its use.
    void setForest(QuadForest& forest);

    // See EditSession::frame().
    FrameReport frame(glm::dvec3 viewer, double budgetMs, const QuadVisibility& visible, std::optional<glm::dvec3> predicted);

    // After an edit (`edited`: a command, an undo or a redo that changed the scene) and its
    // UPDATE: marks dirty the tiles of the `changed` quads, of quads no longer in the tree and of
    // those holding a curve whose z-profile was `dropped`; records the touched quads below the
    // pyramid's L. Returns how many tiles became dirty.
    std::size_t edited(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped, bool edited);
    // After an edit of a scene read lazily (editor/lazy_forest.h): marks dirty the tiles of the
    // `changed` quads and of quads not in the forest now; records the `touched` quads and every
    // quad below them as touched (their appearance no longer read from the pyramid). Returns how
    // many tiles became dirty.
    std::size_t editedLazily(const std::set<QuadKey>& changed, const std::vector<QuadKey>& touched);
    // Edits seen so far (every call of edited() and editedLazily()).
    std::uint64_t editCount() const { return edits_; }
    // Marks dirty the tiles of the quads holding `layer`'s elements (a layer hidden or shown).
    void layerChanged(LayerId layer);
    // Stops the background tiles and subdivision, dropping them (the threads check their cancel
    // flags between the elements they handle), and waits for the threads: call before anything
    // changes the scene, the forest's trees or their curve data (an edit, an undo, a new tree).
    // Returns how many were dropped (the tiles stopped and the subdivision).
    std::size_t quiesce();
    // Whether a quad's tiles or children are being made in the background, or wait for a frame
    // to take them.
    bool backgroundBusy() const { return !background_.empty() || subdivisions_.leaf() != nullptr; }
    // Waits until the background work begun is done (the next frame takes it): for a caller that
    // wants the view complete (a script, a test), not for a frame.
    void waitForBackground();

    const CachedTile* tile(const QuadKey& key) const;
    const std::map<QuadKey, CachedTile>& tiles() const { return cache_; }
    const DrawPlan& plan() const;
    std::pair<const Quad*, const CachedTile*> tileAt(Vec2 p) const;
    double displayedHeight(Vec2 p) const;
    const ObjectCounters& objectCounters() const { return objectCounters_; }

    // See EditSession::setPyramid().
    void setPyramid(std::shared_ptr<PyramidReader> pyramid, std::optional<std::uint64_t> madeAt);
    const std::shared_ptr<PyramidReader>& pyramid() const { return pyramid_; }
    bool readsPyramid(const Quad& q) const;
    const PyramidUse& pyramidUse() const { return pyramidUse_; }

private:
    using Clock = std::chrono::steady_clock;
    struct FrameLeaves {
        std::vector<const Quad*> view;       // visible leaves of the current view
        std::vector<const Quad*> ahead;      // visible leaves only the predicted viewer has, without a clean tile
        std::vector<const Quad*> madeAhead;  // the same, with one
    };
    // `background`: subdivisions of many elements made on the background thread (a frame budget).
    void refine(glm::dvec3 viewer, std::optional<glm::dvec3> predicted, bool background, FrameReport& r);
    FrameLeaves collectLeaves(glm::dvec3 viewer, std::optional<glm::dvec3> predicted, const QuadVisibility& visible,
                              FrameReport& r) const;
    // Marks the tiles of the shown quads and of their ancestors used; returns the shown quads
    // whose tile is missing or dirty.
    std::vector<const Quad*> keepShown(const CacheFit& fit);
    void keepMadeAhead(std::vector<const Quad*> madeAhead, std::size_t kept, glm::dvec3 predicted);
    std::size_t prefetch(std::vector<const Quad*> ahead, glm::dvec3 predicted, double budgetMs, Clock::time_point t0, FrameReport& r);
    void evict();
    // Where a quad's appearance came from: made live, read from the pyramid, made live because the
    // read failed, made live because an edit touched it below the pyramid's L.
    enum Source : char { kLive = 0, kRead = 1, kFailed = 2, kTouched = 3 };
    // The knobs one tile job reads (the session's, or the background thread's copies).
    struct JobParams {
        const AppearanceParams& appearance;
        const ElevationParams& elevation;
        const ObjectParams& objects;
        const WorkClock& clock;
        int border;  // of the appearance tiles read from the pyramid
        PyramidReader* pyramid;
    };
    // One of quad q's two jobs into `t`, timed into the estimates: its appearance (read from the
    // pyramid when `read`, made live when that fails; returns the source) or its elevation and
    // objects (the objects on `objectDem()`'s window; returns kLive).
    Source runJob(bool appearance, const Quad& q, const Quadtree& tree, const CurveDataCache& data, bool read, const Dem& dem,
                  const std::function<const Dem&()>& objectDem, const JobParams& p, CachedTile& t, const CancelFlag* cancel);
    // Puts the made tiles of the quad `key` into the cache (`window`: its streamed DEM window, if any).
    void store(const QuadKey& key, CachedTile&& made, char source, const DemWindow* window, int objectLevel, FrameReport& r);
    // Counts a quad's appearance made or read (PyramidUse).
    void countPyramidUse(char source);
    // Makes the tiles of `quads` in order within the budget; returns how many were made.
    std::size_t produce(const std::vector<const Quad*>& quads, glm::dvec3 viewer, double budgetMs, Clock::time_point t0,
                        FrameReport& r);
    // Records the quads below the pyramid's level L whose appearance the edit changed.
    void recordTouched(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped, bool edited);
    // Marks dirty the tiles of the `changed` quads, of those not in the forest now and of those
    // holding a curve whose z-profile was `dropped`; returns how many.
    std::size_t markDirty(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped);
    bool touched(const Quad& q) const;
    // Whether cached `q` holds one of `dropped`'s curves (its tile used a dropped z-profile).
    bool holdsDropped(const Quad& q, const std::vector<ElementRef>& dropped) const;
    // A streamed DEM (tile_loop_dem.cpp): dirty the shown tiles made from a coarser level than
    // is now loaded for them, renew the requests of those shown; the window of quad `q`, requested
    // with the K rule's ratio for `viewer`; the window its object meshes read (`quadWindow`, or a
    // wider one over the bridges it makes).
    void followDemStream(const CacheFit& fit, glm::dvec3 viewer, FrameReport& r);
    DemWindow demWindow(const Quad& q, glm::dvec3 viewer);
    DemWindow objectWindow(const Quad& q, glm::dvec3 viewer, const DemWindow& quadWindow);
    // Background tiles (tile_loop_background.cpp). Whether `q`'s tiles are estimated to take
    // longer than SessionParams::backgroundMs (`fromPyramid`: its appearance is a read).
    bool slow(const Quad& q, bool fromPyramid) const;
    // Begins q's tiles on a background thread (a lane must be free).
    void startBackground(const Quad& q, bool fromPyramid, glm::dvec3 viewer, FrameReport& r);
    // Takes the background tiles into the cache when they are done (dropped when stale).
    void takeBackground(FrameReport& r);
    // Stops the background tiles and waits, dropping them; returns how many.
    std::size_t dropBackgroundTiles();
    // Before refining for `viewers`: stops the background tiles when the refinement would drop
    // their quad; marks them stale when their quad's vector data arrived (`arrived`).
    void guardBackground(std::span<const glm::dvec3> viewers, FrameReport& r);
    void staleBackground(const std::vector<QuadKey>& arrived);

    const SessionParams& params_;
    const Scene& scene_;
    const Dem& dem_;
    DemStream* stream_ = nullptr;
    std::unique_ptr<WholeTree> whole_;  // setTree()'s
    QuadForest* forest_ = nullptr;
    std::map<QuadKey, CachedTile> cache_;
    mutable DrawPlan plan_;
    mutable bool planPending_ = false;  // frame() ran since the plan was made
    QuadVisibility planVisible_;
    std::uint64_t clock_ = 0, version_ = 0;
    // An appearance and an elevation tile's time (with its objects), and an appearance tile read
    // from the pyramid (whatever its quad holds: a read and a decode).
    ProductionEstimate estimates_[3];
    ObjectCounters objectCounters_;
    std::shared_ptr<PyramidReader> pyramid_;
    int touchLevels_ = 0;  // edits record touched quads of the levels below this (L of the pyramids set)
    std::uint64_t edits_ = 0;
    // Quads below L an edit changed, and those whose whole subtree it may have: the edit count
    // when last touched.
    std::map<QuadKey, std::uint64_t> touched_, touchedBelow_;
    PyramidUse pyramidUse_;
    // A quad's tiles being made on the background thread.
    struct Background {
        QuadKey key;
        const Quad* quad = nullptr;
        std::unique_ptr<CancelFlag> cancel;
        struct Made {
            CachedTile tile;
            char source = 0;  // as produce()'s: live, read from the pyramid, failed there, touched
        };
        std::future<Made> result;
        DemWindow window;             // with a streamed DEM: the quad's window
        int objectLevel = -1;         // and the level its objects' was cut from
        bool stale = false;           // its quad's vector data arrived since it began: dropped when done
    };
    std::vector<Background> background_;  // at most backgroundLanes()
    std::unique_ptr<BackgroundWorkers> workers_;  // their threads, made at the first
    std::size_t backgroundLanes() const;  // quads whose tiles are made in the background at once
    BackgroundSubdivision subdivisions_{params_};
};

}  // namespace lacet
