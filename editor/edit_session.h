#pragma once
// The editing session without a window (issue: the 3D editor; §6, §8): a document (scene,
// georeference, DEM), its quadtree and curve data, an undo/redo stack of commands with exact
// inverses (editor/command.h), and the live loop's tile cache: every command goes through
// changeset -> CurveDataCache::invalidate -> Quadtree::update -> dirty tiles, and frame() makes
// the missing and dirty tiles of the view, nearest first, on TBB worker threads, until its time
// budget is spent.
//
// Tiles: one appearance and one elevation tile per quad (the latter with the quad's object meshes,
// §5.3: made in the same job, dirty and remade with it), cached by (level, x, y) with an LRU
// bound (`cacheTiles`); tiles of the current view, of their ancestors (shown while a leaf is
// made) and those made ahead for a predicted viewer that still wants them are not evicted. When
// the view's leaves and their ancestors are more than the cache holds, the farthest quads are
// shown instead of their children (editor/cache_fit.h, as in §9.1), so the cache never exceeds
// its bound (of one tile or more). A tile is dirty when its quad's graph changed, or when it used
// a z-profile that an edit dropped (a river downstream of the edit); a dirty tile that the frame
// neither shows nor keeps as an ancestor's is dropped (nothing would make it again).
//
// Visibility: frame() takes a predicate (the window's frustum test) and makes only the visible
// leaves' tiles. The draw plan: the session decides what a frame draws (editor/draw_plan.h, made
// from what frame() left when first read): each leaf with the tile that stands for it, its own
// or, while it is made, its nearest ancestor's; the renderer draws that plan, and the displayed
// height reads it.
// Prefetching: frame() may be given the viewer predicted a little later on its path (§8); with
// budget left once the view is complete, it makes the tiles that viewer will need, within the
// cache's room.
//
// Undo granularity: a drag is many commands merged into one undo step (execute(cmd, merge)),
// and a compound edit (a new road: its nodes, then its curve) is one group.
//
// The pyramid (§7, Fig. 10; pyramid/pyramid_reader.h): with one set, the appearance of a quad of
// a level below the pyramid's first vector level L is read from it (a mipmap of level L's tiles)
// instead of produced from the vector data, which at those levels holds most of the scene; its
// elevation (cheap) and every tile at L and deeper are produced live. A quad whose appearance an
// edit changed since the pyramid was made is produced live from then on: after each edit the
// session records the quads below L that changed (UPDATE's changed quads, those holding a curve
// whose z-profile was dropped, the root) and, for such a quad that is a leaf, every quad below it
// (it has no children to say which changed). setPyramid() with the edit count of the document the
// pyramid was made from (after a save and `lacet pyramid update`) forgets the records up to it. A
// tile the pyramid cannot give (corrupt, missing, locked) is produced live and counted. While a
// layer is hidden the pyramid (made with every layer) is not read.

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <tuple>
#include <vector>

#include "editor/cache_fit.h"
#include "editor/command.h"
#include "io/dem_stream.h"
#include "model/graph_step.h"
#include "editor/draw_plan.h"
#include "editor/production_estimate.h"
#include "io/document.h"
#include "model/curve_data.h"
#include "model/quadtree.h"
#include "model/work_clock.h"
#include "pyramid/pyramid_reader.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"
#include "raster/object_meshes.h"

namespace lacet {

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

struct CommandReport {
    double applyMs = 0.0, updateMs = 0.0;  // the edit and the quadtree UPDATE
    std::size_t changedQuads = 0;          // quads whose graph changed
    std::size_t dirtyTiles = 0;            // cached tiles marked dirty (graph or curve data)
};

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
};

// What the pyramid saved the session so far (appearance tiles).
struct PyramidUse {
    std::size_t read = 0;     // read from the pyramid
    std::size_t failed = 0;   // the pyramid could not give them (corrupt, missing, locked): made live
    std::size_t touched = 0;  // below L but changed by an edit since the pyramid was made: made live
    std::size_t live = 0;     // made live in all (failed and touched included)
};

using QuadVisibility = std::function<bool(const Quad&)>;

class EditSession {
public:
    EditSession(SceneDocument document, SessionParams params = {});
    EditSession(const EditSession&) = delete;
    EditSession& operator=(const EditSession&) = delete;

    // Applies a command (EditError leaves everything as it was) and clears the redo stack. With
    // `merge`, and when the last command moved the same vertex or node, the two become one undo
    // step (a drag: undo goes back to where the drag began).
    CommandReport execute(const Command& command, bool merge = false);
    // Commands executed between beginGroup() and endGroup() are undone and redone together.
    void beginGroup();
    void endGroup();
    // Undo the last command (or group) / redo the last undone one; false when there is none.
    bool undo(CommandReport* report = nullptr);
    bool redo(CommandReport* report = nullptr);
    std::size_t undoDepth() const { return done_.size(); }
    std::size_t redoDepth() const { return undone_.size(); }

    // Unsaved changes: the scene differs from the one last saved (or opened).
    bool modified() const { return savedSerial_ != topSerial(); }
    // Marks the document as saved (by the caller, with io/scene_file.h: the session knows no file
    // format): modified() is false while the scene is in this state.
    void markSaved();
    // Forgets the redo history (after a command group was taken back because it was refused: its
    // undoing is no step of the user's to redo).
    void forgetRedo() { undone_.clear(); }

    // Refines the quadtree for `viewer` (x, y, height above the ground; metres) and produces
    // missing or dirty tiles of its visible leaves, nearest first, until `budgetMs` is spent (at
    // least one quad; budget <= 0: until none is left; the time spent refining counts in it).
    // With budget left and a `predicted`
    // viewer, then makes the tiles of the leaves that viewer would have (prefetching).
    FrameReport frame(glm::dvec3 viewer, double budgetMs, const QuadVisibility& visible = {},
                      std::optional<glm::dvec3> predicted = std::nullopt);

    // Accuracy knobs applied live: K takes effect at the next frame; new refinement parameters
    // rebuild the quadtree and drop every tile.
    void setK(double K);  // K > 0 (ViewParams), else std::invalid_argument and nothing changes
    void setRefineBudget(double ms) { params_.refineBudgetMs = ms; }
    void setClock(WorkClock clock) { params_.clock = std::move(clock); }
    void setRefineParams(const RefineParams& refine);
    // Hides a layer from the textures (its appearance and footprint) or shows it again: the tiles
    // of quads holding its elements become dirty.
    void setLayerVisible(LayerId layer, bool visible);
    bool layerVisible(LayerId layer) const {
        return layer >= params_.appearance.hiddenLayers.size() || !params_.appearance.hiddenLayers[layer];
    }
    const SessionParams& params() const { return params_; }

    const SceneDocument& document() const { return doc_; }
    const Quadtree& quadtree() const { return *quadtree_; }
    const CurveDataCache& curveData() const { return *data_; }
    const GraphStep& graphStep() const { return *graphStep_; }
    // What the object meshes cost so far (raster/object_meshes.h): meshes, bridges, pillars, trees.
    const ObjectCounters& objectCounters() const { return objectCounters_; }
    const CachedTile* tile(const QuadKey& key) const;
    // What the last frame draws (editor/draw_plan.h): every leaf with the tile standing for it,
    // made from the tree and the cache as frame() left them (and the visibility test it was
    // given, kept until the next frame) when first read. Edits in between change neither: they
    // keep the tree's shape and mark tiles dirty without dropping any. Valid until the next
    // frame() or setRefineParams(). Not for concurrent first reads.
    const DrawPlan& plan() const;
    // The height shown at p: z_m (bilinear) of the tile the plan draws over p; the DEM where it
    // has none (before the first frame, or where no tile is made yet).
    double displayedHeight(Vec2 p) const;
    // How high a viewer at `eye` is above the displayed ground (metres, at least 1: the K rule
    // and the clip range need a positive height).
    double heightAboveGround(glm::dvec3 eye) const { return std::max(1.0, eye.z - displayedHeight({eye.x, eye.y})); }
    // The tile the plan draws over p and its quad in the tree (edits keep the tree's shape);
    // nullptr, nullptr where the plan draws no tile.
    std::pair<const Quad*, const CachedTile*> tileAt(Vec2 p) const;
    const std::map<QuadKey, CachedTile>& tiles() const { return cache_; }

    // The pyramid the appearance of coarse quads is read from (nullptr: none; every tile live).
    // `madeAt`: the editCount() of the document the pyramid holds (edits after it stay live);
    // the default, now, for a pyramid of the document as it is. Tiles already cached stay. Throws
    // std::invalid_argument when its tiles are not the session's appearance resolution.
    void setPyramid(std::shared_ptr<PyramidReader> pyramid, std::optional<std::uint64_t> madeAt = std::nullopt);
    const std::shared_ptr<PyramidReader>& pyramid() const { return pyramid_; }
    // Edits (commands, undos and redos) applied to the document so far.
    std::uint64_t editCount() const { return edits_; }
    // Whether quad `q`'s appearance would be read from the pyramid now.
    bool readsPyramid(const Quad& q) const;
    const PyramidUse& pyramidUse() const { return pyramidUse_; }
    // The streamed DEM (nullptr when the document's DEM is in memory whole).
    DemStream* demStream() const { return demStream_.get(); }

private:
    struct Done {
        Command command;
        Applied applied;
        std::uint64_t group = 0;   // 0: alone
        std::uint64_t serial = 0;  // identifies the scene state after it (for modified())
    };
    CommandReport afterEdit(const Changeset& cs, double applyMs);
    std::uint64_t topSerial() const { return done_.empty() ? 0 : done_.back().serial; }
    // The steps of frame() (§8).
    struct FrameLeaves {
        std::vector<const Quad*> view;       // visible leaves of the current view
        std::vector<const Quad*> ahead;      // visible leaves only the predicted viewer has, without a clean tile
        std::vector<const Quad*> madeAhead;  // the same, with one
    };
    void refine(glm::dvec3 viewer, std::optional<glm::dvec3> predicted, FrameReport& r);
    FrameLeaves collectLeaves(glm::dvec3 viewer, std::optional<glm::dvec3> predicted, const QuadVisibility& visible,
                              FrameReport& r) const;
    // Marks the tiles of the shown quads and of their ancestors used; returns the shown quads
    // whose tile is missing or dirty.
    std::vector<const Quad*> keepShown(const CacheFit& fit);
    void keepMadeAhead(std::vector<const Quad*> madeAhead, std::size_t kept, glm::dvec3 predicted);
    std::size_t prefetch(std::vector<const Quad*> ahead, glm::dvec3 predicted, double budgetMs,
                         std::chrono::steady_clock::time_point t0, FrameReport& r);
    void evict();
    // Records the quads below the pyramid's level L whose appearance the edit changed.
    void recordTouched(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped, bool edited);
    bool touched(const Quad& q) const;
    // Whether cached `q` holds one of `dropped`'s curves (its tile used a dropped z-profile).
    bool holdsDropped(const Quad& q, const std::vector<ElementRef>& dropped) const;
    // Makes the tiles of `quads` in order within the budget; returns how many were made.
    std::size_t produce(const std::vector<const Quad*>& quads, glm::dvec3 viewer, double budgetMs, std::chrono::steady_clock::time_point t0,
                        FrameReport& r);

    SceneDocument doc_;
    SessionParams params_;
    std::unique_ptr<DemHeightField> demHeights_;  // the DEM in memory as a height field, or
    std::unique_ptr<DemStream> demStream_;       // the streamed DEM
    const HeightField* heights_ = nullptr;       // what the z-profiles sample: one of the two
    // Dirty the shown tiles made from a coarser DEM level than is now loaded for them; renew
    // the requests of those shown.
    void followDemStream(const CacheFit& fit, glm::dvec3 viewer, FrameReport& r);
    // The DEM window of quad `q` (streamed DEM only), requested with the K rule's ratio for `viewer`.
    DemWindow demWindow(const Quad& q, glm::dvec3 viewer);
    // The window its object meshes read: `quadWindow`, or a wider one over the bridges it makes.
    DemWindow objectWindow(const Quad& q, glm::dvec3 viewer, const DemWindow& quadWindow);
    std::unique_ptr<GraphStep> graphStep_;  // before the quadtree that calls it
    std::unique_ptr<Quadtree> quadtree_;
    std::unique_ptr<CurveDataCache> data_;
    std::vector<Done> done_;
    std::vector<Done> undone_;  // command, group and serial kept for redo
    std::map<QuadKey, CachedTile> cache_;
    mutable DrawPlan plan_;
    mutable bool planPending_ = false;  // frame() ran since the plan was made
    QuadVisibility planVisible_;
    std::uint64_t clock_ = 0, version_ = 0, serial_ = 0, savedSerial_ = 0;
    std::uint64_t group_ = 0, nextGroup_ = 0;
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
};

}  // namespace lacet
