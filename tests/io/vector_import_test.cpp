// The vector reader's curve flags from OSM tags, through the whole import (chains merged only
// between curves of the same flags).
#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "io/scene_frame.h"
#include "io/scene_import.h"
#include "model/validate.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

TEST(VectorImport, JunctionRoundaboutWaysAreRoundaboutCurvesKeptApartFromTheirRoads) {
    const auto dir = test::scratchDir("roundabout");
    ImportOptions o;
    o.dem = {test::writeFixtureDem(dir)};
    o.vectors = {test::vectorData("roundabout.osm")};
    ImportReport r;
    const SceneDocument doc = importScene(o, r);
    EXPECT_TRUE(validate(doc.scene).empty());
    const Layer& roads = doc.scene.layers[0];
    ASSERT_EQ(roads.kind, LayerKind::Roads);
    // The OSM node each scene node stands on (junction positions are exact projections).
    const SceneFrame frame(doc.georeference);
    const std::map<int, glm::dvec2> osm = {
        {1, {1.520367, 42.52}},  {3, {1.519633, 42.52}},  {5, {1.522, 42.52}},    {8, {1.517, 42.52}},
        {21, {1.5302, 42.53}},   {31, {1.51, 42.51}},     {32, {1.512, 42.5101}}, {33, {1.514, 42.51}}};
    auto osmNode = [&](ElementId n) {
        for (const auto& [id, lonLat] : osm)
            if (roads.nodes[n].p == frame.forward(lonLat)) return id;
        return 0;
    };
    // Each curve by its end nodes: (start, end) -> flags; a merge across a flag change would make
    // a curve 31 -> 33.
    std::map<std::pair<int, int>, std::uint16_t> curves;
    for (const Curve& c : roads.curves)
        if (c.alive) curves[{osmNode(c.start), osmNode(c.end)}] = c.flags;
    const std::map<std::pair<int, int>, std::uint16_t> expected = {
        {{1, 3}, kRoundabout}, {{3, 1}, kRoundabout},  // the ring's two ways, meeting roads at 1 and 3
        {{5, 1}, 0},           {{3, 8}, 0},            // the roads meeting it
        {{21, 21}, kRoundabout},                       // the closed mini roundabout, one closed curve
        {{31, 32}, 0},         {{32, 33}, kRoundabout}};
    EXPECT_EQ(curves, expected);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
