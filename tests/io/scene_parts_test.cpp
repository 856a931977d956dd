// A scene file read a part at a time (io/scene_parts.h) gives the river and bridge checks of the
// scene read whole, exactly: each river curve, node, bridge and point under a deck counted once, in
// the part that owns it, with what it depends on (the rivers upstream, the rivers a road crosses)
// read there; a part over its budget is refused by name.
#include "io/scene_parts.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "io/dem_stream.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "io/sqlite_db.h"
#include "raster/bridge_check.h"
#include "raster/river_check.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

void expectSameQuantiles(const Quantiles& a, const Quantiles& b, const char* what) {
    EXPECT_EQ(a.count, b.count) << what;
    for (const auto& [x, y] : {std::pair{a.min, b.min}, {a.p01, b.p01}, {a.p05, b.p05}, {a.median, b.median}, {a.p95, b.p95},
                               {a.p99, b.p99}, {a.max, b.max}, {a.fractionOver, b.fractionOver}})
        EXPECT_EQ(x, y) << what;
}

TEST(SceneParts, TheRiverAndBridgeChecksByPartsAreTheWholeScenesEachElementCountedOnce) {
    const std::filesystem::path dir = test::scratchDir("scene_parts");
    const std::string path = (dir / "scene.gpkg").string();
    SceneDocument doc;
    doc.scene = makeSyntheticScene({.seed = 9, .curves = 12000});
    doc.dem = makeSyntheticDem(doc.scene, {.seed = 9, .resolution = 1000});
    saveScene(path, doc);
    const SceneDocument loaded = loadScene(path);
    const RiverCheckReport whole = checkRivers(loaded.scene, *batchDemSource(loaded, 512.0));
    const BridgeCheckReport wholeBridges = checkBridges(loaded.scene, *batchDemSource(loaded, 512.0));
    ASSERT_GT(whole.curves, 20u);
    ASSERT_GT(whole.nodesAboveDem.count, 20u);
    ASSERT_GT(wholeBridges.riverSpans, 5u);
    ASSERT_GT(wholeBridges.bedPoints, 100u);
    for (const double parts : {2.0, 8.0}) {
        RiverCheck check;
        BridgeCheck bridges;
        const ScenePartsRead read = forEachScenePart(path, doc.scene.extent.size().x / parts, 1024.0, 512.0,
                                                     [&](const SceneDocument& part, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
                                                         check.add(part.scene, dem, owns);
                                                         bridges.add(part.scene, dem, owns);
                                                     });
        EXPECT_EQ(read.reads, std::size_t(parts * parts));
        const RiverCheckReport r = check.finish();
        EXPECT_EQ(r.curves, whole.curves) << parts;
        EXPECT_EQ(r.risingSamples, whole.risingSamples) << parts;
        expectSameQuantiles(r.profileAboveDem, whole.profileAboveDem, "profiles");
        expectSameQuantiles(r.nodesAboveDem, whole.nodesAboveDem, "nodes");
        const BridgeCheckReport b = bridges.finish();
        EXPECT_FALSE(b.graphCounters);
        EXPECT_EQ(b.bridges, wholeBridges.bridges) << parts;
        EXPECT_EQ(b.importedBridges, wholeBridges.importedBridges) << parts;
        EXPECT_EQ(b.proceduralBridges, wholeBridges.proceduralBridges) << parts;
        EXPECT_EQ(b.riverSpans, wholeBridges.riverSpans) << parts;
        EXPECT_EQ(b.deckSamples, wholeBridges.deckSamples) << parts;
        EXPECT_EQ(b.deckSamplesBelowClearance, wholeBridges.deckSamplesBelowClearance) << parts;
        EXPECT_EQ(b.leastClearance, wholeBridges.leastClearance) << parts;
        EXPECT_EQ(b.bedPoints, wholeBridges.bedPoints) << parts;
        EXPECT_EQ(b.bedPointsDiffering, wholeBridges.bedPointsDiffering) << parts;
        EXPECT_EQ(b.largestBedDifference, wholeBridges.largestBedDifference) << parts;
    }
    EXPECT_THROW(forEachScenePart(path, 1000.0, 0.001, 512.0, [](const SceneDocument&, const DemSource&, const std::function<bool(Vec2)>&) {}),
                 SceneBudgetError);
    // Parts so small that there would be more than kMaxSceneParts: refused before any read.
    EXPECT_THROW(forEachScenePart(path, 1e-3, 1024.0, 512.0, [](const SceneDocument&, const DemSource&, const std::function<bool(Vec2)>&) {}),
                 std::invalid_argument);
    // A file saved before the feature index: its first read is the whole scene, the one part.
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("DROP TABLE ") + kFeatureIndexTable);
        db.close();
    }
    RiverCheck check;
    const ScenePartsRead read = forEachScenePart(path, doc.scene.extent.size().x / 8.0, 1024.0, 512.0,
                                                 [&](const SceneDocument& part, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
                                                     check.add(part.scene, dem, owns);
                                                 });
    EXPECT_TRUE(read.wholeScene);
    EXPECT_EQ(read.reads, 1u);
    const RiverCheckReport once = check.finish();
    EXPECT_EQ(once.curves, whole.curves);
    expectSameQuantiles(once.profileAboveDem, whole.profileAboveDem, "profiles read whole");
    std::filesystem::remove_all(dir);
}

TEST(SceneParts, EachPointIsOnePartsTheExtentsBordersAndBeyondIncluded) {
    const std::filesystem::path dir = test::scratchDir("scene_parts_owns");
    const std::string path = (dir / "scene.gpkg").string();
    SceneDocument doc;
    doc.scene = makeSyntheticScene({.seed = 4, .curves = 300});
    doc.dem = makeSyntheticDem(doc.scene, {.seed = 4, .resolution = 500});
    saveScene(path, doc);
    const Box e = doc.scene.extent;
    const Vec2 s = e.size();
    const std::vector<Vec2> points = {e.min, e.max, {e.max.x, e.min.y}, e.center(), e.min + s * 0.25, e.min + s * 0.5,
                                      e.min - Vec2(50.0), e.max + Vec2(50.0), {e.min.x + s.x * 0.75, e.max.y + 1.0}};
    std::vector<int> owners(points.size(), 0);
    forEachScenePart(path, s.x / 4.0, 1024.0, 512.0, [&](const SceneDocument&, const DemSource&, const std::function<bool(Vec2)>& owns) {
        for (std::size_t k = 0; k < points.size(); ++k) owners[k] += owns(points[k]);
    });
    for (std::size_t k = 0; k < points.size(); ++k) EXPECT_EQ(owners[k], 1) << points[k].x << "," << points[k].y;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
