#pragma once
// The editing session without a window (issue: the 3D editor; §6, §8): a document (scene,
// georeference, DEM), its quadtree and curve data, the command history (editor/command_history.h:
// undo/redo with exact inverses, drags merged, groups) and the live loop's tiles
// (editor/tile_loop.h: the cache, production within a frame's budget, prefetching, eviction, the
// draw plan, the pyramid's coarse tiles). Every command goes through changeset ->
// CurveDataCache::invalidate -> Quadtree::update -> the loop's dirty tiles; frame() makes the
// missing and dirty tiles of the view, nearest first, until its time budget is spent.
//
// Visibility: frame() takes a predicate (the window's frustum test) and makes only the visible
// leaves' tiles. The draw plan (editor/draw_plan.h) is made from what frame() left when first
// read; the renderer draws it and the displayed height reads it. Prefetching: frame() may be
// given the viewer predicted a little later on its path (§8; editor/look_ahead.h); with budget
// left once the view is complete, it makes the tiles that viewer will need, within the cache's
// room.
//
// The pyramid (§7, Fig. 10): with one set, the appearance of a quad of a level below the
// pyramid's first vector level L is read from it, except where an edit changed it since the
// pyramid was made (editor/tile_loop.h). setPyramid() with the edit count of the document the
// pyramid was made from (after a save and `lacet pyramid update`; editor/pyramid_link.h) forgets
// the records up to it.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include <glm/vec3.hpp>

#include "editor/command.h"
#include "editor/command_history.h"
#include "editor/draw_plan.h"
#include "editor/lazy_edits.h"
#include "editor/lazy_forest.h"
#include "editor/session_params.h"
#include "editor/tile_loop.h"
#include "io/dem_stream.h"
#include "io/document.h"
#include "io/scene_save_edits.h"
#include "model/curve_data.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "pyramid/pyramid_reader.h"
#include "raster/dem_height_field.h"
#include "raster/object_meshes.h"

namespace lacet {

struct CommandReport {
    double applyMs = 0.0, updateMs = 0.0;  // the edit and the quadtree UPDATE (lazily: reading the parts again)
    std::size_t changedQuads = 0;          // quads whose graph changed (lazily: the parts read again, and the top's root)
    std::size_t dirtyTiles = 0;            // cached tiles marked dirty (graph or curve data)
    std::size_t backgroundStopped = 0;     // background work stopped before the edit (TileLoop::quiesce)
    bool topReadAgain = false;             // lazily: the top tree was read again
};

class EditSession {
public:
    EditSession(SceneDocument document, SessionParams params = {});
    // The scene file at `path` read lazily (§7; editor/lazy_forest.h): the levels down to the part
    // level now (LazyForest::readTop), each part as the view wants it, within lazy.vectorBudgetMiB.
    // Its commands name the file's ids (editor/lazy_edits.h: the edits are kept over the file
    // until saveEdits() writes them into it); each reads again the parts it touches, and the top tree where it holds, or
    // would hold, what changed. Throws SceneFileError naming the file.
    EditSession(const std::string& path, LazyParams lazy, SessionParams params = {});
    EditSession(const EditSession&) = delete;
    EditSession& operator=(const EditSession&) = delete;

    // Applies a command (EditError leaves everything as it was) and clears the redo stack. With
    // `merge`, and when the last command moved the same vertex or node, the two become one undo
    // step (a drag: undo goes back to where the drag began). Lazily, a command, undo or redo
    // whose reads of the file fail (SceneFileError naming it) leaves the edits and the history as
    // they were.
    CommandReport execute(const Command& command, bool merge = false);
    // Commands executed between beginGroup() and endGroup() are undone and redone together.
    void beginGroup();
    void endGroup();
    // Undo the last command (or group) / redo the last undone one; false when there is none.
    bool undo(CommandReport* report = nullptr);
    bool redo(CommandReport* report = nullptr);
    std::size_t undoDepth() const { return lazyEdits_ ? lazyEdits_->undoDepth() : history_.undoDepth(); }
    std::size_t redoDepth() const { return lazyEdits_ ? lazyEdits_->redoDepth() : history_.redoDepth(); }

    // The id the next element of `kind` added to `layer` gets (AddNodeCmd, AddCurveCmd): the
    // layer's slot count; lazily, the file's next id (LazyEdits::nextId). std::out_of_range for
    // a layer the scene has not; lazily, SceneFileError when the file cannot be read.
    ElementId nextId(LayerId layer, ElementKind kind) const;

    // Unsaved changes: the scene differs from the one last saved (or opened).
    bool modified() const { return lazyEdits_ ? lazyEdits_->modified() : history_.modified(); }
    // Marks the document as saved (by the caller, with io/scene_file.h: the session knows no file
    // format): modified() is false while the scene is in this state.
    void markSaved() { history_.markSaved(); }
    // A scene read lazily: saves its edits into its file, in place (io/scene_save_edits.h), after
    // the background work and the parts being read are done; modified() is then false, and undo
    // and redo go on over the saved file. SceneFileError naming the file when it cannot be saved
    // (the file changed since it was opened, cannot be written...): the edits stay unsaved.
    // std::logic_error for a session of a whole document.
    SceneEditsSaved saveEdits();
    // Forgets the redo history (after a command group was taken back because it was refused: its
    // undoing is no step of the user's to redo).
    void forgetRedo() { lazyEdits_ ? lazyEdits_->forgetRedo() : history_.forgetRedo(); }

    // Refines the quadtree for `viewer` (x, y, height above the ground; metres) and produces
    // missing or dirty tiles of its visible leaves, nearest first, until `budgetMs` is spent (at
    // least one quad; budget <= 0: until none is left; the time spent refining counts in it).
    // With budget left and a `predicted`
    // viewer, then makes the tiles of the leaves that viewer would have (prefetching).
    FrameReport frame(glm::dvec3 viewer, double budgetMs, const QuadVisibility& visible = {},
                      std::optional<glm::dvec3> predicted = std::nullopt) {
        return loop_->frame(viewer, budgetMs, visible, predicted);
    }

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

    // The document; for a scene read lazily, its top tree's part (Layer::sceneIds give the file's
    // ids, which commands name), read again after an edit that touches it.
    const SceneDocument& document() const { return doc_; }
    const Quadtree& quadtree() const { return *quadtree_; }
    const CurveDataCache& curveData() const { return *data_; }
    const GraphStep& graphStep() const { return *graphStep_; }
    // What the object meshes cost so far (raster/object_meshes.h): meshes, bridges, pillars, trees.
    const ObjectCounters& objectCounters() const { return loop_->objectCounters(); }
    const CachedTile* tile(const QuadKey& key) const { return loop_->tile(key); }
    // What the last frame draws (editor/draw_plan.h): every leaf with the tile standing for it,
    // made from the tree and the cache as frame() left them (and the visibility test it was
    // given, kept until the next frame) when first read. Edits in between change neither: they
    // keep the tree's shape and mark tiles dirty without dropping any. Valid until the next
    // frame() or setRefineParams(). Not for concurrent first reads.
    const DrawPlan& plan() const { return loop_->plan(); }
    // Background work (SessionParams::backgroundMs): whether a slow quad's tiles or children are
    // being made or wait for the next frame, and waiting until they are made (a script, a test:
    // then frame() again until nothing is pending).
    bool backgroundBusy() const { return loop_->backgroundBusy(); }
    void waitForBackground() { loop_->waitForBackground(); }
    // The height shown at p: z_m (bilinear) of the tile the plan draws over p; the DEM where it
    // has none (before the first frame, or where no tile is made yet).
    double displayedHeight(Vec2 p) const { return loop_->displayedHeight(p); }
    // How high a viewer at `eye` is above the displayed ground (metres, at least 1: the K rule
    // and the clip range need a positive height).
    double heightAboveGround(glm::dvec3 eye) const { return std::max(1.0, eye.z - displayedHeight({eye.x, eye.y})); }
    // The tile the plan draws over p and its quad in the tree (edits keep the tree's shape);
    // nullptr, nullptr where the plan draws no tile.
    std::pair<const Quad*, const CachedTile*> tileAt(Vec2 p) const { return loop_->tileAt(p); }
    const std::map<QuadKey, CachedTile>& tiles() const { return loop_->tiles(); }

    // The pyramid the appearance of coarse quads is read from (nullptr: none; every tile live).
    // `madeAt`: the editCount() of the document the pyramid holds (edits after it stay live);
    // the default, now, for a pyramid of the document as it is. Tiles already cached stay. Throws
    // std::invalid_argument when its tiles are not the session's appearance resolution.
    void setPyramid(std::shared_ptr<PyramidReader> pyramid, std::optional<std::uint64_t> madeAt = std::nullopt) {
        loop_->setPyramid(std::move(pyramid), madeAt);
    }
    const std::shared_ptr<PyramidReader>& pyramid() const { return loop_->pyramid(); }
    // Edits (commands, undos and redos) applied to the document so far.
    std::uint64_t editCount() const { return loop_->editCount(); }
    // Whether quad `q`'s appearance would be read from the pyramid now.
    bool readsPyramid(const Quad& q) const { return loop_->readsPyramid(q); }
    const PyramidUse& pyramidUse() const { return loop_->pyramidUse(); }
    // The documents the window sees (the file's ids in Layer::sceneIds): document(), then, for a
    // scene read lazily, each part held (an element may be in several; each holds it as it is).
    void forEachHeldDocument(const std::function<void(const SceneDocument&)>& f) const {
        f(doc_);
        if (forest_) forest_->forEachPart(f);
    }
    // The parts of a scene read lazily (nullptr: the whole scene is loaded).
    const LazyForest* lazyForest() const { return forest_.get(); }
    // Its edits, for a scene read lazily (nullptr otherwise).
    const LazyEdits* lazyEdits() const { return lazyEdits_.get(); }
    // A scene read lazily: its file's stored checksum (io/scene_checksum.h; what a pyramid of it
    // records); empty for a document loaded whole (its own checksum is computed from it).
    const std::string& storedChecksum() const { return storedChecksum_; }
    // The streamed DEM (nullptr when the document's DEM is in memory whole).
    DemStream* demStream() const { return demStream_.get(); }

private:
    EditSession(LazyTop top, LazyParams lazy, SessionParams params);
    // After each command, undo or redo: the curve data, UPDATE and the loop's dirty tiles.
    CommandReport afterEdit(const Changeset& cs, double applyMs);
    // After a step of a scene read lazily: reads again what it touched, marks the tiles to make.
    // When the top cannot be read again (the file changed or cannot be read), the step is taken
    // back (LazyEdits::rollback) and the exception goes on.
    CommandReport afterLazyStep(const LazyStep& step, double applyMs);
    // An undo or redo of a scene read lazily (`step`: none when there was nothing to undo or redo).
    bool afterLazyHistory(const std::optional<LazyStep>& step, CommandReport* report, std::size_t stopped);
    // Whether the top tree holds, or would hold, an element the step changed.
    bool topTouched(const LazyStep& step) const;
    // Reads the top tree's vector data again with the edits and makes its tree and curve data.
    void readTopAgain();
    // Runs `step` (a history call) summing the reports of the edits it makes.
    template <class Step>
    CommandReport edits(Step&& step);
    void buildTree();  // the graph step, quadtree and curve data (and the lazy forest), for params_.refine

    SceneDocument doc_;
    SessionParams params_;
    std::unique_ptr<DemHeightField> demHeights_;  // the DEM in memory as a height field, or
    std::unique_ptr<DemStream> demStream_;       // the streamed DEM
    const HeightField* heights_ = nullptr;       // what the z-profiles sample: one of the two
    std::unique_ptr<GraphStep> graphStep_;  // before the quadtree that calls it
    std::unique_ptr<Quadtree> quadtree_;
    std::unique_ptr<CurveDataCache> data_;
    std::string lazyPath_;                 // a scene read lazily: its file,
    std::optional<LazyParams> lazy_;       // its knobs,
    std::string storedChecksum_;           // its stored checksum,
    double topReach_ = 0.0;                // m around a part's quad its read searches (the top's, at the part level)
    std::unique_ptr<LazyEdits> lazyEdits_;  // its edits
    std::unique_ptr<LazyForest> forest_;   // and its parts (over the quadtree: destroyed before it)
    CommandHistory history_;
    std::unique_ptr<TileLoop> loop_;  // reads params_, doc_ and the tree
};

}  // namespace lacet
