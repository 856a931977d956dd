// io/scene_region.h: the tiles of any quad of a region, made from the part of the scene file that
// loadSceneRegion reads, are the tiles made from the whole scene, bit for bit (randomized regions
// with fixed seeds, at several levels, over a synthetic scene with bridges, roundabouts, rivers,
// lakes, fields and forests); what is read follows the region; a file without the feature index is
// read whole; a corrupt index is refused by name.
#include "io/scene_region.h"

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "model/curve_data.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "raster/dem_source.h"
#include "raster/parallel_producers.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

void collect(Quadtree& qt, Quad& q, const Box& region, int level, std::vector<const Quad*>& out) {
    if (!q.bounds.intersects(region)) return;
    if (q.level == level) {
        out.push_back(&q);
        return;
    }
    if (q.isLeaf()) qt.subdivide(q);
    for (auto& c : q.children) collect(qt, *c, region, level, out);
}

struct RegionTiles {
    std::vector<AppearanceTile> appearance;
    std::vector<ElevationTile> elevation;
    std::size_t bridges = 0, roundaboutRoads = 0;
};

RegionTiles tilesOf(const SceneDocument& doc, const Box& region, int level) {
    GraphStep step(doc.scene);
    Quadtree qt(doc.scene, {}, &step);
    std::vector<const Quad*> quads;
    collect(qt, qt.root(), region, level, quads);
    const InMemoryDem dem(*doc.dem);
    CurveDataCache data(qt, dem.heights());
    RegionTiles t;
    t.appearance = produceAppearanceTiles(quads, qt, data, dem, {});
    t.elevation = produceElevationTiles(quads, qt, data, dem, {});
    for (const Quad* q : quads)
        for (const QuadLayer& l : q->layers)
            for (const auto& [id, pieces] : l.curves)
                if (const ProceduralCurve* p = qt.proceduralCurve(0, id); p && (p->curve.flags & kBridge) && !pieces.empty()) ++t.bridges;
    t.roundaboutRoads = step.counters().roundaboutRoads;
    return t;
}

class SceneRegion : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::filesystem::path(test::scratchDir("scene_region"));
        SceneDocument doc;
        doc.scene = makeSyntheticScene({.seed = 7, .curves = 20000, .roundaboutFraction = 0.3});
        doc.dem = makeSyntheticDem(doc.scene, {.seed = 7, .resolution = 5000});
        path_ = new std::string((*dir_ / "scene.gpkg").string());
        saveScene(*path_, doc);
        whole_ = new SceneDocument(loadScene(*path_));
    }
    static void TearDownTestSuite() {
        std::filesystem::remove_all(*dir_);
        delete whole_;
        delete path_;
        delete dir_;
    }
    static std::filesystem::path* dir_;
    static std::string* path_;
    static SceneDocument* whole_;
};
std::filesystem::path* SceneRegion::dir_ = nullptr;
std::string* SceneRegion::path_ = nullptr;
SceneDocument* SceneRegion::whole_ = nullptr;

TEST_F(SceneRegion, RandomRegionsGiveTheWholeScenesTilesFromWhatTheyRead) {
    const Box extent = whole_->scene.extent;
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    constexpr int kRegions = 40;
    std::size_t bridges = 0, roundabouts = 0, partial = 0;
    for (int k = 0; k < kRegions; ++k) {
        const int level = 5 + k % 3;  // quads of 560 m to 140 m over a 17.9 km extent
        const Vec2 size = extent.size();
        const double side = size.x * (0.002 + 0.05 * unit(rng));
        const Vec2 at = extent.min + Vec2(unit(rng), unit(rng)) * (size - side);
        const Box region{at, at + side};
        SceneRegionStats stats;
        const SceneDocument part = loadSceneRegion(*path_, region, {}, level, &stats);
        SCOPED_TRACE("region " + std::to_string(k) + " at level " + std::to_string(level));
        EXPECT_FALSE(stats.wholeScene);
        EXPECT_GT(stats.found, 0u);
        EXPECT_EQ(stats.sceneCurves, [&] {
            std::size_t n = 0;
            for (const Layer& l : whole_->scene.layers) n += l.curves.size();
            return n;
        }());
        if (stats.curves < stats.sceneCurves / 2) ++partial;
        const RegionTiles a = tilesOf(*whole_, region, level), b = tilesOf(part, region, level);
        ASSERT_EQ(a.appearance.size(), b.appearance.size());
        for (std::size_t q = 0; q < a.appearance.size(); ++q) {
            EXPECT_TRUE(a.appearance[q] == b.appearance[q]) << "appearance tile " << q;
            EXPECT_TRUE(a.elevation[q] == b.elevation[q]) << "elevation tile " << q;
        }
        EXPECT_EQ(a.bridges, b.bridges);
        bridges += b.bridges;
        roundabouts += b.roundaboutRoads;
    }
    EXPECT_EQ(partial, std::size_t(kRegions));  // each region read less than half of the scene
    EXPECT_GT(bridges, 0u);      // the regions held bridges...
    EXPECT_GT(roundabouts, 0u);  // ...and roads trimmed at roundabouts
}

TEST_F(SceneRegion, ARegionOnTheQuadBordersAtEveryLevelGivesTheSameTiles) {
    const Vec2 c = whole_->scene.extent.center();
    const Box region{c - 1.0, c + 1.0};  // the corner of the four quads of level 1, and of every level below
    const SceneDocument part = loadSceneRegion(*path_, region, {}, 6);
    const RegionTiles a = tilesOf(*whole_, region, 6), b = tilesOf(part, region, 6);
    ASSERT_EQ(a.appearance.size(), 4u);
    EXPECT_TRUE(a.appearance == b.appearance);
    EXPECT_TRUE(a.elevation == b.elevation);
}

TEST_F(SceneRegion, AFileWithoutTheFeatureIndexIsReadWhole) {
    const std::string copy = (*dir_ / "old.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(copy, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("DROP TABLE ") + kFeatureIndexTable);
    }
    const Vec2 c = whole_->scene.extent.center();
    SceneRegionStats stats;
    const SceneDocument part = loadSceneRegion(copy, {c - 100.0, c + 100.0}, {}, 6, &stats);
    EXPECT_TRUE(stats.wholeScene);
    EXPECT_EQ(stats.curves, stats.sceneCurves);
    EXPECT_TRUE(part.scene.layers.size() == whole_->scene.layers.size());
}

TEST_F(SceneRegion, ACorruptIndexIsRefusedNamingTheFileAndTable) {
    const std::string copy = (*dir_ / "corrupt.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(copy, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("UPDATE ") + kFeatureIndexTable + " SET max_curve_wf = -1");
    }
    const Vec2 c = whole_->scene.extent.center();
    try {
        loadSceneRegion(copy, {c - 100.0, c + 100.0}, {}, 6);
        FAIL() << "a corrupt index was read";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find(copy), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(kFeatureIndexTable), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadSceneRegion(*path_, {c + 1.0, c - 1.0}, {}, 6), std::invalid_argument);
    EXPECT_THROW(loadSceneRegion(*path_, {c - 1.0, c + 1.0}, {}, 31), std::invalid_argument);
}

}  // namespace
}  // namespace lacet
