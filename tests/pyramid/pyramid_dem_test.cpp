// A pyramid over a DEM streamed from its LOD tree (issue 23, io/dem_stream.h): each quad reads its
// window at the level it needs, never the coarse level held in memory, and the tree is part of
// the pyramid's inputs.
#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {


// Elevation tiles of a level, decoded: key -> heights.
std::unordered_map<PyramidKey, std::vector<float>, PyramidKeyHash> elevationTiles(const std::string& path, int level) {
    std::unordered_map<PyramidKey, std::vector<float>, PyramidKeyHash> out;
    for (auto& [key, bytes] : tilesOf(path, kElevationTable))
        if (key.level == level) out[key] = decodeFloatTiff(bytes).values;
    return out;
}

// The largest difference between two pyramids' elevation tiles of a level (metres).
double largestDifference(const std::string& a, const std::string& b, int level, std::size_t* tiles = nullptr) {
    const auto ta = elevationTiles(a, level), tb = elevationTiles(b, level);
    EXPECT_EQ(ta.size(), tb.size());
    double worst = 0.0;
    for (const auto& [key, za] : ta) {
        const auto it = tb.find(key);
        if (it == tb.end() || it->second.size() != za.size()) {
            ADD_FAILURE() << "tile " << key.level << "/" << key.tx << "/" << key.ty << " differs in size or is missing";
            continue;
        }
        for (std::size_t k = 0; k < za.size(); ++k) worst = std::max(worst, double(std::abs(za[k] - it->second[k])));
    }
    if (tiles) *tiles = ta.size();
    return worst;
}

// Issue 23 (full resolution in batch): a scene whose DEM is a LOD tree (io/dem_lod.h) holds only a
// coarse level in memory; the pyramid used to be made from that level, silently. Now each quad
// reads its window at the level it needs: the deepest tiles equal those made with the finest
// level in memory (the z-profiles read the finest level too: the DEM's 20 m cells are coarser
// than their 10 m), a build from the coarse level alone differs, and the budget changes memory
// only, never a tile.
TEST(PyramidBuild, AStreamedDemIsReadAtTheLevelEachQuadNeedsNotTheCoarseLevelInMemory) {
    SceneDocument fine;
    fine.scene = makeSyntheticScene({9, 1500});
    fine.dem = makeSyntheticDem(fine.scene, {9, 5000});
    TempFile tree("pyramid_dem_tree.gpkg");
    const auto lod = writeTree(*fine.dem, tree.path);
    ASSERT_GE(lod->layout().levels, 4);
    const int coarseLevel = lod->layout().levels - 3;  // samples 4x farther apart than the DEM's
    SceneDocument streamed;
    streamed.scene = fine.scene;
    streamed.demLod = lod;
    streamed.dem = readDemLevel(*lod, coarseLevel);  // as loadScene holds a tree larger than memory
    SceneDocument coarse;
    coarse.scene = fine.scene;
    coarse.dem = streamed.dem;

    PyramidParams p = smallParams();
    p.appearance = false;
    const double quadSide = fine.scene.extent.size().x / double(1 << p.maxLevel);
    ASSERT_LE(quadDemNeed(Box{Vec2(0.0), Vec2(quadSide)}).spacing, lod->layout().cell) << "the deepest quads need the finest level";
    TempFile a("pyramid_dem_fine.gpkg"), b("pyramid_dem_streamed.gpkg"), c("pyramid_dem_coarse.gpkg"), d("pyramid_dem_small.gpkg");
    buildPyramid(fine, a.path, p, false, nullptr);
    const PyramidStats sb = buildPyramid(streamed, b.path, p, false, nullptr);
    buildPyramid(coarse, c.path, p, false, nullptr);
    PyramidParams small = p;
    small.demBudgetMiB = 0.001;  // less than one 16^2 block: each window's blocks read, then dropped
    const PyramidStats sd = buildPyramid(streamed, d.path, small, false, nullptr);

    std::size_t tiles = 0;
    const double streamedError = largestDifference(a.path, b.path, p.maxLevel, &tiles);
    const double coarseError = largestDifference(a.path, c.path, p.maxLevel);
    EXPECT_EQ(tiles, 64u);
    EXPECT_LE(streamedError, 1e-3) << "the deepest tiles are not made from the finest level";
    EXPECT_GT(coarseError, 1.0) << "the coarse level does not differ: the test would not see a coarse build";
    expectSamePyramid(b.path, d.path);
    // Every quad read one window, at the level it needs (no block failed).
    EXPECT_TRUE(sb.dem.streamed);
    EXPECT_EQ(sb.dem.windows, sb.quads);
    EXPECT_EQ(sb.dem.fallbacks, 0u);
    ASSERT_EQ(sb.dem.windowsAtLevel.size(), std::size_t(lod->layout().levels));
    EXPECT_GE(sb.dem.windowsAtLevel.back(), 64u);  // the deepest quads' windows come from the finest level
    EXPECT_GT(sb.dem.blocksRead, 0u);
    EXPECT_GT(sd.dem.blocksEvicted, 0u);
    EXPECT_FALSE(buildPyramid(fine, a.path, p, true, nullptr).dem.streamed);
    std::printf("[ figures ] streamed DEM, level-%d tiles: largest difference from the finest level in memory %.2g m, from the "
                "level-%d grid in memory %.2f m; %llu blocks read (budget 512 MiB), %llu (budget 0.001 MiB, %llu dropped)\n",
                p.maxLevel, streamedError, coarseLevel, coarseError, (unsigned long long)sb.dem.blocksRead,
                (unsigned long long)sd.dem.blocksRead, (unsigned long long)sd.dem.blocksEvicted);
}

// The tree's digest is the DEM's part of the pyramid's inputs: an update of the same tree remakes
// nothing; another tree under the same scene remakes everything.
TEST(PyramidUpdate, AStreamedDemTreeIsPartOfTheInputs) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({10, 800});
    const Dem dem = makeSyntheticDem(doc.scene, {10, 5000});
    TempFile tree("pyramid_inputs_tree.gpkg"), other("pyramid_inputs_other.gpkg"), f("pyramid_inputs.gpkg");
    std::vector<float> z = dem.heights();
    z[z.size() / 2] += 5.0f;
    const auto changed = writeTree(Dem(dem.extent(), dem.width(), dem.height(), std::move(z)), other.path);
    doc.demLod = writeTree(dem, tree.path);
    doc.dem = readDemLevel(*doc.demLod, 0);
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    EXPECT_EQ(updatePyramid(doc, f.path, nullptr).tilesMade, 0u);
    doc.demLod = changed;  // the same coarse level in memory
    const PyramidStats st = updatePyramid(doc, f.path, nullptr);
    EXPECT_TRUE(st.rebuilt);
    EXPECT_THROW(updatePyramid(doc, f.path, nullptr, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace lacet
