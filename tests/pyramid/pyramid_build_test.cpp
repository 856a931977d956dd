// The tile pyramid (§7, pyramid/pyramid_build.h): GIS tools read what it stores, an update after
// random edits equals a build from scratch tile for tile and remakes only what changed, and bad
// input (another scene, an interrupted build, a corrupt tile) is refused or reported.
#include "tests/pyramid/pyramid_fixtures.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

TEST(PyramidBuild, GdalReadsTheTablesAsTheyAre) {
    const SceneDocument doc = smallScene();
    TempFile f("pyramid_gdal.gpkg");
    const PyramidStats st = buildPyramid(doc, f.path, smallParams(), false, nullptr);
    EXPECT_EQ(st.appearanceTiles, 85u);
    EXPECT_EQ(st.elevationTiles, 85u);
    EXPECT_GT(st.waterTiles, 0u);
    EXPECT_LT(st.waterTiles, 85u);  // tiles without water are not stored

    GDALAllRegister();
    {
        const std::string open = "GPKG:" + f.path + ":" + kAppearanceTable;
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(open.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        ASSERT_TRUE(ds) << CPLGetLastErrorMsg();
        EXPECT_EQ(ds->GetRasterXSize(), 8 * 256);  // the deepest level, 2^3 tiles of 256
        EXPECT_EQ(ds->GetRasterYSize(), 8 * 256);
        double gt[6];
        ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
        EXPECT_NEAR(gt[0], doc.scene.extent.min.x, 1e-6);
        EXPECT_NEAR(gt[3], doc.scene.extent.max.y, 1e-6);
        EXPECT_NEAR(gt[1], doc.scene.extent.size().x / 2048.0, 1e-9);
        // A texel GDAL reads equals the tile's: quad (tx 2, ty 5) of level 3 is tile row 2.
        std::vector<std::uint8_t> px(3);
        const int col = 2 * 256 + 17, row = 2 * 256 + 200;
        ASSERT_EQ(ds->RasterIO(GF_Read, col, row, 1, 1, px.data(), 1, 1, GDT_Byte, 3, nullptr, 3, 3, 1, nullptr), CE_None);
        PyramidStore s(f.path, PyramidStore::Mode::ReadOnly);
        const DecodedImage tile = decodeImage(*s.tile(kAppearanceTable, PyramidKey{3, 2, 5}));
        for (int c = 0; c < 3; ++c) EXPECT_EQ(px[std::size_t(c)], tile.pixels[std::size_t((200 * 256 + 17) * 3 + c)]);
        EXPECT_EQ(ds->GetRasterBand(1)->GetOverviewCount(), 3);  // levels 2, 1, 0
    }
    {
        const std::string open = "GPKG:" + f.path + ":" + kElevationTable;
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(open.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        ASSERT_TRUE(ds) << CPLGetLastErrorMsg();
        EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Float32);
        EXPECT_EQ(ds->GetRasterXSize(), 8 * 24);
        float z = 0.0f;
        ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 24 + 5, 24 * 6 + 3, 1, 1, &z, 1, 1, GDT_Float32, 0, 0), CE_None);
        PyramidStore s(f.path, PyramidStore::Mode::ReadOnly);
        const DecodedFloats tile = decodeFloatTiff(*s.tile(kElevationTable, PyramidKey{3, 1, 1}));
        EXPECT_EQ(z, tile.values[3 * 24 + 5]);
        EXPECT_GT(z, -1000.0f);
    }
    const PyramidCheck check = checkPyramid(f.path);
    EXPECT_TRUE(check.problems.empty());
    EXPECT_TRUE(check.info.complete);
}

// An update after random edits (fixed seeds) equals a build from scratch of the edited scene,
// tile for tile and byte for byte, and leaves untouched tiles as they were.
TEST(PyramidUpdate, EqualsARebuildAfterRandomEdits) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
        SceneDocument doc = smallScene(seed);
        TempFile updated("pyramid_updated.gpkg"), rebuilt("pyramid_rebuilt.gpkg");
        PyramidParams params = smallParams();
        params.vectorLevels = 2;  // levels 2-3 from vector data, 0-1 mipmapped
        buildPyramid(doc, updated.path, params, false, nullptr);
        const Tiles before = tilesOf(updated.path, kAppearanceTable);

        std::mt19937_64 rng(seed);
        const int edits = 3;
        for (int e = 0; e < edits; ++e) applyRandomEdit(doc.scene, rng, 60.0);
        const PyramidStats up = updatePyramid(doc, updated.path, nullptr);
        EXPECT_FALSE(up.rebuilt);
        EXPECT_LT(up.quadsChanged, up.quads) << "seed " << seed;
        buildPyramid(doc, rebuilt.path, params, false, nullptr);
        expectSamePyramid(updated.path, rebuilt.path);

        // Tiles of quads the edits did not reach are untouched.
        const Tiles after = tilesOf(updated.path, kAppearanceTable);
        std::size_t same = 0;
        for (std::size_t i = 0; i < after.size(); ++i) same += after[i].second == before[i].second;
        EXPECT_GT(same, 0u) << "seed " << seed;
        EXPECT_GE(up.tilesWritten, after.size() - same);
    }
}

// Shards are independent: any shard level gives the same pyramid (the top levels read the shard
// roots from the file, on several threads at once).
TEST(PyramidBuild, EveryShardLevelGivesTheSamePyramid) {
    const SceneDocument doc = smallScene();
    TempFile reference("pyramid_shard0.gpkg");
    PyramidParams p = smallParams();
    p.shardLevel = 0;
    p.encoding = parseEncoding("jpeg:90");
    buildPyramid(doc, reference.path, p, false, nullptr);
    for (int level : {1, 2, 3}) {
        TempFile f("pyramid_shard.gpkg");
        p.shardLevel = level;
        buildPyramid(doc, f.path, p, false, nullptr);
        expectSamePyramid(f.path, reference.path);
    }
}

// A shard deeper than PyramidParams::passLevels goes depth first: any pass depth gives the same
// pyramid, while the quads held below a shard's root fall from its whole subtree (4 + 16 + 64 +
// 256 below level 0 of levels 0-4) to four a level down one path; an update after random edits,
// made depth first (the default 3 levels a pass under a shard of 5), equals a rebuild.
TEST(PyramidBuild, EveryPassDepthGivesTheSamePyramidInTheMemoryOfOnePath) {
    SceneDocument doc = smallScene(3, 2500);
    PyramidParams p = smallParams();
    p.maxLevel = 4;
    p.shardLevel = 0;
    p.vectorLevels = 2;  // levels 0-2 mipmapped: depth first, their children come from the store
    p.encoding = parseEncoding("jpeg:90");
    TempFile reference("pyramid_pass5.gpkg");
    p.passLevels = 5;
    EXPECT_EQ(buildPyramid(doc, reference.path, p, false, nullptr).peakShardQuads, 340u);
    // Under the sanitizers, the shallowest pass and one in the middle.
    for (int passLevels : test::kSanitized ? std::vector<int>{1, 3} : std::vector<int>{1, 2, 3, 4}) {
        SCOPED_TRACE("pass levels " + std::to_string(passLevels));
        TempFile f("pyramid_pass.gpkg");
        p.passLevels = passLevels;
        const PyramidStats st = buildPyramid(doc, f.path, p, false, nullptr);
        // A path of 5 - passLevels quads subdivided one level (4 each), then a pass's subtree.
        std::size_t pass = 0;
        for (int l = 1; l < passLevels; ++l) pass += std::size_t(1) << (2 * l);
        EXPECT_EQ(st.peakShardQuads, 4u * std::size_t(5 - passLevels) + pass);
        expectSamePyramid(f.path, reference.path);
    }
    // An update (PyramidParams' default pass depth and shard level) after random edits.
    p.passLevels = PyramidParams{}.passLevels;
    ASSERT_LT(p.passLevels, 5);
    TempFile updated("pyramid_pass_updated.gpkg"), rebuilt("pyramid_pass_rebuilt.gpkg");
    buildPyramid(doc, updated.path, p, false, nullptr);
    std::mt19937_64 rng(11);
    for (int e = 0; e < 5; ++e) applyRandomEdit(doc.scene, rng, 60.0);
    const PyramidStats up = updatePyramid(doc, updated.path, nullptr);
    EXPECT_FALSE(up.rebuilt);
    EXPECT_GT(up.quadsChanged, 0u);
    EXPECT_LT(up.quadsChanged, up.quads);
    buildPyramid(doc, rebuilt.path, p, false, nullptr);
    expectSamePyramid(updated.path, rebuilt.path);

    p.passLevels = 0;
    EXPECT_THROW(p.resolve(doc.scene.extent.size().x, 256), std::invalid_argument);
}

// The default shard level follows the scene's curves and areas, counted in the document or in the
// file: a shard of at most shardElements of them (here level 3, deeper than maxLevel - 4: a shard
// of 2 levels, 4 quads below its root). The same pyramid at any level.
TEST(PyramidBuild, TheDefaultShardLevelFollowsTheScenesSize) {
    const fs::path dir = fs::temp_directory_path() / ("lacet_pyramid_shards_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string scene = (dir / "scene.gpkg").string();
    const SceneDocument doc = smallScene(4, 2000);
    saveScene(scene, doc);
    PyramidParams p = smallParams();
    p.maxLevel = 4;
    p.shardLevel = -1;
    p.passLevels = 5;
    const std::string a = (dir / "a.gpkg").string(), b = (dir / "b.gpkg").string(), c = (dir / "c.gpkg").string();
    EXPECT_EQ(buildPyramid(doc, a, p, false, nullptr).peakShardQuads, 340u);  // level 0: a few thousand elements
    std::size_t elements = 0;
    for (const Layer& l : doc.scene.layers) elements += l.curves.size() + l.areas.size();
    p.shardElements = double(elements) / 32.0;  // more than 4^2 shards, at most 4^3: level 3
    EXPECT_EQ(buildPyramid(doc, b, p, false, nullptr).peakShardQuads, 4u);
    EXPECT_EQ(buildPyramid(scene, c, p, false, nullptr).peakShardQuads, 4u);
    expectSamePyramid(a, b);
    expectSamePyramid(a, c);
    fs::remove_all(dir);
}

// Out of core (§7): a pyramid built from the scene file, each shard reading only its part and
// the levels above only what their elevation reads, is the pyramid built from the whole document,
// tile for tile and digest for digest, whether the levels above the shards are mipmapped or made
// from vector data; an update from the file after random edits equals a rebuild.
TEST(PyramidBuild, FromTheSceneFileOutOfCoreEqualsFromTheWholeDocument) {
    const fs::path dir = fs::temp_directory_path() / ("lacet_pyramid_file_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string scene = (dir / "scene.gpkg").string();
    for (std::uint64_t seed = 1; seed <= std::uint64_t(test::sanitizedOr(2, 1)); ++seed) {
        SceneDocument doc = smallScene(seed, 3000);
        saveScene(scene, doc);
        for (int vectorLevels : {2, 4}) {  // the levels above the shards mipmapped (elevation only), or not
            PyramidParams p = smallParams();
            p.maxLevel = 4;
            p.shardLevel = 2;
            p.vectorLevels = vectorLevels;
            const std::string whole = (dir / "whole.gpkg").string(), part = (dir / "part.gpkg").string();
            buildPyramid(loadScene(scene), whole, p, true, nullptr);
            buildPyramid(scene, part, p, true, nullptr);
            SCOPED_TRACE("seed " + std::to_string(seed) + ", vector levels " + std::to_string(vectorLevels));
            expectSamePyramid(whole, part);
            PyramidStore a(whole, PyramidStore::Mode::ReadOnly), b(part, PyramidStore::Mode::ReadOnly);
            ASSERT_TRUE(a.info() && b.info());
            EXPECT_EQ(a.info()->sceneChecksum, b.info()->sceneChecksum);
            EXPECT_EQ(a.info()->inputs, b.info()->inputs);
        }
        // Edited and saved: the update from the file equals a rebuild of the edited document.
        PyramidParams p = smallParams();
        p.maxLevel = 4;
        p.shardLevel = 2;
        p.vectorLevels = 2;
        const std::string updated = (dir / "updated.gpkg").string(), rebuilt = (dir / "rebuilt.gpkg").string();
        EXPECT_TRUE(buildPyramid(scene, updated, p, true, nullptr).wholeFileChecked);
        std::mt19937_64 rng(seed + 40);
        for (int e = 0; e < 4; ++e) applyRandomEdit(doc.scene, rng, 60.0);
        saveScene(scene, doc);
        const PyramidStats up = updatePyramid(scene, updated, nullptr);
        // The update reads no page it does not need: no O(file) read transaction for a save to wait on.
        EXPECT_FALSE(up.wholeFileChecked);
        EXPECT_FALSE(up.rebuilt);
        EXPECT_LT(up.quadsChanged, up.quads);
        buildPyramid(loadScene(scene), rebuilt, p, true, nullptr);
        expectSamePyramid(updated, rebuilt);
    }
    fs::remove_all(dir);
}

// PyramidParams::vectorBudgetMiB: the vector data a build over a file holds. With room for the
// largest shard's part beside the top part but not for two parts, the next part is not read ahead
// (counted) and the pyramid is the same, tile for tile, its peak within the budget; with no room
// for the largest part, the build is refused naming the file, the shard, the budget and the way out,
// and no pyramid is left.
TEST(PyramidBuild, AVectorBudgetReadsAheadOnlyWhatFitsAndRefusesAPartThatDoesNot) {
    const fs::path dir = fs::temp_directory_path() / ("lacet_pyramid_budget_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string scene = (dir / "scene.gpkg").string();
    saveScene(scene, smallScene(3, 3000));
    PyramidParams p = smallParams();
    p.maxLevel = 4;
    p.shardLevel = 2;
    const std::string free = (dir / "free.gpkg").string(), tight = (dir / "tight.gpkg").string(),
                      refused = (dir / "refused.gpkg").string();
    const PyramidStats a = buildPyramid(scene, free, p, false, nullptr);
    const double top = a.topVectorMiB, largest = a.largestPartMiB;
    EXPECT_EQ(a.readsNotAhead, 0u);
    ASSERT_GT(top, 0.0);
    ASSERT_GT(largest, 0.0);
    EXPECT_GT(a.peakVectorMiB, top + largest) << "a part read ahead beside the one being made";
    EXPECT_LE(a.peakVectorMiB, top + 2.0 * largest);

    p.vectorBudgetMiB = top + 1.02 * largest;
    PyramidStats b;
    try {
        b = buildPyramid(scene, tight, p, false, nullptr);
    } catch (const PyramidError& e) {
        FAIL() << "a budget over the largest part was refused: " << e.what();
    }
    EXPECT_GT(b.readsNotAhead, 0u);
    EXPECT_LE(b.peakVectorMiB, p.vectorBudgetMiB);
    EXPECT_EQ(b.largestPartMiB, largest);
    expectSamePyramid(free, tight);

    p.vectorBudgetMiB = top + 0.3 * largest;
    try {
        buildPyramid(scene, refused, p, false, nullptr);
        ADD_FAILURE() << "a part over the budget was read";
    } catch (const PyramidError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(scene), std::string::npos) << m;
        EXPECT_NE(m.find("budget"), std::string::npos) << m;
        EXPECT_NE(m.find("shard 2/"), std::string::npos) << m;
        EXPECT_NE(m.find("--shard-level"), std::string::npos) << m;
    }
    EXPECT_FALSE(fs::exists(refused));
    fs::remove_all(dir);
}

TEST(PyramidUpdate, NothingChangedRemakesNothing) {
    const SceneDocument doc = smallScene();
    TempFile f("pyramid_same.gpkg");
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    const PyramidStats st = updatePyramid(doc, f.path, nullptr);
    EXPECT_EQ(st.quadsChanged, 0u);
    EXPECT_EQ(st.tilesMade, 0u);
    EXPECT_EQ(st.tilesWritten, 0u);
}

// A scene saved and loaded again, with no edit, is the same scene to the digests.
TEST(PyramidUpdate, ASaveAndLoadRemakesNothing) {
    const SceneDocument doc = smallScene();
    TempFile f("pyramid_saved.gpkg"), scene("pyramid_scene.gpkg");
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    saveScene(scene.path, doc);
    const PyramidStats st = updatePyramid(loadScene(scene.path), f.path, nullptr);
    EXPECT_EQ(st.quadsChanged, 0u);
    EXPECT_EQ(st.tilesMade, 0u);
}

TEST(PyramidUpdate, OneMovedRoadRemakesFewTiles) {
    SceneDocument doc = smallScene();
    TempFile f("pyramid_road.gpkg");
    const PyramidStats built = buildPyramid(doc, f.path, smallParams(), false, nullptr);
    // Moves a control point of a cubic road by 20 m, one whose nodes are not 3-way junctions (where
    // the direction a road leaves the node decides the stop lines of all three), nor roundabouts.
    Layer& roads = doc.scene.layers[kRoadsLayer];
    bool moved = false;
    const auto plain = [&](ElementId n) { return roads.nodes[n].curves.size() != 3 && roads.nodes[n].roundabout == 0.0f; };
    for (Curve& c : roads.curves)
        if (c.alive && c.vertices.size() == 4 && !c.vertices[1].onCurve && plain(c.start) && plain(c.end)) {
            c.vertices[1].p += Vec2(20.0, 0.0);
            moved = true;
            break;
        }
    ASSERT_TRUE(moved);
    const PyramidStats st = updatePyramid(doc, f.path, nullptr);
    std::printf("one moved road: %zu of %zu tiles remade, %zu quads of %zu changed\n", st.tilesMade, built.tilesMade,
                st.quadsChanged, st.quads);
    EXPECT_GE(st.quadsChanged, 4u);  // one quad per level at least
    EXPECT_LE(st.tilesMade, built.tilesMade / 5);
}

TEST(PyramidBuild, RefusesAPyramidOfAnotherScene) {
    const SceneDocument a = smallScene(1, 1500), b = smallScene(1, 3000);  // another extent
    TempFile f("pyramid_other.gpkg");
    buildPyramid(a, f.path, smallParams(), false, nullptr);
    try {
        updatePyramid(b, f.path, nullptr);
        FAIL() << "an update for another scene was accepted";
    } catch (const PyramidError& e) {
        EXPECT_NE(std::string(e.what()).find("another scene"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(f.path), std::string::npos) << e.what();
    }
    EXPECT_THROW(buildPyramid(b, f.path, smallParams(), false, nullptr), PyramidError);
    EXPECT_NO_THROW(buildPyramid(b, f.path, smallParams(), true, nullptr));  // --force
}

// A progress that fails part-way, as a killed build would stop.
struct FailingProgress : Progress {
    std::size_t left;
    explicit FailingProgress(std::size_t n) : left(n) {}
    void begin(const std::string&, std::size_t, const std::string&) override {}
    void advance(std::size_t units) override {
        if (units >= left) throw std::runtime_error("interrupted");
        left -= units;
    }
    void end() override {}
};

TEST(PyramidBuild, AnInterruptedBuildOrUpdateLeavesThePreviousPyramid) {
    SceneDocument doc = smallScene();
    TempFile f("pyramid_interrupted.gpkg");
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    const Tiles before = tilesOf(f.path, kAppearanceTable);
    FailingProgress failing(100);
    EXPECT_THROW(buildPyramid(smallScene(9), f.path, smallParams(), true, &failing), std::runtime_error);
    EXPECT_EQ(tilesOf(f.path, kAppearanceTable), before);
    std::mt19937_64 rng(4);
    for (int e = 0; e < 5; ++e) applyRandomEdit(doc.scene, rng, 200.0);
    FailingProgress failing2(20);
    EXPECT_THROW(updatePyramid(doc, f.path, &failing2), std::runtime_error);
    EXPECT_EQ(tilesOf(f.path, kAppearanceTable), before);
    EXPECT_TRUE(checkPyramid(f.path).problems.empty());
}

TEST(PyramidParams, DefaultDeepestLevelReachesTheTexelSize) {
    PyramidParams p;
    p.texel = 1.0;
    p.resolve(34172.0, 256);  // Andorra's extent
    EXPECT_EQ(p.maxLevel, 7);  // 34172 / 2^7 / 256 = 1.04 m, nearer 1 m than 0.52 m
    PyramidParams q;
    q.texel = 0.6;
    q.resolve(34172.0, 256);
    EXPECT_EQ(q.maxLevel, 8);
    PyramidParams bad;
    bad.minLevel = 3;
    bad.maxLevel = 2;
    EXPECT_THROW(bad.resolve(1000.0, 256), std::invalid_argument);
    PyramidParams huge;
    huge.maxLevel = 20;  // 4^20 quads at the deepest level
    EXPECT_THROW(huge.resolve(1000.0, 256), std::invalid_argument);
    PyramidParams many;
    many.minLevel = 3;
    many.maxLevel = 5;
    many.vectorLevels = 10;
    many.resolve(1000.0, 256);
    EXPECT_EQ(many.vectorLevels, 3);  // what the file stores: an update gets the same knobs
    // The default shard level: the deepest - 4, or deeper where a shard would hold over
    // shardElements curves and areas (never deeper than maxLevel).
    const auto shardLevelOf = [](int maxLevel, std::size_t elements, double shardElements = PyramidParams{}.shardElements) {
        PyramidParams s;
        s.maxLevel = maxLevel;
        s.shardElements = shardElements;
        s.resolve(100000.0, 256, elements);
        return s.shardLevel;
    };
    EXPECT_EQ(shardLevelOf(7, 60000), 3);
    EXPECT_EQ(shardLevelOf(6, 600000), 2);    // 37,500 a shard
    EXPECT_EQ(shardLevelOf(6, 6000000), 3);   // 93,750 a shard, not 375,000
    EXPECT_EQ(shardLevelOf(6, 6000000, 1000.0), 6);  // no deeper than the deepest level
    EXPECT_EQ(shardLevelOf(2, 6000000), 2);
    PyramidParams noElements;
    noElements.shardElements = 0.0;
    EXPECT_THROW(noElements.resolve(1000.0, 256), std::invalid_argument);
    EXPECT_THROW(parseEncoding("gif"), std::invalid_argument);
    EXPECT_THROW(parseEncoding("jpeg:0"), std::invalid_argument);
    EXPECT_EQ(encodingName(parseEncoding("webp:75")), "webp:75");
}

}  // namespace
}  // namespace lacet
