// `lacet check heights` (pyramid/pyramid_height_check.h): a pyramid's deep elevation tiles are
// shown to come from the DEM level their quads need, the finest of the tree; tiles made from a
// coarser level are caught and named by their level; a pyramid of another state of the scene, or
// a level it does not store, is refused.
#include "pyramid/pyramid_height_check.h"
#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {

PyramidParams elevationOnly(int maxLevel) {
    PyramidParams p;
    p.minLevel = 0;
    p.maxLevel = maxLevel;
    p.shardLevel = 1;
    p.appearance = false;
    return p;
}

// A scene file whose DEM is a LOD tree of 16-sample blocks (5 m cells over the synthetic extent),
// and the same scene with only a coarse level of it in memory.
struct StreamedScene {
    TempFile tree{"height_check_tree.gpkg"}, scene{"height_check_scene.gpkg"};
    SceneDocument doc, coarse;
    int coarseLevel = 0;

    StreamedScene() {
        doc.scene = makeSyntheticScene({9, 1500});
        const Dem fine = makeSyntheticDem(doc.scene, {9, 5000});
        doc.demLod = writeTree(fine, tree.path);
        coarseLevel = doc.demLod->layout().levels - 3;
        doc.dem = readDemLevel(*doc.demLod, coarseLevel);
        saveScene(scene.path, doc);
        coarse.scene = doc.scene;
        coarse.dem = doc.dem;
    }
};

TEST(PyramidHeightCheck, TheDeepestTilesComeFromTheTreesFinestLevelAndTilesOfACoarserOneAreCaught) {
    StreamedScene s;
    const int finest = s.doc.demLod->layout().levels - 1;
    TempFile pyramid("height_check.pyramid.gpkg"), coarse("height_check_coarse.pyramid.gpkg");
    const PyramidParams p = elevationOnly(3);
    buildPyramid(s.scene.path, pyramid.path, p, false, nullptr);

    const PyramidHeightCheck good = checkPyramidHeights(s.scene.path, pyramid.path);
    EXPECT_TRUE(good.passed());
    EXPECT_TRUE(good.streamed);
    EXPECT_EQ(good.level, 3);
    EXPECT_EQ(good.neededLevel, finest) << "the level-3 quads need the finest level";
    EXPECT_EQ(good.tilesChecked, 64u);
    EXPECT_EQ(good.tilesMissing, 0u);
    EXPECT_EQ(good.cells, 64u * 24u * 24u);
    ASSERT_EQ(good.levels.size(), std::size_t(finest + 1));  // every level of the tree, the root first
    EXPECT_EQ(good.levels.front().demLevel, 0);
    const HeightLevelMatch& best = good.levels.back();
    EXPECT_EQ(best.demLevel, finest);
    EXPECT_EQ(best.tilesBest + good.tilesUndecided, 64u);
    EXPECT_GT(best.tilesBest, 32u);
    EXPECT_EQ(best.medianM, 0.0) << "away from the footprints a cell is the finest level's, exactly";
    EXPECT_GT(good.levels[std::size_t(finest - 2)].medianM, 0.01) << "a coarser level differs: the check tells them apart";
    EXPECT_EQ(good.json()["passed"], true);

    // The deepest elevation tiles replaced by those a build from the coarse level in memory makes:
    // the check names that level.
    buildPyramid(s.coarse, coarse.path, p, false, nullptr);
    {
        PyramidStore from(coarse.path, PyramidStore::Mode::ReadOnly), to(pyramid.path, PyramidStore::Mode::ReadWrite);
        to.begin();
        for (auto& [key, bytes] : from.allTiles(kElevationTable))
            if (key.level == 3) to.putElevation(key, bytes, 0.0, 0.0, 0.0, 0.0);
        to.commit();
    }
    const PyramidHeightCheck bad = checkPyramidHeights(s.scene.path, pyramid.path);
    EXPECT_FALSE(bad.passed());
    EXPECT_GT(bad.tilesElsewhere(), 32u);
    EXPECT_EQ(bad.levels.back().tilesBest, 0u) << "no tile agrees best with the finest level";
    std::size_t atCoarse = 0;
    for (const HeightLevelMatch& l : bad.levels)
        if (l.demLevel == s.coarseLevel) atCoarse = l.tilesBest;
    EXPECT_EQ(atCoarse, bad.tilesElsewhere()) << "the tiles agree best with the level they were made from";

    // The root is checked against the level it needs, coarser than the finest.
    const PyramidHeightCheck upper = checkPyramidHeights(s.scene.path, pyramid.path, {.level = 0, .tiles = 4});
    EXPECT_TRUE(upper.passed());
    EXPECT_EQ(upper.tilesChecked, 1u);
    EXPECT_EQ(upper.neededLevel, s.doc.demLod->layout().levelFor(quadDemNeed(s.doc.scene.extent).spacing));
    ASSERT_LT(upper.neededLevel, finest);
    EXPECT_EQ(upper.tilesElsewhere(), 0u);
    EXPECT_EQ(upper.levels.back().demLevel, finest) << "finer levels are compared too";
}

TEST(PyramidHeightCheck, RefusesAPyramidOfAnotherStateOfTheSceneALevelNotStoredAndBadKnobs) {
    StreamedScene s;
    TempFile pyramid("height_check_refuse.pyramid.gpkg");
    buildPyramid(s.scene.path, pyramid.path, elevationOnly(2), false, nullptr);
    EXPECT_THROW(checkPyramidHeights(s.scene.path, pyramid.path, {.level = 3}), PyramidError);
    EXPECT_THROW(checkPyramidHeights(s.scene.path, pyramid.path, {.tiles = 0}), std::invalid_argument);
    EXPECT_THROW(checkPyramidHeights(s.scene.path, pyramid.path, {.toleranceM = 0.0}), std::invalid_argument);
    EXPECT_THROW(checkPyramidHeights(s.scene.path, s.scene.path), PyramidError) << "a scene file holds no pyramid";

    SceneDocument edited = loadScene(s.scene.path);
    std::mt19937_64 rng(5);
    applyRandomEdit(edited.scene, rng, 50.0);
    saveScene(s.scene.path, edited);
    try {
        checkPyramidHeights(s.scene.path, pyramid.path);
        ADD_FAILURE() << "a pyramid of an earlier state of the scene was checked";
    } catch (const PyramidError& e) {
        EXPECT_NE(std::string(e.what()).find("another state"), std::string::npos) << e.what();
    }
}

// A scene whose DEM is in memory (no LOD tree) has one level: the tiles agree with it.
TEST(PyramidHeightCheck, AnInMemoryDemIsTheOneLevel) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({7, 1500});
    doc.dem = makeSyntheticDem(doc.scene, {7, 800});
    TempFile scene("height_check_memory.gpkg"), pyramid("height_check_memory.pyramid.gpkg");
    saveScene(scene.path, doc);
    buildPyramid(scene.path, pyramid.path, elevationOnly(3), false, nullptr);
    const PyramidHeightCheck c = checkPyramidHeights(scene.path, pyramid.path, {.tiles = 16});
    EXPECT_TRUE(c.passed());
    EXPECT_FALSE(c.streamed);
    EXPECT_EQ(c.tilesChecked, 16u);
    ASSERT_EQ(c.levels.size(), 1u);
    EXPECT_EQ(c.levels[0].tilesBest, 16u);
    EXPECT_EQ(c.levels[0].medianM, 0.0);
}

}  // namespace
}  // namespace lacet
