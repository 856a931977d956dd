#pragma once
// `lacet pyramid build` and `lacet pyramid update` (§7): the appearance and elevation tiles of
// every quad of levels minLevel..maxLevel of a scene, stored in a GeoPackage (pyramid/pyramid_store.h).
//
// Which tiles are made how:
// - elevation (z_m) at every level from vector data (the producer of §5.2: cheap, 25^2 samples a
//   quad), so every level's elevation is exact;
// - appearance at the `vectorLevels` deepest levels from vector data (§5.1), and each level above
//   them mipmapped from its children's stored tiles (decoded, so that an update, which decodes the
//   unchanged children from the file, gives the same bytes as a build).
// The work goes by subtrees: the quadtree is clipped down to `shardLevel` once; then each subtree
// below a quad of that level (a shard) is made depth first in passes of `passLevels` levels: a
// pass clips its subtree down to maxLevel, makes its tiles on all cores (TBB), encodes and writes
// them, and the subtree is merged again; a quad above the deepest pass is made after its four
// children's subtrees, one at a time (its mipmap from their stored tiles), so memory holds the
// clipped graphs of one path down the shard and one pass's tiles. The levels above the shards are
// made last, from the shards' stored tiles. Shards are independent: `lacet pyramid build --shards`
// runs them on the ranks of an MPI job (app/cmd_pyramid.cpp).
//
// An update is the same walk with the digests of the previous build (pyramid/quad_digest.h): a
// quad whose digest is unchanged keeps its tiles, unread; a mipmapped tile is remade when one of
// its children was; a remade tile is written only when its bytes differ. When the scene's DEM,
// layers or a knob changed (PyramidInfo::inputs), everything is remade; a pyramid of another
// extent or CRS is refused.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/document.h"
#include "io/tile_codec.h"
#include "model/progress.h"
#include "pyramid/pyramid_store.h"

namespace lacet {

// Limits of a pyramid run: quads of all its levels, and the shards' level (4^level shards).
inline constexpr double kMaxPyramidQuads = 268435456.0;  // 2^28 (levels 0-13)
inline constexpr int kMaxShardLevel = 12;

struct PyramidParams {
    int minLevel = 0;         // first level stored, >= 0
    int maxLevel = -1;        // last level stored, >= minLevel, <= 24; -1: the level whose texel is nearest `texel`
    double texel = 1.0;       // m per appearance texel the default maxLevel comes nearest to (by ratio), > 0
    int vectorLevels = 1;     // the deepest levels whose appearance is made from vector data (>= 1); the rest mipmapped
    // Level of the subtrees' roots, <= maxLevel and kMaxShardLevel; -1: max(0, maxLevel - 4), or
    // deeper where a shard would hold over `shardElements` of the scene's curves and areas (spread
    // evenly: a shard's part of a scene file is what a job over the file holds in memory).
    int shardLevel = -1;
    double shardElements = 200000.0;  // curves and areas, > 0: see shardLevel
    // Levels of a shard's subtree clipped and made at once (>= 1): a deeper shard goes depth first
    // (see above). Fewer: less memory, fewer quads made in parallel. Memory only: not stored with
    // the pyramid, no tile depends on it.
    int passLevels = 3;
    bool appearance = true, elevation = true;
    TileEncoding encoding{};
    // A streamed DEM's blocks held at once (MiB, > 0; io/dem_stream.h): each quad reads its window
    // at the level it needs (never the coarse level in memory), the least recently used blocks
    // dropped. Memory only: not stored with the pyramid, no tile depends on it.
    double demBudgetMiB = 512.0;
    // MiB of vector data a job over a scene file holds at once (> 0; model/graph.h's memoryBytes):
    // the part read for the levels above the shards, then the shards' parts, the next one read
    // ahead while a shard is made only when both fit. A part that alone would pass it is refused
    // (PyramidError naming the shard, the budget and what was read; a deeper shardLevel makes
    // smaller parts), its read stopped once it passes (io/scene_region.h: what is not counted).
    // The clipped quads made from a part are not counted (passLevels bounds them). Memory only:
    // not stored with the pyramid, no tile depends on it.
    double vectorBudgetMiB = 2048.0;
    // A job over a scene file: SQLite's quick_check of every page of the file before its first
    // read (io/scene_region.h: SceneRegionOptions::wholeFileCheck), O(file) in one read
    // transaction that a save waits for (99 s for a cold 3.6 GB file). A build reads most of the
    // file and checks it; an update (after a save) leaves it: SQLite still checks each page it
    // reads and every row read is checked. Not stored, no tile depends on it.
    bool wholeFileCheck = true;
    // The scene checksum the pyramid records (empty: the document's, io/scene_checksum.h). A job
    // over a document read whole from a scene file gives that file's stored text, whose form
    // follows the file's format, as a session reading the file lazily compares it. Not stored.
    std::string sceneChecksum;
    // Checks ranges (and the limits above) and fills the defaults for a scene of `extentSize`
    // metres a side holding `sceneElements` curves and areas; throws std::invalid_argument.
    void resolve(double extentSize, int tileSize, std::size_t sceneElements = 0);
    // The shallowest level whose appearance is made from vector data (the ones above are mipmapped).
    int vectorLevel() const { return std::max(minLevel, maxLevel - vectorLevels + 1); }
};

// Seconds summed over threads (a stage on two cores for one second counts two).
struct PyramidTimes {
    double clip = 0.0, digest = 0.0, elevation = 0.0, appearance = 0.0, mipmap = 0.0, encode = 0.0, decode = 0.0,
           write = 0.0;
    double dem = 0.0;  // a streamed DEM's windows: blocks read and cut
};

// A streamed DEM's reads (io/dem_stream.h) in a run.
struct PyramidDemStats {
    bool streamed = false;
    std::uint64_t windows = 0;    // one a quad made
    std::uint64_t fallbacks = 0;  // cut from a coarser level than the quad needs (a block that could not be read)
    std::vector<std::uint64_t> windowsAtLevel;  // windows cut from each level of the tree (0: the root)
    std::uint64_t blocksRead = 0, blocksEvicted = 0, blocksFailed = 0;
    double readSeconds = 0.0;     // reading and rebuilding blocks, summed over threads
};

struct PyramidStats {
    std::size_t quads = 0;            // quads of the stored levels
    std::size_t quadsChanged = 0;     // quads whose digest differed (all of them in a build)
    std::size_t tilesMade = 0;        // tiles produced, mipmapped or remade
    std::size_t tilesWritten = 0;     // tiles whose stored bytes changed (added, replaced or removed)
    std::size_t appearanceTiles = 0, waterTiles = 0, elevationTiles = 0;  // stored after the run
    std::uint64_t bytes = 0;          // of the stored tiles after the run
    bool rebuilt = false;             // an update that remade everything (inputs changed)
    std::size_t peakShardQuads = 0;   // the most quads below a shard's root clipped at once (PyramidParams::passLevels)
    double peakVectorMiB = 0.0;       // a job over a file: the most vector data held at once (parts read, MiB)
    double topVectorMiB = 0.0;        // of it, the part read for the levels above the shards
    double largestPartMiB = 0.0;      // the largest shard's part
    std::size_t readsNotAhead = 0;    // shards' parts not read ahead: with the one being made, over vectorBudgetMiB
    bool wholeFileChecked = false;    // a job over a scene file: SQLite's quick_check read every page first (PyramidParams::wholeFileCheck)
    PyramidTimes times;
    PyramidDemStats dem;
    double wallSeconds = 0.0;
};

// One run over a scene: the clipped tree to the shard level, the curve data and digests.
class PyramidJob {
public:
    // `previous`: the digests of the pyramid being updated (empty for a build).
    PyramidJob(const SceneDocument& doc, PyramidParams params, QuadDigestMap previous = {});
    // A job over the scene file at `scenePath`, out of core (§7): each shard reads only its part
    // of the file (io/scene_region.h: what its quads' tiles need, through the feature tables'
    // R-trees), the levels above the shards only what their tiles read (their elevation, when their
    // appearance is mipmapped: the curves wide enough to show and the water areas), and every quad
    // its DEM window; memory follows a shard, not the scene. The tiles and digests are those of a
    // job over the whole document. A file without the feature index is read whole, once.
    PyramidJob(const std::string& scenePath, PyramidParams params, QuadDigestMap previous = {});
    ~PyramidJob();
    const PyramidParams& params() const;
    PyramidInfo info() const;  // what the pyramid's lacet_pyramid says (complete = false)

    // The roots of the shards, in a fixed order.
    std::vector<PyramidKey> shards() const;
    // Makes the tiles of the shard's subtree (levels shardLevel..maxLevel that are stored) into
    // `store` (which must hold the pyramid, inside a transaction), and their digests.
    void runShard(const PyramidKey& shard, PyramidStore& store, Progress* progress);
    // runShard() for each of `shards` into one store, each shard's tiles written while the next
    // is made; returns when all are written.
    void runShards(const std::vector<PyramidKey>& shards, PyramidStore& store, Progress* progress);
    // The levels above the shards, from the shards' stored tiles at shardLevel.
    void runTop(PyramidStore& store, Progress* progress);
    // Tiles of the whole run, for the progress bar (every stored level's quads, both layers).
    std::size_t tileTotal() const;
    // Remakes every tile (an update whose inputs changed).
    void forgetPrevious();
    PyramidStats& stats();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// "png:1", "jpeg:90", "webp:90"; parseEncoding() reads them back (also "png", "jpeg", "webp" for the
// defaults) and throws std::invalid_argument naming the accepted forms.
std::string encodingName(const TileEncoding& e);
TileEncoding parseEncoding(const std::string& text);

// The default pyramid file of a scene file: "a/b.gpkg" -> "a/b.pyramid.gpkg".
std::string defaultPyramidPath(const std::string& scenePath);

// Builds the pyramid of `doc` into `out` in one transaction (a previous pyramid there stays
// readable until it commits; a new file is built beside `out` and renamed into place once
// committed, so that a build that fails or is killed leaves nothing at `out`). Refuses a pyramid of
// another scene in `out` unless `force`.
PyramidStats buildPyramid(const SceneDocument& doc, const std::string& out, PyramidParams params, bool force,
                          Progress* progress);
// The same from the scene file at `scenePath`, out of core (PyramidJob above).
PyramidStats buildPyramid(const std::string& scenePath, const std::string& out, PyramidParams params, bool force,
                          Progress* progress);

// Updates the pyramid at `path` to `doc` (knobs as stored; a streamed DEM's blocks within
// `demBudgetMiB`, PyramidParams::demBudgetMiB). Throws PyramidError when there is no
// pyramid, it is incomplete, or it was made for another extent or CRS.
PyramidStats updatePyramid(const SceneDocument& doc, const std::string& path, Progress* progress,
                           double demBudgetMiB = PyramidParams{}.demBudgetMiB, const std::string& sceneChecksum = {});
// The same from the scene file at `scenePath`, out of core (PyramidJob above), its vector data
// within `vectorBudgetMiB` (PyramidParams::vectorBudgetMiB).
PyramidStats updatePyramid(const std::string& scenePath, const std::string& path, Progress* progress,
                           double demBudgetMiB = PyramidParams{}.demBudgetMiB,
                           double vectorBudgetMiB = PyramidParams{}.vectorBudgetMiB);

// Throws PyramidError naming `path` when a stored pyramid was made for another extent or CRS than
// `wanted` (a build refuses to replace it without --force, an update refuses it).
void checkPyramidMatches(const PyramidInfo& stored, const PyramidInfo& wanted, const std::string& path);

// The parameters a stored pyramid was built with.
PyramidParams pyramidParams(const PyramidInfo& info);

}  // namespace lacet
