#include "pyramid/pyramid_build.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>
#include <iomanip>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include <tbb/parallel_for.h>
#include <tbb/parallel_for_each.h>
#include <tbb/task_group.h>

#include "io/dem_stream.h"
#include "io/scene_checksum.h"
#include "io/scene_region.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "io/digest.h"
#include "pyramid/pyramid_tiles.h"
#include "pyramid/quad_digest.h"
#include "raster/appearance_producer.h"
#include "raster/elevation_producer.h"

namespace lacet {
namespace {

using Clock = std::chrono::steady_clock;

// Nanoseconds summed over threads.
struct StageClock {
    std::atomic<std::int64_t> ns{0};
    template <class F>
    auto time(F&& f) {
        const auto t0 = Clock::now();
        struct Add {
            std::atomic<std::int64_t>& ns;
            Clock::time_point t0;
            ~Add() { ns += std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count(); }
        } add{ns, t0};
        return f();
    }
    double seconds() const { return double(ns.load()) * 1e-9; }
};

struct KeySet {
    std::unordered_set<PyramidKey, PyramidKeyHash> set;
    bool has(const PyramidKey& k) const { return set.count(k) != 0; }
};

PyramidKey keyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

// Every setting a tile depends on besides the scene's vector data.
std::uint64_t inputsDigest(const SceneDocument& doc, const PyramidParams& p, const RefineParams& refine,
                           const ZProfileParams& z, const GraphStepParams& g, const AppearanceParams& a) {
    Digest d;
    d.word(kPyramidFormatVersion).word(kQuadDigestVersion).text(encodingName(p.encoding)).word(std::uint64_t(p.minLevel)).word(std::uint64_t(p.maxLevel));
    d.word(std::uint64_t(p.vectorLevels)).word(p.appearance).word(p.elevation);
    const Scene& s = doc.scene;
    d.real(s.extent.min.x).real(s.extent.min.y).real(s.extent.max.x).real(s.extent.max.y).word(s.layers.size());
    for (const Layer& l : s.layers) d.text(l.name).word(std::uint64_t(l.kind));
    if (doc.demLod) {
        // A streamed DEM: its tree (each quad reads its window at the level it needs, the
        // z-profiles their fixed level), not the coarse level held in memory.
        const DemLodLayout& l = doc.demLod->layout();
        d.text("dem_lod").word(std::uint64_t(l.width)).word(std::uint64_t(l.height)).real(l.cell).real(l.origin.x).real(l.origin.y);
        d.word(std::uint64_t(l.blockSide)).text(doc.demLod->digest()).real(kDemSamplesPerQuad).real(DemStreamParams{}.profileSpacing);
    } else if (doc.dem) {
        const Dem& dem = *doc.dem;
        d.real(dem.extent().min.x).real(dem.extent().min.y).real(dem.extent().max.x).real(dem.extent().max.y);
        d.word(std::uint64_t(dem.width())).word(std::uint64_t(dem.height())).reals(std::span<const float>(dem.heights()));
    }
    d.word(std::uint64_t(refine.resolution)).word(std::uint64_t(refine.appearanceBorder));
    d.word(std::uint64_t(refine.elevationResolution)).word(std::uint64_t(refine.elevationBorder)).real(refine.toleranceTexels);
    d.real(z.sampleSpacing).real(z.kernelRadius).real(z.arcLengthTolerance);
    d.real(g.crossingTolerance).real(g.abutmentLength).real(g.clearance).real(g.deckThickness).word(g.bridges);
    d.real(g.minBridgedRiverWidth);
    d.word(std::uint64_t(a.samples)).real(a.markingMinTexels).word(std::uint64_t(a.groundCells)).real(a.groundCellMin);
    d.word(a.detectUniform).real(a.tunnelPortalLength);
    return d.value();
}

// A tile made in this run, ready to store.
struct MadeTile {
    std::vector<std::uint8_t> appearance, water;  // water empty: none
    PyramidImage half;                             // at half size as read back from the file: what the parent assembles
    bool hasAppearance = false;
    std::vector<std::uint8_t> elevation;
    ElevationCells cells;
    bool hasElevation = false;
};

// The scene a job's tiles are made from, clipped: the caller's whole document, or a part of a
// scene file (io/scene_region.h) read for the levels above the shards or for one shard. Every
// model reads the job's one DEM source.
struct SceneModel {
    SceneDocument part;  // the part read (empty when the model borrows a document)
    const SceneDocument& doc;
    GraphStep graphStep;
    Quadtree qt;
    CurveDataCache data;
    QuadDigests digests;
    SceneModel(const SceneDocument* borrowed, SceneDocument read, const RefineParams& refine, const HeightField& heights)
        : part(std::move(read)),
          doc(borrowed ? *borrowed : part),
          graphStep(doc.scene),
          qt(doc.scene, refine, &graphStep),
          data(qt, heights),
          digests(qt, data) {}
};

// What the levels above the shards read of a scene file: their elevation only, when their
// appearance is mipmapped (the road and river curves at least two elevation samples wide at the
// deepest of them, lakes and river areas, and what those depend on), else everything; with the
// DEM.
struct TopPart {
    SceneDocument doc;
    std::string checksum;       // the file's stored checksum
    bool whole = false;         // the file has no feature index and was read whole
    std::size_t elements = 0;   // the file's curves and areas (loadSceneOutline)
    std::size_t bytes = 0;      // doc's vector data (SceneRegionStats::bytes)
};
TopPart readTopPart(const std::string& path, PyramidParams params, const RefineParams& refine) {
    TopPart top;
    const SceneOutline outline = loadSceneOutline(path);
    const Box extent = outline.extent;
    top.elements = outline.elements;
    params.resolve(extent.size().x, refine.resolution, top.elements);
    const int deepest = std::max(0, params.shardLevel - 1);
    SceneRegionOptions filter;
    filter.elevationOnly = params.vectorLevel() >= params.shardLevel || !params.appearance;
    const double quad = extent.size().x / double(std::int64_t(1) << deepest);
    filter.minCurveWidth = 2.0 * quad / double(refine.elevationResolution);
    filter.wholeFileCheck = params.wholeFileCheck;  // a build reads most of the file: every page checked once, first
    filter.budgetMiB = params.vectorBudgetMiB;
    SceneRegionStats st;
    try {
        top.doc = loadSceneRegion(path, extent, refine, deepest, &st, filter);
    } catch (const SceneBudgetError& e) {
        throw PyramidError(std::string(e.what()) + ": the read for the levels above the shards (" + std::to_string(deepest) +
                           " and up) does not fit in --vector-budget; raise it");
    }
    top.bytes = st.bytes;
    top.checksum = st.checksum;
    top.whole = st.wholeScene;
    return top;
}

}  // namespace

struct PyramidJob::Impl {
    PyramidParams params;
    QuadDigestMap previous;
    RefineParams refine;
    // A job over a scene file (not empty): each shard reads its part of it; the levels above read
    // topPart. Otherwise the caller's whole document.
    std::string scenePath;
    bool fromFile = false;  // a job over a scene file (its read of the levels above checks it whole when asked)
    std::string fileChecksum;  // the scene file's stored checksum (a job over a file, or PyramidParams::sceneChecksum)
    std::size_t fileElements = 0;  // its curves and areas (the default shard level)
    std::size_t topBytes = 0;      // topPart's vector data (model/graph.h: memoryBytes)
    SceneDocument topPart;
    const SceneDocument& doc;  // the caller's document, or topPart
    // Each quad's DEM and the z-profiles' heights: a streamed DEM's (doc.demLod) window at the level
    // the quad needs within params.demBudgetMiB, as the editor reads it; else the DEM in memory,
    // else flat ground at 0 m.
    std::unique_ptr<DemSource> demSource;
    std::unique_ptr<SceneModel> top;  // the model of `doc`: the shards (whole document) and the levels above
    SceneModel* cur = nullptr;        // the model being made: `top`, or a shard's part
    AppearanceParams appearanceParams;
    ElevationParams elevationParams;
    PyramidStats stats;
    StageClock clip, digest, elevation, appearance, mipmap, encode, decode, write;
    StageClock demRead;  // the streamed DEM's windows (reads and cuts)
    std::mutex remadeMutex;
    KeySet remade;  // an update's appearance tiles remade at the roots of passes (the mipmaps above read them)
    Progress* progress = nullptr;
    bool deferWrites = false;          // runShards(): a shard's tiles are written while the next is made
    std::future<void> pendingWrite;    // that write

    Impl(const SceneDocument& d, PyramidParams p, QuadDigestMap prev)
        : params(p),
          previous(std::move(prev)),
          fileChecksum(p.sceneChecksum),
          doc(d),
          demSource(batchDemSource(d, p.demBudgetMiB)),
          top(std::make_unique<SceneModel>(&d, SceneDocument{}, refine, demSource->heights())),
          cur(top.get()) {
        std::size_t elements = 0;
        for (const Layer& l : d.scene.layers) elements += l.curves.size() + l.areas.size();
        params.resolve(d.scene.extent.size().x, refine.resolution, elements);
    }

    Impl(const std::string& path, PyramidParams p, QuadDigestMap prev)
        : params(p), previous(std::move(prev)), scenePath(path), fromFile(true), topPart(readTop(path, p)), doc(topPart),
          demSource(batchDemSource(topPart, p.demBudgetMiB)),
          top(std::make_unique<SceneModel>(&topPart, SceneDocument{}, refine, demSource->heights())),
          cur(top.get()) {
        params.resolve(doc.scene.extent.size().x, refine.resolution, fileElements);
        stats.topVectorMiB = toMiB(topBytes);
        noteHeld(topBytes);
    }

    SceneDocument readTop(const std::string& path, const PyramidParams& p) {
        TopPart read = readTopPart(path, p, refine);
        fileChecksum = std::move(read.checksum);
        fileElements = read.elements;
        topBytes = read.bytes;
        if (read.whole) scenePath.clear();  // no feature index: read whole once, the shards made from it
        return std::move(read.doc);
    }

    // Makes the tiles of `shard`'s subtree from `part` (a job over a file) or from the whole
    // document's tree (merged again after).
    void runShardOn(const PyramidKey& shard, std::unique_ptr<SceneModel> part, PyramidStore& store) {
        if (part) cur = part.get();
        struct Back {
            Impl& m;
            ~Back() { m.cur = m.top.get(); }
        } back{*this};
        Quad& root = quadAt(shard);
        heldQuads = 0;
        makeSubtree(root, store);
        if (!part) top->qt.merge(root);
    }

    // Makes the tiles of q's subtree (PyramidParams::passLevels): within a pass's depth at once;
    // deeper, each child's subtree in turn, merged once made, then q alone (its mipmap from its
    // children's stored tiles). Leaves q's children to the caller to merge; returns how many quads
    // below q it clipped (held until then).
    std::size_t makeSubtree(Quad& q, PyramidStore& store) {
        const int levels = params.maxLevel - q.level + 1;
        if (levels <= params.passLevels) {
            clip.time([&] { subdivideAll(q); });
            std::vector<std::vector<Quad*>> byLevel(static_cast<std::size_t>(levels));
            collect(q, byLevel, q.level);
            std::size_t below = 0;
            for (std::size_t i = 1; i < byLevel.size(); ++i) below += byLevel[i].size();
            hold(below);
            makeLevels(byLevel, q.level, store, false);
            return below;
        }
        std::size_t below = 0;
        if (q.isLeaf()) {
            clip.time([&] { cur->qt.subdivide(q); });
            hold(below = 4);
        }
        for (auto& c : q.children) {
            const std::size_t its = makeSubtree(*c, store);
            cur->qt.merge(*c);
            heldQuads -= its;
        }
        std::vector<std::vector<Quad*>> byLevel{{&q}};
        makeLevels(byLevel, q.level, store, false);
        return below;
    }

    std::size_t heldQuads = 0;  // below the shard's root
    void hold(std::size_t quads) {
        heldQuads += quads;
        stats.peakShardQuads = std::max(stats.peakShardQuads, heldQuads);
    }

    // Vector data held (params.vectorBudgetMiB): `bytes` of the top part and the shards' parts in
    // memory now; the largest seen is stats.peakVectorMiB.
    std::mutex heldMutex;
    void noteHeld(std::size_t bytes) {
        const std::lock_guard lock(heldMutex);
        stats.peakVectorMiB = std::max(stats.peakVectorMiB, toMiB(bytes));
    }

    // A shard's part of the scene file: what the tiles of its quads need (io/scene_region.h),
    // within `budgetMiB` of vector data (SceneBudgetError past it) and its bytes in `bytes`.
    // Thread-safe (it reads the file on its own connection): runShards() reads the next while one
    // is made.
    std::unique_ptr<SceneModel> shardModel(const Box& bounds, int level, double budgetMiB, std::size_t& bytes) {
        SceneRegionOptions filter;
        filter.dem = false;              // the job's DEM source serves every model
        filter.wholeFileCheck = false;   // done once, by the read of the levels above
        filter.budgetMiB = budgetMiB;
        // The shard's quad alone: a box inside it (its neighbours, which touch its border, are
        // other shards).
        const Box inside = bounds.dilated(-1e-3 * bounds.size().x);
        SceneRegionStats st;
        SceneDocument part = clip.time([&] { return loadSceneRegion(scenePath, inside, refine, level, &st, filter); });
        bytes = st.bytes;
        {
            const std::lock_guard lock(heldMutex);
            stats.largestPartMiB = std::max(stats.largestPartMiB, toMiB(bytes));
        }
        return std::make_unique<SceneModel>(nullptr, std::move(part), refine, demSource->heights());
    }
    // The same with all of the budget the top part leaves, refused with the figure and the way out.
    std::unique_ptr<SceneModel> shardModelAlone(const PyramidKey& shard, const Box& bounds, std::size_t& bytes) {
        try {
            return shardModel(bounds, shard.level, budgetLeft(0), bytes);
        } catch (const SceneBudgetError& e) {
            std::ostringstream m;
            m << std::fixed << std::setprecision(2) << "shard " << shard.level << "/" << shard.tx << "/" << shard.ty
              << "'s part does not fit in --vector-budget " << params.vectorBudgetMiB << " MiB beside the "
              << toMiB(topBytes) << " MiB of the levels above the shards (" << e.what()
              << "); a deeper --shard-level (now " << params.shardLevel << ") makes smaller parts, or raise --vector-budget";
            throw PyramidError(m.str());
        }
    }
    // MiB of the vector budget left beside the top part and `held` bytes of another part (at
    // least a byte's worth: a read with nothing left is refused at its first element).
    double budgetLeft(std::size_t held) const {
        return std::max(toMiB(1), params.vectorBudgetMiB - toMiB(topBytes + held));
    }

    int vectorLevel() const { return params.vectorLevel(); }
    bool stored(int level) const { return level >= params.minLevel && level <= params.maxLevel; }
    bool lossless() const { return params.encoding.format == TileFormat::Png; }

    Quad& quadAt(const PyramidKey& k) {
        Quad* q = &cur->qt.root();
        for (int l = 0; l < k.level; ++l) {
            if (q->isLeaf()) clip.time([&] { cur->qt.subdivide(*q); });
            const int shift = k.level - l - 1;
            const int child = int((k.tx >> shift) & 1) + 2 * int((k.ty >> shift) & 1);
            q = q->children[std::size_t(child)].get();
        }
        return *q;
    }

    // Subdivides q's subtree down to maxLevel, subtrees on TBB tasks.
    void subdivideAll(Quad& q) {
        if (q.level >= params.maxLevel) return;
        cur->qt.subdivide(q);
        tbb::parallel_for(0, 4, [&](int k) { subdivideAll(*q.children[std::size_t(k)]); });
    }

    static void collect(Quad& q, std::vector<std::vector<Quad*>>& byLevel, int base) {
        byLevel[std::size_t(q.level - base)].push_back(&q);
        if (!q.isLeaf())
            for (auto& c : q.children) collect(*c, byLevel, base);
    }

    // Encodes a tile's appearance into `t`; with keepForParent, also its image at half size as its
    // parent reads it back from the file (decodeImageHalf of a lossy tile; the exact halve() of a
    // lossless one).
    void encodeImage(const PyramidImage& image, bool keepForParent, MadeTile& t) {
        t.hasAppearance = true;
        encode.time([&] {
            t.appearance = encodeRgb(image.rgb, image.size, image.size, params.encoding);
            if (image.hasWater()) t.water = encodeGreyPng(image.water, image.size, image.size, 1);
        });
        if (keepForParent) {
            t.half = mipmap.time([&] { return halve(image); });
            if (!lossless()) {
                decode.time([&] {
                    DecodedImage d = decodeImageHalf(t.appearance);
                    t.half.rgb = std::move(d.pixels);
                });
            }
        }
    }

    // The stored tile at half size, as encodeImage() keeps it (colour decoded, water from its tile
    // or none).
    PyramidImage storedHalf(PyramidStore& store, const PyramidKey& k) {
        return decode.time([&] {
            const auto where = [&] { return std::to_string(k.level) + "/" + std::to_string(k.tx) + "/" + std::to_string(k.ty); };
            auto bytes = store.tile(kAppearanceTable, k);
            if (!bytes)
                throw PyramidError(store.path() + ": appearance tile " + where() + " is missing (an incomplete pyramid: build it again)");
            const int h = refine.resolution / 2;
            DecodedImage d = decodeImageHalf(*bytes);
            if (d.width != h || d.height != h || d.channels != 3)
                throw PyramidError(store.path() + ": appearance tile " + where() + " is not " + std::to_string(2 * h) + "x" +
                                   std::to_string(2 * h) + " RGB");
            PyramidImage image;
            image.size = h;
            image.rgb = std::move(d.pixels);
            image.water.assign(std::size_t(h) * std::size_t(h), 0);
            if (auto w = store.tile(kWaterTable, k)) {
                DecodedImage m = decodeImageHalf(*w);
                if (m.width != h || m.height != h || m.channels != 1)
                    throw PyramidError(store.path() + ": water tile " + where() + " is not " + std::to_string(2 * h) + "x" +
                                       std::to_string(2 * h) + " grey");
                image.water = std::move(m.pixels);
            }
            return image;
        });
    }

    // Makes the tiles of a pass: `byLevel` (byLevel[i] holds level base + i; the deepest last);
    // a mipmapped quad whose children are not in it reads them from the store, made by an earlier
    // pass (the shards below the top pass, the children's subtrees of a deep shard's quad).
    void makeLevels(std::vector<std::vector<Quad*>>& byLevel, int base, PyramidStore& store, bool topPass) {
        const int vl = vectorLevel();
        std::vector<std::pair<Quad*, std::size_t>> all;
        for (auto& level : byLevel)
            for (Quad* q : level) all.push_back({q, 0});
        // Digests.
        std::vector<std::uint64_t> dig(all.size());
        std::vector<char> changed(all.size());
        tbb::parallel_for(std::size_t(0), all.size(), [&](std::size_t i) {
            // Below the vector levels only the elevation follows from the quad's graph.
            const QuadDigestScope scope = all[i].first->level < vl ? QuadDigestScope::Elevation : QuadDigestScope::All;
            dig[i] = digest.time([&] { return cur->digests.of(*all[i].first, scope); });
            auto it = previous.find(keyOf(*all[i].first));
            changed[i] = it == previous.end() || it->second != dig[i];
        });
        std::unordered_map<const Quad*, std::size_t> index;
        for (std::size_t i = 0; i < all.size(); ++i) index[all[i].first] = i;
        std::vector<MadeTile> made(all.size());
        // Elevation at every level, appearance at the vector levels: from vector data.
        tbb::parallel_for(std::size_t(0), all.size(), [&](std::size_t i) {
            Quad& q = *all[i].first;
            if (!stored(q.level) || !changed[i]) return;
            std::shared_ptr<const Dem> quadDem;
            if (params.elevation || (params.appearance && q.level >= vl)) quadDem = demRead.time([&] { return demSource->quadDem(q); });
            const Quadtree& qt = cur->qt;
            const CurveDataCache& data = cur->data;
            if (params.elevation) {
                ElevationTile t = elevation.time([&] { return produceElevation(q, qt, data, *quadDem, elevationParams); });
                MadeTile& m = made[i];
                m.cells = elevationCells(t);
                m.elevation = encode.time([&] { return encodeFloatTiff(m.cells.z, m.cells.size, m.cells.size); });
                m.hasElevation = true;
                progressAdvance(progress);
            }
            if (params.appearance && q.level >= vl) {
                AppearanceTile t = appearance.time([&] { return produceAppearance(q, qt, data, *quadDem, appearanceParams); });
                encodeImage(pyramidImage(t), q.level > params.minLevel && q.level <= vl, made[i]);
                progressAdvance(progress);
            }
        });
        // Mipmapped levels, bottom up. They may read children from the store (an update's
        // unchanged ones, those of an earlier pass): the writes in flight go first.
        const bool earlierChildren = base + int(byLevel.size()) - 1 < params.maxLevel;  // the deepest level's
        if (earlierChildren || !previous.empty()) flushWrites();
        if (params.appearance) {
            for (int li = int(byLevel.size()) - 1; li >= 0; --li) {
                const int level = base + li;
                if (level >= vl || !stored(level)) continue;
                auto& quads = byLevel[std::size_t(li)];
                // Children images not made in this pass come from the store (an update's unchanged
                // children; those of an earlier pass).
                tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t qi) {
                    Quad& q = *quads[qi];
                    const std::size_t i = index.at(&q);
                    std::array<PyramidImage, 4> loaded;
                    std::array<const PyramidImage*, 4> kids{};
                    bool any = false;
                    for (int k = 0; k < 4; ++k) {
                        const PyramidKey ck{q.level + 1, q.tx * 2 + std::uint32_t(k & 1), q.ty * 2 + std::uint32_t(k >> 1)};
                        const Quad* c = q.isLeaf() ? nullptr : q.children[std::size_t(k)].get();
                        auto it = c ? index.find(c) : index.end();
                        if (it != index.end() && made[it->second].hasAppearance) {
                            kids[std::size_t(k)] = &made[it->second].half;
                            any = true;
                        } else {
                            // The root of an earlier pass (a shard, below the top pass, on
                            // whichever rank): remade in a build, in an update when its pass
                            // remade it.
                            if (it == index.end()) {
                                std::lock_guard lock(remadeMutex);
                                any = any || previous.empty() || remade.has(ck);
                            }
                            kids[std::size_t(k)] = nullptr;
                        }
                    }
                    if (!any) return;
                    for (int k = 0; k < 4; ++k)
                        if (!kids[std::size_t(k)]) {
                            const PyramidKey ck{q.level + 1, q.tx * 2 + std::uint32_t(k & 1), q.ty * 2 + std::uint32_t(k >> 1)};
                            loaded[std::size_t(k)] = storedHalf(store, ck);
                            kids[std::size_t(k)] = &loaded[std::size_t(k)];
                        }
                    const PyramidImage image = mipmap.time([&] { return assemble(kids); });
                    encodeImage(image, q.level > params.minLevel, made[i]);
                    progressAdvance(progress);
                });
            }
        }
        // Unchanged tiles count as done for the progress bar.
        std::size_t skipped = 0;
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (!stored(all[i].first->level)) continue;
            if (params.elevation && !made[i].hasElevation) ++skipped;
            if (params.appearance && !made[i].hasAppearance) ++skipped;
        }
        progressAdvance(progress, skipped);
        // Write, in one thread (SQLite): now, or while the next shard is made (deferWrites).
        auto batch = std::make_shared<WriteBatch>();
        batch->rootLevel = topPass ? -1 : base;
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (!stored(all[i].first->level)) continue;
            batch->keys.push_back(keyOf(*all[i].first));
            batch->changed.push_back(changed[i]);
            batch->digests.push_back(dig[i]);
            batch->made.push_back(std::move(made[i]));
        }
        flushWrites();
        if (deferWrites && !topPass) pendingWrite = std::async(std::launch::async, [this, batch, &store] { writeBatch(*batch, store); });
        else writeBatch(*batch, store);
    }

    struct WriteBatch {
        std::vector<PyramidKey> keys;
        std::vector<char> changed;
        std::vector<std::uint64_t> digests;
        std::vector<MadeTile> made;
        int rootLevel = -1;  // the pass's root's level (update: a later pass's mipmap asks if it was remade); -1: the top pass
    };

    void writeBatch(WriteBatch& b, PyramidStore& store) {
        write.time([&] {
            for (std::size_t i = 0; i < b.keys.size(); ++i) {
                const PyramidKey& k = b.keys[i];
                ++stats.quads;
                if (b.changed[i]) {
                    ++stats.quadsChanged;
                    store.putDigest(k, b.digests[i]);
                }
                MadeTile& m = b.made[i];
                if (m.hasElevation) {
                    ++stats.tilesMade;
                    if (store.putElevation(k, m.elevation, m.cells.min, m.cells.max, m.cells.mean, m.cells.stdDev)) ++stats.tilesWritten;
                }
                if (m.hasAppearance) {
                    stats.tilesMade += 1;
                    if (store.putTile(kAppearanceTable, k, m.appearance)) ++stats.tilesWritten;
                    if (!m.water.empty()) {
                        if (store.putTile(kWaterTable, k, m.water)) ++stats.tilesWritten;
                    } else if (store.removeTile(kWaterTable, k)) {
                        ++stats.tilesWritten;
                    }
                    if (k.level == b.rootLevel && !previous.empty()) {
                        std::lock_guard lock(remadeMutex);
                        remade.set.insert(k);
                    }
                }
            }
        });
    }

    // Waits for the write in flight, if any; rethrows its error.
    void flushWrites() {
        if (!pendingWrite.valid()) return;
        std::future<void> f = std::move(pendingWrite);
        f.get();
    }
};

PyramidJob::PyramidJob(const SceneDocument& doc, PyramidParams params, QuadDigestMap previous)
    : impl_(std::make_unique<Impl>(doc, params, std::move(previous))) {}
PyramidJob::PyramidJob(const std::string& scenePath, PyramidParams params, QuadDigestMap previous)
    : impl_(std::make_unique<Impl>(scenePath, params, std::move(previous))) {}
PyramidJob::~PyramidJob() = default;
void PyramidJob::forgetPrevious() { impl_->previous.clear(); }
const PyramidParams& PyramidJob::params() const { return impl_->params; }
PyramidStats& PyramidJob::stats() {
    auto& s = impl_->stats;
    s.wholeFileChecked = impl_->fromFile && impl_->params.wholeFileCheck;
    s.times = {impl_->clip.seconds(),   impl_->digest.seconds(), impl_->elevation.seconds(), impl_->appearance.seconds(),
               impl_->mipmap.seconds(), impl_->encode.seconds(), impl_->decode.seconds(),    impl_->write.seconds(),
               impl_->demRead.seconds()};
    if (const auto* streamed = dynamic_cast<const StreamedDem*>(impl_->demSource.get())) {
        const DemStreamStats d = streamed->stats();
        s.dem = {true, d.windows, d.fallbacks, {}, d.loaded, d.evicted, d.failed, d.loadMs / 1000.0};
        s.dem.windowsAtLevel.assign(d.windowsAtLevel.begin(), d.windowsAtLevel.end());
        while (!s.dem.windowsAtLevel.empty() && s.dem.windowsAtLevel.back() == 0) s.dem.windowsAtLevel.pop_back();
    }
    return s;
}

PyramidInfo PyramidJob::info() const {
    const Impl& m = *impl_;
    PyramidInfo i;
    i.minLevel = m.params.minLevel;
    i.maxLevel = m.params.maxLevel;
    i.vectorLevel = m.vectorLevel();
    i.appearance = m.params.appearance;
    i.elevation = m.params.elevation;
    i.tileSize = m.refine.resolution;
    i.elevationSize = m.refine.elevationResolution;
    i.encoding = encodingName(m.params.encoding);
    i.extent = m.doc.scene.extent;
    i.crsWkt = m.doc.georeference.valid ? m.doc.georeference.crsWkt : std::string();
    i.inputs = inputsDigest(m.doc, m.params, m.refine, m.top->data.params(), m.top->graphStep.params(), m.appearanceParams);
    i.sceneChecksum = m.fileChecksum.empty() ? sceneChecksumText(m.doc) : m.fileChecksum;
    return i;
}

std::vector<PyramidKey> PyramidJob::shards() const {
    const int s = impl_->params.shardLevel;
    std::vector<PyramidKey> out;
    const std::uint32_t n = std::uint32_t(1) << s;
    for (std::uint32_t ty = 0; ty < n; ++ty)
        for (std::uint32_t tx = 0; tx < n; ++tx) out.push_back({s, tx, ty});
    return out;
}

std::size_t PyramidJob::tileTotal() const {
    const Impl& m = *impl_;
    std::size_t quads = 0;
    for (int l = m.params.minLevel; l <= m.params.maxLevel; ++l) quads += std::size_t(1) << (2 * l);
    return quads * (std::size_t(m.params.appearance) + std::size_t(m.params.elevation));
}

void PyramidJob::runShard(const PyramidKey& shard, PyramidStore& store, Progress* progress) {
    Impl& m = *impl_;
    m.progress = progress;
    // A job over a file: the shard's own part of it (the tree above, clipped to the shards, gives
    // its bounds).
    std::size_t bytes = 0;
    std::unique_ptr<SceneModel> part = m.scenePath.empty() ? nullptr : m.shardModelAlone(shard, m.quadAt(shard).bounds, bytes);
    m.noteHeld(m.topBytes + bytes);
    m.runShardOn(shard, std::move(part), store);
}

void PyramidJob::runShards(const std::vector<PyramidKey>& shards, PyramidStore& store, Progress* progress) {
    Impl& m = *impl_;
    m.progress = progress;
    m.deferWrites = true;
    // A job over a file: the next shard's part, read while this one is made within the budget
    // this one leaves (nullptr when it did not fit: read alone once this one is made).
    // `bounds` and `nextBytes` are declared before `next`: a read ahead still running when a shard
    // throws reads them until the catch below has waited for it.
    std::vector<Box> bounds;
    std::size_t nextBytes = 0;
    std::future<std::unique_ptr<SceneModel>> next;
    try {
        if (m.scenePath.empty()) {
            for (const PyramidKey& s : shards) runShard(s, store, progress);
        } else {
            for (const PyramidKey& s : shards) bounds.push_back(m.quadAt(s).bounds);
            const auto readAhead = [&](std::size_t i, std::size_t held) {
                return std::async(std::launch::async, [&m, &bounds, &shards, &nextBytes, i, held]() -> std::unique_ptr<SceneModel> {
                    try {
                        return m.shardModel(bounds[i], shards[i].level, m.budgetLeft(held), nextBytes);
                    } catch (const SceneBudgetError&) {
                        nextBytes = 0;
                        return nullptr;
                    }
                });
            };
            for (std::size_t i = 0; i < shards.size(); ++i) {
                std::size_t bytes = 0;
                std::unique_ptr<SceneModel> part;
                if (next.valid()) {
                    part = next.get();
                    bytes = nextBytes;
                }
                if (!part) {
                    if (i > 0) ++m.stats.readsNotAhead;
                    part = m.shardModelAlone(shards[i], bounds[i], bytes);
                }
                m.noteHeld(m.topBytes + bytes);
                if (i + 1 < shards.size()) next = readAhead(i + 1, bytes);
                m.runShardOn(shards[i], std::move(part), store);
                if (next.valid()) {
                    next.wait();  // the part read ahead is held beside this one until it is made
                    m.noteHeld(m.topBytes + bytes + nextBytes);
                }
            }
        }
        m.deferWrites = false;
        m.flushWrites();
    } catch (...) {
        m.deferWrites = false;
        try {  // the read and the write in flight, if any, must end before the caller rolls back
            if (next.valid()) next.wait();
            m.flushWrites();
        } catch (...) {
        }
        throw;
    }
}

void PyramidJob::runTop(PyramidStore& store, Progress* progress) {
    Impl& m = *impl_;
    m.progress = progress;
    if (m.params.shardLevel <= m.params.minLevel) return;
    // The quads above the shards: their graphs are still there (runShard merges only below).
    std::vector<std::vector<Quad*>> byLevel(std::size_t(m.params.shardLevel));
    std::vector<Quad*> stack{&m.top->qt.root()};
    for (const PyramidKey& k : shards()) m.quadAt(k);  // a merged rank's top may not be there yet (quadAt times it)
    while (!stack.empty()) {
        Quad* q = stack.back();
        stack.pop_back();
        if (q->level >= m.params.shardLevel) continue;
        byLevel[std::size_t(q->level)].push_back(q);
        for (auto& c : q->children) stack.push_back(c.get());
    }
    m.makeLevels(byLevel, 0, store, true);
}

}  // namespace lacet
