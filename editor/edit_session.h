#pragma once
// The editing session without a window (issue: the 3D editor; §6, §8): a document (scene,
// georeference, DEM), its quadtree and curve data, an undo/redo stack of commands with exact
// inverses (editor/command.h), and the live loop's tile cache: every command goes through
// changeset -> CurveDataCache::invalidate -> Quadtree::update -> dirty tiles, and frame() makes
// the missing and dirty tiles of the view, nearest first, on TBB worker threads, until its time
// budget is spent.
//
// Tiles: one appearance and one elevation tile per quad, cached by (level, x, y) with an LRU
// bound (`cacheTiles`, the paper's 784 elevation tiles by default); tiles of the current view are
// never evicted. A tile is dirty when its quad's graph changed, or when it used a z-profile that
// an edit dropped (a river downstream of the edit).
//
// Not here yet (the window's part): frustum culling, prefetching along the camera path, the
// coarser ancestor shown while a quad is produced.

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <tuple>

#include "editor/command.h"
#include "io/scene_file.h"
#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"

namespace lacet {

struct SessionParams {
    RefineParams refine;
    double K = 2.8;            // subdivide quads closer to the viewer than K times their size (§8)
    int maxLevel = 24;
    std::size_t cacheTiles = 784;
    AppearanceParams appearance;
    ElevationParams elevation;
};

using QuadKey = std::tuple<int, std::uint32_t, std::uint32_t>;  // level, x, y

struct CachedTile {
    AppearanceTile appearance;
    ElevationTile elevation;
    bool dirty = false;
    std::uint64_t lastUsed = 0;
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
    double refineMs = 0.0, produceMs = 0.0;
};

class EditSession {
public:
    EditSession(SceneDocument document, SessionParams params = {});
    EditSession(const EditSession&) = delete;
    EditSession& operator=(const EditSession&) = delete;

    // Applies a command (EditError leaves everything as it was) and clears the redo stack.
    CommandReport execute(const Command& command);
    // Undo the last command / redo the last undone one; false when there is none.
    bool undo(CommandReport* report = nullptr);
    bool redo(CommandReport* report = nullptr);
    std::size_t undoDepth() const { return done_.size(); }

    // Refines the quadtree for `viewer` (x, y, height; metres) and produces missing or dirty tiles
    // of its leaves, nearest first, until `budgetMs` is spent (at least one batch; budget <= 0:
    // until none is left).
    FrameReport frame(glm::dvec3 viewer, double budgetMs);

    const SceneDocument& document() const { return doc_; }
    const Quadtree& quadtree() const { return *quadtree_; }
    const CurveDataCache& curveData() const { return *data_; }
    const CachedTile* tile(const QuadKey& key) const;
    const std::map<QuadKey, CachedTile>& tiles() const { return cache_; }

private:
    CommandReport afterEdit(const Changeset& cs, double applyMs);

    SceneDocument doc_;
    SessionParams params_;
    std::unique_ptr<DemHeightField> heights_;
    std::unique_ptr<Quadtree> quadtree_;
    std::unique_ptr<CurveDataCache> data_;
    std::vector<std::pair<Command, Applied>> done_;
    std::vector<Command> undone_;
    std::map<QuadKey, CachedTile> cache_;
    std::uint64_t clock_ = 0;
};

QuadKey keyOf(const Quad& q);

}  // namespace lacet
