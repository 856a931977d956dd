#pragma once
// The DEM streamed from the scene file within a memory budget (issue 16; Lerbour, Marvie & Gautron,
// §6-§9): the blocks of the non-redundant LOD tree (io/dem_lod.h) that the view needs are loaded
// by a background thread, most important first, and the least useful are dropped when the blocks
// held pass the budget.
//
// Two uses. The editor streams (below); batch commands (the pyramid build, render) read each
// quad's window at once at the level it needs, windowNow(), within the same budget, the blocks
// used least recently dropped first: the same windows the editor's tiles end with, never a fixed
// coarse level (issue 23).
//
// Order of calls, each frame: beginFrame() (requests not renewed since the last frame are dropped:
// the queue follows the view), availableLevel() for the tiles made from a coarser level than they
// wanted (remade when it rose) and request() for those still waiting, then window() for every
// quad whose tiles are made. Any thread may call window(), request(), availableLevel() and
// heights(); one thread calls beginFrame() and setBudget().
//
// Windows. A producer asks for the DEM under a quad's box at the sample spacing it needs; it gets
// an in-memory Dem (raster/dem.h) of the box plus a margin of kWindowMargin samples, cut from
// the blocks of the level whose spacing is at most that (DemLodLayout::levelFor), or, while some
// of those blocks are not loaded, from the finest coarser level whose blocks are all there (the
// root block is always held, so every window is served). A window of the finest level is the same
// grid of samples as the whole DEM in memory (same values, the same cells).
//
// Importance: the caller gives each window a priority (lower is more important; the session uses
// the quad's distance to the viewer over its size, the K rule's ratio); a block missing from a
// window is requested with it, and its missing ancestors before it (a block is rebuilt from its
// parent). The loader takes the most important request first. When the blocks held would pass
// the budget it drops the block used longest ago (uses are counted one by one, so a z-profile
// walking a long curve drops the blocks it left behind first); it never drops the root, and it does not drop a block used in this frame for a request less important than
// that block's last use (the request waits: the view keeps the coarser level there).
//
// heights(): a HeightField (model/curve_data.h) for the z-profiles of curves, which must not change
// with the view: one fixed level, the coarsest whose spacing is at most `profileSpacing` (the
// z-profiles' own sample spacing, 10 m: finer samples would be smoothed away by their kernel); a
// block it needs and that is not held is read at once (synchronously) and counted.
//
// Units: positions in scene metres, heights in metres, the budget in MiB (2^20 bytes of samples).

#include <array>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>
#include <tuple>
#include <vector>

#include "io/dem_lod.h"
#include "io/document.h"
#include "model/curve_data.h"
#include "raster/dem.h"
#include "raster/dem_source.h"

namespace lacet {

struct DemStreamParams {
    // Memory of the blocks held (MiB): blockSide^2 floats a block (256 KiB for 256^2). At least the
    // root is held, whatever the budget; the z-profiles' reads hold up to a chain of blocks (one per
    // level) and 8 more when the budget is smaller than that.
    double budgetMiB = 512.0;
    // Whether a background thread loads the blocks; without it, load() loads them when called
    // (tests and benchmarks that want a deterministic order).
    bool background = true;
    // Metres between the DEM samples the z-profiles read (ZProfileParams::sampleSpacing, > 0): the
    // level heights() samples. Coarser reads fewer blocks synchronously, and follows the terrain less.
    double profileSpacing = 10.0;
};

// A block of the tree: (level, column, row from the top).
using DemBlockKey = std::tuple<int, int, int>;

// What the producers read of the DEM for a quad with bounds `quad`: a little beyond it (the
// elevation tile's border and the footprints' reach, the appearance's border, model/tile_grid.h;
// a quarter of the side covers both), at samples `spacing` metres apart: the quad's side over
// `samplesPerQuad` (the elevation tile has 24 intervals a side; the appearance's ground shading
// reads the slope between them). One rule for the editor and the batch commands.
inline constexpr double kDemSamplesPerQuad = 64.0;
struct DemNeed {
    Box box;
    double spacing = 0.0;
};
DemNeed quadDemNeed(const Box& quad, double samplesPerQuad = kDemSamplesPerQuad);

struct DemWindow {
    std::shared_ptr<const Dem> dem;
    int level = 0;   // the level it was cut from
    int wanted = 0;  // the level asked for
    bool complete() const { return level >= wanted; }
};

struct DemStreamStats {
    std::size_t held = 0;          // blocks in memory now
    double heldMiB = 0.0;
    std::size_t pending = 0;       // requests waiting
    std::uint64_t loaded = 0;      // blocks read in all (by the loader and synchronously)
    std::uint64_t loadedSync = 0;  // of which read at once (heights(), windowNow())
    std::uint64_t evicted = 0;
    std::uint64_t refused = 0;     // requests dropped because the budget holds more important blocks
    std::uint64_t failed = 0;      // block reads that failed (corrupt tile): their windows and heights stay coarser
    std::uint64_t windows = 0, fallbacks = 0;  // windows cut, and those from a coarser level than wanted
    std::array<std::uint64_t, kMaxDemLevels> windowsAtLevel{};  // windows cut from each level
    double loadMs = 0.0;           // time reading and rebuilding blocks
};

class DemStream {
public:
    // Reads the root block at once (throws what DemLodFile throws). Throws std::invalid_argument for
    // a budget that is not a positive finite number.
    DemStream(std::shared_ptr<const DemLodFile> file, DemStreamParams params = {});
    ~DemStream();
    DemStream(const DemStream&) = delete;
    DemStream& operator=(const DemStream&) = delete;

    const DemLodLayout& layout() const { return file_->layout(); }
    const DemStreamParams& params() const { return params_; }
    void setBudget(double budgetMiB);

    void beginFrame();
    // The DEM under `box` for samples `spacing` metres apart (see the header); requests what is
    // missing with `priority`.
    DemWindow window(const Box& box, double spacing, double priority);
    // The DEM under `box` for samples `spacing` metres apart, from the level asked for: the blocks
    // it needs that are not held are read now (the least recently used dropped to stay within
    // the budget, beyond it for the blocks this window needs at once). A block that cannot be
    // read leaves the window to the finest coarser level whose blocks can (counted in
    // stats().failed and fallbacks; DemWindow::complete() says so). Any thread may call it.
    DemWindow windowNow(const Box& box, double spacing);
    // Renews the requests of the blocks window() would want for `box` (for a tile made from a
    // coarser level, still shown, that waits for them).
    void request(const Box& box, double spacing, double priority);
    // Which level window() would cut now for `box` and `spacing` (no request).
    int availableLevel(const Box& box, double spacing) const;
    // Without a background thread: takes up to `count` requests, most important first (loading
    // them, or refusing them for the budget); returns how many it took. With one, waits until the
    // queue is empty and nothing is being read (`count` is ignored), and returns 0.
    std::size_t load(std::size_t count = SIZE_MAX);
    DemStreamStats stats() const;

    const HeightField& heights() const { return heights_; }
    int profileLevel() const { return heights_.level(); }
    // The box (scene metres) a block's samples cover, cells centred on them.
    Box blockBox(const DemBlockKey& key) const;

private:
    struct Block {
        std::shared_ptr<const std::vector<float>> samples;
        std::uint64_t lastUsed = 0;  // the frame of its last use
        std::uint64_t tick = 0;      // the order of its last use (the LRU's clock: finer than frames)
        double priority = 0.0;  // of its last use
    };
    class ProfileHeights : public HeightField {
    public:
        ProfileHeights(DemStream& s, int level) : s_(&s), level_(level) {}
        double height(Vec2 p) const override;
        int level() const { return level_; }
    private:
        DemStream* s_;
        int level_;
    };
    // The level-l sample range covering `box` with the margin: [k0, k1) x [r0, r1), clamped.
    std::array<int, 4> range(const Box& box, int level) const;
    // The blocks of `level` that hold a range of range().
    std::vector<DemBlockKey> blocksOf(int level, const std::array<int, 4>& rg) const;
    void enqueue(const DemBlockKey& key, double priority);  // under mutex_: requested, the most important priority kept
    // Reads a block and its missing ancestors (outside the lock) and inserts them, evicting to fit;
    // nullptr when the budget refuses them (never with `sync`, which reads them even so). Throws
    // what DemLodFile throws, and for a block that failed before (the failing one is remembered).
    std::shared_ptr<const std::vector<float>> fetch(const DemBlockKey& key, double priority, bool sync);
    // Under mutex_: evicts until `count` more blocks fit, the least useful first (see the header);
    // without `force`, evicts nothing and returns false when a victim would be a block this frame
    // used for a request at least as important as `priority`. False when only the root is left.
    // `capacity`: the blocks allowed, at least the budget's.
    bool makeRoom(std::size_t count, double priority, bool force, std::size_t capacity = 0);
    // What the z-profiles' synchronous reads may hold under a smaller budget: a chain and
    // kProfileSpare blocks more.
    static constexpr std::size_t kProfileSpare = 8;
    std::size_t profileFloor() const;
    Dem cut(int level, const std::array<int, 4>& r, const std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>>& blocks) const;
    // The blocks of `level` over `rg`, those not held read at once (fetch with sync) for a use of
    // importance `priority`; throws when one cannot be read.
    std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>> readNow(int level, const std::array<int, 4>& rg, double priority);
    void loaderLoop();
    bool loadOne();
    // The height at p from the blocks of `level` (read at once when not held); throws when one
    // cannot be read.
    double sampleLevel(int level, Vec2 p);

    std::shared_ptr<const DemLodFile> file_;
    DemStreamParams params_;
    ProfileHeights heights_;
    mutable std::mutex mutex_;
    std::condition_variable wake_, idle_;
    std::map<DemBlockKey, Block> blocks_;
    std::map<DemBlockKey, double> requests_;  // block -> priority (lowest wins)
    std::set<DemBlockKey> failed_;            // blocks that could not be read: never asked again
    std::map<DemBlockKey, std::uint64_t> refused_;  // blocks the budget refused, and the frame it did
    // A refused block is asked again when the blocks in use change (a still view comes to rest:
    // nothing pending), or after this many frames.
    static constexpr std::uint64_t kRetryRefusedFrames = 60;
    bool usedChanged_ = false;  // a block was used this frame that the last frame did not use
    std::size_t usedThisFrame_ = 0, usedLastFrame_ = 0;  // blocks used
    // The importance of the z-profiles' reads (they cannot wait), and of batch windows
    // (windowNow(): the least recently used go first, the profiles' blocks after them).
    static constexpr double kProfilePriority = -1.0;
    static constexpr double kBatchPriority = 0.0;
    void touch(Block& b, double priority);  // under mutex_: used now
    bool wants(const DemBlockKey& key) const;  // under mutex_: neither failed nor refused lately
    std::uint64_t frame_ = 1, tick_ = 0;
    std::size_t maxBlocks_ = 1;
    std::size_t inFlight_ = 0;
    DemStreamStats stats_;
    bool stop_ = false;
    std::thread loader_;
};

// A streamed DEM read in batch (raster/dem_source.h): each quad's window read at once at the
// level it needs (windowNow, quadDemNeed), the z-profiles from the stream's fixed level.
class StreamedDem final : public DemSource {
public:
    // Throws what DemStream's constructor throws.
    StreamedDem(std::shared_ptr<const DemLodFile> file, double budgetMiB);
    const HeightField& heights() const override { return stream_.heights(); }
    std::shared_ptr<const Dem> quadDem(const Quad& q) const override;
    DemStreamStats stats() const { return stream_.stats(); }

private:
    mutable DemStream stream_;
};

// The DEM a batch command reads of `doc`: its LOD tree streamed within `budgetMiB` when it has
// one (never the coarse level held in memory), else its DEM in memory, else flat ground at 0 m
// over the scene. The document must outlive it.
std::unique_ptr<DemSource> batchDemSource(const SceneDocument& doc, double budgetMiB);

}  // namespace lacet
