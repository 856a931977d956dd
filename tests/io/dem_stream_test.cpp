// The streamed DEM (io/dem_stream.h): windows equal the DEM in memory, the budget holds, the
// root always serves, heights() equals the DEM, and the session's tiles once every block is loaded
// equal those made with the whole DEM in memory.
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "io/dem_stream.h"
#include "editor/edit_session.h"
#include "io/dem_lod.h"
#include "io/gpkg_dem.h"
#include "io/sqlite_db.h"
#include "raster/bridge_check.h"
#include "raster/river_check.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

std::string tempPath(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("lacet_dem_stream_" + std::to_string(::getpid()) + "_" + name)).string();
}

// A DEM with detail at every scale: each level of its tree differs from the others.
Dem roughDem(int w, int h, double cell) {
    std::vector<float> z(std::size_t(w) * std::size_t(h));
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            z[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                float(800.0 + 120.0 * std::sin(i * 0.031) * std::cos(j * 0.017) + 0.05 * i - 0.08 * j) + 3.0f * noise(rng);
    return Dem(Box{{1000.0, -2000.0}, {1000.0 + w * cell, -2000.0 + h * cell}}, w, h, std::move(z));
}

// The tree of `dem` in a new GeoPackage at `path`.
std::shared_ptr<const DemLodFile> lodOf(const Dem& dem, const std::string& path, int blockSide) {
    std::filesystem::remove(path);
    createEmptyGpkg(path);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        writeDemLod(db, dem, blockSide, 0);
        db.close();
    }
    return std::make_shared<const DemLodFile>(path);
}

// The tree of `dem` (blocks of 16) at `path` with every tile of its finest level corrupt.
std::shared_ptr<const DemLodFile> corruptFinestLevel(const Dem& dem, const std::string& path) {
    const int finest = lodOf(dem, path, 16)->layout().levels - 1;
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE " + std::string(kDemLodTable) + " SET tile_data = x'00010203' WHERE zoom_level = " + std::to_string(finest));
        db.close();
    }
    return std::make_shared<const DemLodFile>(path);
}

struct Removed {
    std::string path;
    ~Removed() { std::filesystem::remove(path); }
};

TEST(DemStream, FinestWindowsAreTheDemsSamplesAndFallBackUntilLoaded) {
    const Dem dem = roughDem(301, 177, 10.0);
    Removed file{tempPath("finest.gpkg")};
    DemStream stream(lodOf(dem, file.path, 32), {.budgetMiB = 64.0, .background = false});
    const DemLodLayout& L = stream.layout();
    ASSERT_EQ(L.levels, 5);  // 32 * 2^4 = 512 >= 301
    const Box box{{1800.0, -1500.0}, {2100.0, -1300.0}};
    // Only the root is held: the window is cut from it, and the finest blocks are requested.
    DemWindow w = stream.window(box, 5.0, 1.0);
    EXPECT_EQ(w.level, 0);
    EXPECT_EQ(w.wanted, L.levels - 1);
    EXPECT_FALSE(w.complete());
    EXPECT_GT(stream.stats().pending, 0u);
    EXPECT_GT(stream.load(), 0u);
    w = stream.window(box, 5.0, 1.0);
    ASSERT_TRUE(w.complete());
    ASSERT_EQ(w.level, L.levels - 1);
    // The same cells as the whole DEM, and the same values.
    const Dem& d = *w.dem;
    EXPECT_NEAR(d.cellSize().x, 10.0, 1e-9);
    const int i0 = int(std::lround((d.extent().min.x - dem.extent().min.x) / 10.0));
    const int j0 = int(std::lround((d.extent().min.y - dem.extent().min.y) / 10.0));
    EXPECT_NEAR(d.extent().min.x, dem.extent().min.x + 10.0 * i0, 1e-6);
    for (int j = 0; j < d.height(); ++j)
        for (int i = 0; i < d.width(); ++i) ASSERT_EQ(d.at(i, j), dem.at(i0 + i, j0 + j)) << i << " " << j;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> ux(box.min.x, box.max.x), uy(box.min.y, box.max.y);
    for (int k = 0; k < 500; ++k) {
        const Vec2 p(ux(rng), uy(rng));
        EXPECT_NEAR(d.sample(p), dem.sample(p), 1e-6);
    }
}

TEST(DemStream, ACoarserLevelKeepsEveryStepthSampleFromTheTop) {
    const Dem dem = roughDem(250, 190, 4.0);
    Removed file{tempPath("coarse.gpkg")};
    DemStream stream(lodOf(dem, file.path, 16), {.budgetMiB = 64.0, .background = false});
    const DemLodLayout& L = stream.layout();
    const Box box = dem.extent();
    stream.window(box, 16.0, 1.0);  // level n - 3: every fourth sample
    stream.load();
    const DemWindow w = stream.window(box, 16.0, 1.0);
    ASSERT_TRUE(w.complete());
    ASSERT_EQ(L.step(w.level), 4);
    const Dem& d = *w.dem;
    ASSERT_EQ(d.width(), L.levelWidth(w.level));
    ASSERT_EQ(d.height(), L.levelHeight(w.level));
    for (int j = 0; j < d.height(); ++j) {
        const int r = d.height() - 1 - j;           // the level's row from the top
        const int jf = dem.height() - 1 - 4 * r;    // the DEM's row
        for (int i = 0; i < d.width(); ++i) ASSERT_EQ(d.at(i, j), dem.at(4 * i, jf)) << i << " " << j;
    }
    // Its samples stand where the DEM's do.
    EXPECT_NEAR(d.samplePosition(0, d.height() - 1).x, dem.samplePosition(0, dem.height() - 1).x, 1e-6);
    EXPECT_NEAR(d.samplePosition(0, d.height() - 1).y, dem.samplePosition(0, dem.height() - 1).y, 1e-6);
}

TEST(DemStream, HeightsEqualTheDemEvenWithATinyBudget) {
    const Dem dem = roughDem(200, 140, 7.5);
    Removed file{tempPath("heights.gpkg")};
    DemStream stream(lodOf(dem, file.path, 16), {.budgetMiB = 0.001, .background = false});
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> ux(dem.extent().min.x - 50.0, dem.extent().max.x + 50.0),
        uy(dem.extent().min.y - 50.0, dem.extent().max.y + 50.0);
    for (int k = 0; k < 2000; ++k) {
        const Vec2 p(ux(rng), uy(rng));
        ASSERT_NEAR(stream.heights().height(p), dem.sample(p), 1e-4) << p.x << " " << p.y;
    }
    EXPECT_TRUE(std::isnan(stream.heights().height(Vec2(std::nan(""), 0.0))));
    const DemStreamStats s = stream.stats();
    EXPECT_GT(s.loadedSync, 0u);
    // The budget holds one block, the root; the profiles' reads keep a chain and 8 more.
    EXPECT_LE(s.held, std::size_t(stream.layout().levels) + 8u);
    // A profile walks along its curve: each block is read about once, not once per sample.
    Removed walkFile{tempPath("walk.gpkg")};
    DemStream walker(lodOf(dem, walkFile.path, 16), {.budgetMiB = 0.001, .background = false});
    const Box e = dem.extent();
    for (int k = 0; k <= 4000; ++k) {
        const Vec2 p = e.min + (e.max - e.min) * (double(k) / 4000.0);
        ASSERT_NEAR(walker.heights().height(p), dem.sample(p), 1e-4);
    }
    // 200 x 140 samples in blocks of 16: the diagonal crosses about 25 finest blocks.
    EXPECT_LT(walker.stats().loadedSync, 25u * std::size_t(walker.layout().levels));
}

TEST(DemStream, TheBudgetHoldsAndTheRootAlwaysServes) {
    const Dem dem = roughDem(400, 400, 5.0);
    Removed file{tempPath("budget.gpkg")};
    const double blockMiB = 16.0 * 16.0 * 4.0 / 1048576.0;
    DemStream stream(lodOf(dem, file.path, 16), {.budgetMiB = 40.5 * blockMiB, .background = false});
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Box e = dem.extent();
    std::size_t fallbacks = 0, complete = 0;
    for (int frame = 0; frame < 60; ++frame) {
        stream.beginFrame();
        for (int q = 0; q < 6; ++q) {
            const Vec2 c(e.min.x + u(rng) * e.size().x, e.min.y + u(rng) * e.size().y);
            const double side = 5.0 + 30.0 * u(rng);
            const DemWindow w = stream.window(Box{c - side, c + side}, side / 20.0, u(rng));
            ASSERT_TRUE(w.dem);
            ASSERT_GE(w.dem->width(), 1);
            fallbacks += !w.complete();
            complete += w.complete();
        }
        stream.load();
        const DemStreamStats s = stream.stats();
        ASSERT_LE(s.held, 40u);
        ASSERT_GE(s.held, 1u);
    }
    const DemStreamStats s = stream.stats();
    EXPECT_GT(s.evicted, 0u);
    EXPECT_GT(fallbacks, 0u);
    EXPECT_GT(complete, 0u);
    // A budget of less than a block: every window comes from the root, none fails.
    stream.setBudget(1e-6);
    stream.beginFrame();
    stream.load();
    const DemWindow w = stream.window(Box{e.center() - 10.0, e.center() + 10.0}, 1.0, 0.0);
    stream.load();
    EXPECT_EQ(stream.stats().held, 1u);
    EXPECT_TRUE(w.dem);
}

TEST(DemStream, ACorruptBlockLeavesItsWindowsCoarserAndIsNotReadAgain) {
    const Dem dem = roughDem(120, 120, 10.0);
    Removed file{tempPath("corrupt.gpkg")};
    const auto lod = corruptFinestLevel(dem, file.path);
    const int finest = lod->layout().levels - 1;
    DemStream stream(lod, {.budgetMiB = 64.0, .background = true, .profileSpacing = 10.0});
    const Box box{dem.extent().center() - 30.0, dem.extent().center() + 30.0};
    for (int frame = 0; frame < 3; ++frame) {
        stream.beginFrame();
        const DemWindow w = stream.window(box, 1.0, 0.0);
        stream.load();
        EXPECT_LT(w.level, finest);
    }
    const DemWindow w = stream.window(box, 1.0, 0.0);
    EXPECT_EQ(w.level, finest - 1);
    const std::uint64_t failed = stream.stats().failed;
    EXPECT_GT(failed, 0u);
    // Asked again in later frames, it is not read again.
    for (int frame = 0; frame < 3; ++frame) {
        stream.beginFrame();
        stream.window(box, 1.0, 0.0);
        stream.load();
    }
    EXPECT_EQ(stream.stats().failed, failed);
    EXPECT_EQ(stream.stats().pending, 0u);
    // The z-profiles' heights there come from the next coarser level: no throw, the DEM's shape.
    const Vec2 c = dem.extent().center();
    const double h = stream.heights().height(c);
    EXPECT_NEAR(h, dem.sample(c), 30.0);
    EXPECT_EQ(h, stream.heights().height(c));  // the same every time
}

// Batch windows (windowNow, issue 23): read at once at the level asked for, the same samples as
// a streamed window once loaded, with any budget; from several threads at once; a corrupt block
// leaves them to the next coarser level, counted, never a throw.
TEST(DemStream, WindowsReadNowAreTheWantedLevelsSamplesWhateverTheBudget) {
    const Dem dem = roughDem(301, 177, 10.0);
    Removed file{tempPath("now.gpkg")};
    const auto lod = lodOf(dem, file.path, 16);
    DemStream loaded(lod, {.budgetMiB = 64.0, .background = false});
    DemStream tiny(lod, {.budgetMiB = 0.001, .background = false});
    std::mt19937_64 rng(11);
    const Box e = dem.extent();
    std::uniform_real_distribution<double> ux(e.min.x - 100.0, e.max.x), uy(e.min.y - 100.0, e.max.y), side(20.0, 900.0),
        spacing(2.0, 200.0);
    for (int k = 0; k < 60; ++k) {
        const Vec2 p(ux(rng), uy(rng));
        const Box box{p, p + side(rng)};
        const double s = spacing(rng);
        loaded.window(box, s, 0.0);
        loaded.load();
        const DemWindow streamed = loaded.window(box, s, 0.0);
        ASSERT_TRUE(streamed.complete());
        const DemWindow now = tiny.windowNow(box, s);
        ASSERT_TRUE(now.complete());
        ASSERT_EQ(now.level, streamed.level);
        ASSERT_EQ(now.dem->width(), streamed.dem->width());
        ASSERT_EQ(now.dem->height(), streamed.dem->height());
        EXPECT_EQ(now.dem->extent().min, streamed.dem->extent().min);
        EXPECT_TRUE(now.dem->heights() == streamed.dem->heights()) << "window " << k;
    }
    const DemStreamStats st = tiny.stats();
    EXPECT_EQ(st.windows, 60u);
    EXPECT_EQ(st.fallbacks, 0u);
    EXPECT_GT(st.evicted, 0u);  // read, used, dropped: the budget holds the root only
    EXPECT_LE(st.held, std::size_t(tiny.layout().levels) + 8u);
    // Many threads at once: the same windows.
    const Box box{e.center() - 200.0, e.center() + 150.0};
    const DemWindow reference = tiny.windowNow(box, 10.0);
    std::vector<std::thread> threads;
    std::atomic<int> same{0};
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < 20; ++i) same += tiny.windowNow(box, 10.0).dem->heights() == reference.dem->heights();
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(same.load(), 80);
}

TEST(DemStream, AWindowReadNowOverACorruptBlockComesFromTheNextCoarserLevel) {
    const Dem dem = roughDem(120, 120, 10.0);
    Removed file{tempPath("now_corrupt.gpkg")};
    const auto lod = corruptFinestLevel(dem, file.path);
    const int finest = lod->layout().levels - 1;
    DemStream stream(lod, {.budgetMiB = 64.0, .background = false});
    const Box box{dem.extent().center() - 30.0, dem.extent().center() + 30.0};
    const DemWindow w = stream.windowNow(box, 1.0);
    EXPECT_EQ(w.wanted, finest);
    EXPECT_EQ(w.level, finest - 1);
    EXPECT_FALSE(w.complete());
    const DemStreamStats st = stream.stats();
    EXPECT_EQ(st.fallbacks, 1u);
    EXPECT_GT(st.failed, 0u);
    // Not read again: the next window falls back at once.
    EXPECT_EQ(stream.windowNow(box, 1.0).level, finest - 1);
    EXPECT_EQ(stream.stats().loaded, st.loaded);
}

TEST(DemStream, ARequestLessImportantThanTheBlocksInUseIsRefused) {
    const Dem dem = roughDem(256, 256, 5.0);
    Removed file{tempPath("refuse.gpkg")};
    const double blockMiB = 16.0 * 16.0 * 4.0 / 1048576.0;
    DemStream stream(lodOf(dem, file.path, 16), {.budgetMiB = 5.5 * blockMiB, .background = false});
    const Box e = dem.extent();
    // A window near one corner, very important, fills the budget this frame.
    stream.beginFrame();
    const Box important{e.min + 10.0, e.min + 40.0};
    stream.window(important, 1.0, 0.0);
    stream.load();
    ASSERT_TRUE(stream.window(important, 1.0, 0.0).complete());
    const std::size_t held = stream.stats().held;
    // In the same frame, a far window of little importance: refused, the important blocks stay.
    const Box far{e.max - 40.0, e.max - 10.0};
    stream.window(far, 1.0, 100.0);
    stream.load();
    EXPECT_GT(stream.stats().refused, 0u);
    EXPECT_TRUE(stream.window(important, 1.0, 0.0).complete());
    EXPECT_FALSE(stream.window(far, 1.0, 100.0).complete());
    EXPECT_EQ(stream.stats().held, held);
    // Next frame, with the important window no longer in view, the far one gets its blocks.
    stream.beginFrame();
    stream.window(far, 1.0, 100.0);
    stream.load();
    EXPECT_TRUE(stream.window(far, 1.0, 100.0).complete());
    EXPECT_LE(stream.stats().held, 5u);
}

// The session with a streamed DEM: once every block is loaded, the tiles are those made with the
// whole DEM in memory; before, tiles made from coarser blocks are remade when the finer arrive.
SceneDocument sceneWithDem(std::uint64_t seed) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({seed, 1500});
    doc.dem = makeSyntheticDem(doc.scene, {seed, 5000});
    return doc;
}

TEST(EditSessionDemStream, TilesEqualTheInMemoryDemsOnceEveryBlockIsLoaded) {
    SceneDocument memory = sceneWithDem(31);
    Removed file{tempPath("session.gpkg")};
    SceneDocument streamed = memory;
    streamed.demLod = lodOf(*memory.dem, file.path, 32);
    SessionParams params;
    params.refine.resolution = 64;
    params.view.maxLevel = 9;
    params.demSamplesPerQuad = 1e9;  // every quad wants the finest level: the DEM in memory's samples
    params.demStream.background = false;
    EditSession a(std::move(memory), params), b(std::move(streamed), params);
    const Box ext = a.document().scene.extent;
    const glm::dvec3 viewer(ext.min.x + 0.3 * ext.size().x, ext.min.y + 0.6 * ext.size().y, 80.0);
    a.frame(viewer, 0.0);
    std::size_t fallbacks = 0, remade = 0;
    for (int f = 0; f < 20; ++f) {
        const FrameReport r = b.frame(viewer, 0.0);
        fallbacks += r.demFallbacks;
        remade += r.demRemade;
        if (b.demStream()->load() == 0 && r.pending == 0 && r.demRemade == 0 && f > 0) break;
    }
    EXPECT_GT(fallbacks, 0u);  // the first frame drew from the root
    EXPECT_GT(remade, 0u);
    std::size_t compared = 0;
    for (const auto& [key, ta] : a.tiles()) {
        const CachedTile* tb = b.tile(key);
        if (!tb) continue;
        ASSERT_FALSE(tb->dirty);
        ASSERT_EQ(tb->demLevel, tb->demWanted);
        ASSERT_EQ(ta.elevation.zm.size(), tb->elevation.zm.size());
        for (std::size_t k = 0; k < ta.elevation.zm.size(); ++k) ASSERT_NEAR(ta.elevation.zm[k], tb->elevation.zm[k], 1e-3);
        ASSERT_EQ(ta.appearance.rgbm.size(), tb->appearance.rgbm.size());
        int worst = 0;
        for (std::size_t k = 0; k < ta.appearance.rgbm.size(); ++k) worst = std::max(worst, std::abs(int(ta.appearance.rgbm[k]) - int(tb->appearance.rgbm[k])));
        EXPECT_LE(worst, 1);
        ++compared;
    }
    EXPECT_GE(compared, a.tiles().size() * 9 / 10);
}

TEST(EditSessionDemStream, AFarTooSmallBudgetStillDrawsTheTerrainCoarser) {
    SceneDocument doc = sceneWithDem(32);
    Removed file{tempPath("small.gpkg")};
    doc.demLod = lodOf(*doc.dem, file.path, 32);
    const auto [lo, hi] = std::minmax_element(doc.dem->heights().begin(), doc.dem->heights().end());
    SessionParams params;
    params.refine.resolution = 64;
    params.view.maxLevel = 9;
    params.demStream.budgetMiB = 0.001;  // less than one block: the root alone
    params.demStream.background = false;
    EditSession s(std::move(doc), params);
    const Box ext = s.document().scene.extent;
    for (int f = 0; f < 5; ++f) {
        const FrameReport r = s.frame({ext.center().x + 40.0 * f, ext.center().y, 30.0}, 0.0);
        s.demStream()->load();
        EXPECT_EQ(r.pending, 0u);
    }
    // A still view comes to rest: what the budget refused is not asked again while the blocks in
    // use stay the same (the editor's "idle" waits for no pending block).
    std::size_t pending = 0;
    for (int f = 0; f < 6; ++f) {
        s.frame({ext.center().x + 160.0, ext.center().y, 30.0}, 0.0);
        pending = s.demStream()->stats().pending;
        s.demStream()->load();
    }
    EXPECT_EQ(pending, 0u);
    EXPECT_GT(s.demStream()->stats().refused, 0u);
    std::size_t coarser = 0;
    for (const auto& [key, t] : s.tiles()) {
        EXPECT_LE(t.demLevel, t.demWanted);
        coarser += t.demLevel < t.demWanted;
        for (float z : t.elevation.zm) {
            ASSERT_TRUE(std::isfinite(z));
            EXPECT_GT(z, *lo - 50.0f);
            EXPECT_LT(z, *hi + 50.0f);
        }
    }
    EXPECT_GT(coarser, 0u);
    EXPECT_LE(s.demStream()->stats().held, std::size_t(s.demStream()->layout().levels) + 8u);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Batch commands read a streamed DEM through StreamedDem (io/dem_stream.h): where every quad and
// the z-profiles read the finest level (the DEM's 20 m cells are coarser than the profiles' 10 m
// and than the level-7 quads' windows need), the checks find what they find on the DEM in memory.
TEST(StreamedDem, ChecksThroughItEqualTheDemInMemoryWhereTheyReadTheFinestLevel) {
    SceneDocument memory = sceneWithDem(33);
    Removed file{tempPath("checks.gpkg")};
    SceneDocument streamed;
    streamed.scene = memory.scene;
    streamed.demLod = lodOf(*memory.dem, file.path, 32);
    streamed.dem = readDemLevel(*streamed.demLod, 0);  // coarse: must not be what is read
    const std::unique_ptr<DemSource> a = batchDemSource(memory, 512.0), b = batchDemSource(streamed, 0.5);
    ASSERT_NE(dynamic_cast<const InMemoryDem*>(a.get()), nullptr);
    ASSERT_NE(dynamic_cast<const StreamedDem*>(b.get()), nullptr);

    const RiverCheckReport ra = checkRivers(memory.scene, *a), rb = checkRivers(streamed.scene, *b);
    ASSERT_GT(ra.profileAboveDem.count, 100u);
    EXPECT_EQ(ra.profileAboveDem.count, rb.profileAboveDem.count);
    EXPECT_NEAR(ra.profileAboveDem.median, rb.profileAboveDem.median, 1e-4);
    EXPECT_NEAR(ra.profileAboveDem.max, rb.profileAboveDem.max, 1e-4);
    EXPECT_NEAR(ra.nodesAboveDem.max, rb.nodesAboveDem.max, 1e-4);
    EXPECT_EQ(ra.risingSamples, rb.risingSamples);
    // The coarse level alone would not give that: the test sees which level was read.
    const RiverCheckReport rc = checkRivers(streamed.scene, *streamed.dem);
    EXPECT_GT(std::abs(rc.profileAboveDem.max - ra.profileAboveDem.max) + std::abs(rc.profileAboveDem.median - ra.profileAboveDem.median), 1e-3);

    const BridgeCheckReport ba = checkBridges(memory.scene, *a), bb = checkBridges(streamed.scene, *b);
    ASSERT_GT(ba.bridges, 0u);
    EXPECT_EQ(ba.bridges, bb.bridges);
    EXPECT_EQ(ba.bedPoints, bb.bedPoints);
    EXPECT_EQ(ba.bedPointsDiffering, bb.bedPointsDiffering);
    EXPECT_NEAR(ba.leastClearance, bb.leastClearance, 1e-4);
    EXPECT_NEAR(ba.largestBedDifference, bb.largestBedDifference, 1e-3);
    const DemStreamStats st = dynamic_cast<const StreamedDem&>(*b).stats();
    EXPECT_GT(st.windows, 0u);
    EXPECT_EQ(st.fallbacks, 0u);

    // No DEM at all: flat ground at 0 m.
    SceneDocument flat;
    flat.scene = memory.scene;
    const std::unique_ptr<DemSource> f = batchDemSource(flat, 512.0);
    EXPECT_EQ(f->heights().height(flat.scene.extent.center()), 0.0);
    EXPECT_EQ(f->quadDem(Quadtree(flat.scene).root())->sample(flat.scene.extent.center()), 0.0);
}

}  // namespace
}  // namespace lacet
