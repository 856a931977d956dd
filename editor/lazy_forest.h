#pragma once
// A scene file's vector data read lazily, as the view needs it (§7: "the vector data ... loaded
// on demand"; issue 23): the forest (editor/quad_forest.h) of
//   - the top tree: the editing session's quadtree over what the levels down to the part level P
//     need, read once (io/scene_region.h: elevation only, when a pyramid gives their appearance),
//     refined no deeper than P;
//   - one part per quad of level P that a viewer wants subdivided: what the tiles of that quad and
//     every quad below it need (loadSceneRegion of the quad, exactly as a pyramid shard reads it,
//     so its tiles are the same, bit for bit, as with the whole scene loaded), with its own graph
//     step, quadtree (subdivided down the path to the quad, refined for the viewers below it) and
//     curve data.
// Memory follows the view: the parts' vector data (SceneRegionStats::bytes) stays within
// `vectorBudgetMiB` less the top tree's; past it, the parts no viewer wants now go, least recently
// wanted first, as the DEM stream drops blocks. Not counted: a part being read (at most the budget
// left when its read began, so the peak is up to twice the parts' budget), the parts' clipped
// quadtrees and curve data (io/scene_region.h lists what else a read holds). Without a pyramid
// (topElevationOnly false) the top tree reads every curve and area, for the appearance of the levels
// down to P: the whole scene, within the budget (refused past it); lazy reading pays with a
// pyramid. A part that does not fit beside those wanted now is refused (counted) and
// its quad stays a leaf of the top tree, drawn with its tile; so is a part the file cannot give (a
// corrupt row: counted, its error kept). Parts are read on a worker thread while frames go on
// (or in the frame that wants them, `background` false: deterministic, for tests); until a part
// arrives its quad is a leaf of the top tree, and its tile is made again when the part arrives
// (takeArrived).
//
// A part's read also checks the file's stored checksum against the top's: a file changed since is
// refused (counted, its error kept).
//
// Edits not saved (editor/lazy_edits.h) are read over the file (setOverlay): a part read sees them,
// renew() updates in memory, or reads again at once, the parts an edit touched (updated in place
// through UPDATE when it holds the same elements), and a part whose read began before an edit that
// touches it is read again when it arrives. The reads of the session's thread go through one
// connection kept open (io/scene_file.h); the worker's open the file.
//
// Not yet: parts stored clipped in the scene file (each part is clipped from the root curves it
// reads), and a part's own graph step sees the part alone (as a pyramid shard's does).

#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "editor/lazy_edits.h"
#include "editor/quad_forest.h"
#include "editor/session_params.h"
#include "io/document.h"
#include "io/scene_region.h"
#include "model/graph_step.h"
#include "raster/dem_height_field.h"

namespace lacet {

struct LazyParams {
    // P, the level of the quads read as one part (>= 1); -1: the first level whose quads are at
    // most `partQuadM` metres wide.
    int partLevel = -1;
    double partQuadM = 5000.0;
    double vectorBudgetMiB = 512.0;  // MiB of the parts' vector data held (> 0)
    bool background = true;          // parts read on a worker thread; false: in the frame that wants them
    // The top tree reads only what elevation needs (the appearance of levels up to P comes from a
    // pyramid; its tiles are otherwise made without the narrow curves and the other areas).
    bool topElevationOnly = false;
    // P for a scene of `extent`: partLevel, or the first level of quads at most partQuadM wide.
    int level(const Box& extent) const;
    void validate() const;  // std::invalid_argument naming the bad knob
};

// What the top tree reads of a scene file (LazyForest::readTop) and the read's figures (its stored
// checksum among them: the whole file's, which a pyramid of it records).
struct LazyTop {
    std::string path;
    SceneDocument doc;
    SceneRegionStats stats;
};

struct LazyStats {
    int partLevel = 0;
    double topMiB = 0.0;            // the top tree's vector data (the parts have the budget less this)
    std::size_t partsRead = 0;      // parts read (again after an eviction: counted again)
    std::size_t partsEvicted = 0;   // parts dropped for the budget
    std::size_t partsRefused = 0;   // reads refused: past the budget left, or the file could not give them
    std::size_t partsRenewed = 0;   // read again after an edit (renew)
    std::size_t partsUpdated = 0;   // of those, updated in place (the same elements)
    std::size_t partsMoved = 0;     // of those, updated in memory (no read: moveInPlace)
    std::size_t partsGrown = 0;     // of those, curves added or taken back in memory (no read: growInPlace)
    std::size_t partsHeld = 0;      // now
    std::size_t partsHeldPeak = 0;
    double heldMiB = 0.0, peakMiB = 0.0, largestPartMiB = 0.0;
    double readMs = 0.0, slowestReadMs = 0.0;  // reading and clipping parts (on the worker thread when in background)
    std::string lastError;          // of the last read the file could not give
};

class LazyForest final : public QuadForest {
public:
    // `top` (refined here no deeper than the part level), `topData` and `heights` must outlive the
    // forest; the parts are made with `params`' refinement, graph step and z-profile knobs. A part
    // whose read finds another stored checksum than `storedChecksum` (the file the top was read
    // from; empty: unchecked) is refused: the file changed since.
    LazyForest(std::string path, std::string storedChecksum, Quadtree& top, const CurveDataCache& topData, const HeightField& heights,
               const SessionParams& params, LazyParams lazy);
    ~LazyForest() override;  // waits for a read in flight
    LazyForest(const LazyForest&) = delete;
    LazyForest& operator=(const LazyForest&) = delete;

    // What the top tree reads of the scene file at `path`: the scene's extent down to the part level
    // (elevation only with topElevationOnly: the road and river curves at least two elevation
    // samples wide at that level, lakes and river areas), with the DEM, within the vector budget.
    // Throws SceneFileError naming the file (SceneBudgetError past the budget).
    static LazyTop readTop(const std::string& path, const LazyParams& lazy, const RefineParams& refine, bool dem = true,
                           const SceneOverlay* overlay = nullptr);

    // The narrowest road or river curve the top tree reads with topElevationOnly (m): two
    // elevation samples of the part level's quads.
    static double topMinCurveWidth(const Box& extent, const LazyParams& lazy, const RefineParams& refine);

    // Edits not saved, read over the file from now on (never null), and their version; then
    // renew() with what the edit changed.
    void setOverlay(std::shared_ptr<const SceneOverlay> overlay, std::uint64_t version);
    // Each part held: its document (the file's ids in Layer::sceneIds), in quad order.
    void forEachPart(const std::function<void(const SceneDocument&)>& f) const;
    // Waits for the parts being read on the worker (they are taken by the next refine()).
    void waitForReads() const;
    // The file's stored checksum after its edits were saved into it (io/scene_save_edits.h), which
    // the reads from now on must find.
    void setStoredChecksum(std::string checksum) { storedChecksum_ = std::move(checksum); }
    // The top tree read again (the same knobs; both must outlive the forest).
    void setTop(Quadtree& top, const CurveDataCache& topData);
    // After an edit of `refs` (the file's ids) that lay and lies in `boxes`: reads again, with the
    // overlay, every part held that holds one of them or whose region (its quad and reach) meets a
    // box dilated by `margin` (m). A part read again with the same elements (the same file ids) is
    // updated in place: the elements whose values differ are its changeset, through its curve data
    // and UPDATE (§6, as a whole scene's edit), its refined subtree kept; one with other elements is
    // made anew; one that no longer fits or cannot be read goes (its quad a leaf of the top tree).
    struct Renewal {
        std::vector<QuadKey> parts;    // read again, made anew or gone
        std::vector<QuadKey> rebuilt;  // of those, made anew or gone: every tile below is to be made again
        std::set<QuadKey> changed;     // the quads of the parts updated in place whose tiles are to be made again
    };
    Renewal renew(const LazyStep& step, double margin);
    // Whether `doc` (a part read: the file's ids in Layer::sceneIds) holds one of `refs`.
    static bool holdsAny(const SceneDocument& doc, const std::vector<ElementRef>& refs);

    const Quad& root() const override { return top_->root(); }
    const Quad& resolve(const Quad& q) const override;
    const Quad* parentOf(const Quad& q) const override;
    const Quadtree& treeOf(const Quad& q) const override;
    const CurveDataCache& dataOf(const Quad& q) const override;
    // The top tree for the viewers down to P, then each wanted part's tree below its quad; takes
    // the parts read since, reads (or asks the worker for) the missing wanted ones nearest first,
    // and evicts past the budget. False when a subdivision was deferred or a wanted part is not
    // there yet.
    bool refine(std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                ChildMaker* maker = nullptr) override;
    std::vector<QuadKey> takeArrived() override;
    bool holdsAppearance(const Quad& q) const override { return !lazy_.topElevationOnly || owner(q) != nullptr; }
    // Also a part's own quad: its part is wanted (a part no viewer wants may go for the budget).
    bool keeps(const Quad& q, std::span<const glm::dvec3> viewers, const ViewParams& view) const override {
        return QuadForest::keeps(q, viewers, view) && (q.level != level_ || !owner(q) || Quadtree::wantedByAny(q, viewers, view));
    }

    const LazyStats& stats() const { return stats_; }
    int partLevel() const { return level_; }
    const LazyParams& params() const { return lazy_; }
    // Whether the part of quad `key` (of the part level) is held now.
    bool holds(const QuadKey& key) const { return parts_.count(key) > 0; }

private:
    struct Part;
    struct Read {
        QuadKey key;
        double budgetMiB = 0.0;
        std::uint64_t version = 0;  // of the overlay it reads
        std::future<std::unique_ptr<Part>> result;
    };
    // The part of quad `key` made of `doc`, read with `st`.
    std::unique_ptr<Part> makePart(const QuadKey& key, SceneDocument doc, const SceneRegionStats& st) const;
    // `connection`: the file kept open by this thread (connection_), or nullptr (the worker's: the
    // file opened for the read).
    std::unique_ptr<Part> read(const QuadKey& key, const Box& bounds, double budgetMiB, std::shared_ptr<const SceneOverlay> overlay,
                               SceneFileConnection* connection) const;
    // The z-profiles and lake levels the tiles of `part`'s quad will ask for, made now: by the
    // worker thread with the part, so that the DEM blocks they read are loaded before it arrives,
    // not by a frame's production.
    static void warmCurveData(const Part& part);
    // The vector data of the part of quad `bounds` (what read() makes a part of).
    SceneDocument readPart(const Box& bounds, double budgetMiB, const SceneOverlay* overlay, SceneRegionStats& stats,
                           SceneFileConnection* connection) const;
    // Updates `part` in place to `doc`, read again with the same elements after `step` but for the
    // elements it added or took back (the largest ids); adds the keys of its quads whose tiles
    // change to `changed`.
    void update(Part& part, SceneDocument doc, const LazyStep& step, std::set<QuadKey>& changed);
    // Whether `step` touches `part` (renew()): it names an element the part holds, meets the
    // region its read searched, or puts a river (a road) where a held road's (bridge's) read finds it.
    static bool touches(const Part& part, const LazyStep& step, double margin);
    // The rivers (curves and areas, the file's ids) whose feature boxes meet the hull of a road of
    // a step (by its index in the step), read from the file with the edits once for the step.
    using StepRivers = std::map<std::size_t, std::vector<ElementRef>>;
    // Updates `part` in memory to `step` when what its read would load is still loaded (the step
    // moves vertices and nodes, no river, no bridge road; what it changed that the part's region
    // finds now it found before; a moved road's rivers, those its hull meets, are all held: within
    // the region, or else found through the file's R-trees, in `rivers`); false, changing nothing,
    // otherwise.
    bool moveInPlace(Part& part, const LazyStep& step, StepRivers& rivers, std::set<QuadKey>& changed);
    // Whether `step` adds a curve or takes one back (a draw, its undo or redo).
    static bool addsOrTakesCurves(const LazyStep& step);
    // The same as moveInPlace for such a step, of roads only (no bridge): a curve the part's region
    // search finds now is added with its end nodes when every curve at them is held or comes with
    // it, it is no wider than a held road (the region's reach stays) and its rivers are held; one
    // taken back goes with its end nodes when no other held curve ends there; each the last ids of
    // their kinds, as the read after the step gives them. False, changing nothing, otherwise.
    bool growInPlace(Part& part, const LazyStep& step, StepRivers& rivers, std::set<QuadKey>& changed);
    // Whether the rivers road `road` (step index `k`) bridges are held by `part` (moveInPlace).
    bool riversHeld(const Part& part, const Curve& road, std::size_t k, StepRivers& rivers);
    // Applies `cs` (the part's ids; its scene already changed) through the curve data and UPDATE;
    // adds the keys of its quads whose tiles change to `changed`.
    void applyChangeset(Part& part, Changeset cs, std::set<QuadKey>& changed);
    // An edit's renew() arguments, kept while a read begun before it is in flight.
    struct Step {
        std::uint64_t version = 0;
        LazyStep step;
        double margin = 0.0;
    };
    void settle(Read& r);        // takes a finished read's part, or its refusal
    void evict(std::size_t keepBytes);  // drops parts not wanted now while held + keepBytes > budget
    double budgetLeft() const;   // MiB left beside the parts wanted now
    const Part* owner(const Quad& q) const;  // the part whose tree holds q (nullptr: the top tree)

    std::string path_;
    SceneFileConnection connection_;  // the file kept open for the reads of the session's thread
    std::string storedChecksum_;
    Quadtree* top_;
    const CurveDataCache* topData_;
    std::shared_ptr<const SceneOverlay> overlay_;
    std::uint64_t version_ = 0;
    const HeightField& heights_;
    const RefineParams refine_;
    const GraphStepParams graph_;
    const ZProfileParams profiles_;
    LazyParams lazy_;
    int level_ = 0;
    double partsBudgetMiB_ = 0.0;  // the vector budget less the top tree's
    std::map<QuadKey, std::unique_ptr<Part>> parts_;
    std::map<QuadKey, double> refused_;  // key -> the budget left (MiB) when it was refused
    std::vector<Read> reading_;          // at most one in background
    std::deque<Step> steps_;             // the edits since the oldest read in flight began
    std::vector<QuadKey> arrived_;
    std::set<QuadKey> wanted_;  // the parts' quads the last refine wanted
    std::uint64_t clock_ = 0;
    std::size_t held_ = 0;  // bytes
    LazyStats stats_;
};

}  // namespace lacet
