// Stop lines from the ancestor node's degree (Fig. 3-4) and junction radii.
#include "model/junctions.h"

#include <gtest/gtest.h>

#include "tests/raster/hand_scenes.h"

namespace lacet {
namespace {

// Curves meeting at one node at the given directions (degrees), each 50 m long.
struct Star {
    Layer layer;
    ElementId centre;
    std::vector<ElementId> curves;
    Star(std::initializer_list<double> degrees, bool reverseFirst = false) {
        centre = layer.addNode({0, 0});
        bool first = true;
        for (double d : degrees) {
            const double a = d * std::numbers::pi / 180.0;
            const ElementId far = layer.addNode({50.0 * std::cos(a), 50.0 * std::sin(a)});
            Curve c;
            const bool reverse = first && reverseFirst;
            c.start = reverse ? far : centre;
            c.end = reverse ? centre : far;
            c.vertices = {{layer.nodes[c.start].p}, {layer.nodes[c.end].p}};
            c.w = float(4 + curves.size());
            c.wf = c.w + 6.0f;
            curves.push_back(layer.addCurve(c));
            first = false;
        }
    }
};

TEST(Junctions, FourWayJunctionsHaveAStopLineOnEveryRoad) {
    const Star s({0, 90, 180, 270});
    EXPECT_EQ(nodeDegree(s.layer, s.centre), 4);
    for (ElementId c : s.curves) EXPECT_TRUE(hasStopLine(s.layer, s.centre, c));
    EXPECT_DOUBLE_EQ(junctionRadius(s.layer, s.centre), 0.5 * 7.0);
}

TEST(Junctions, ThreeWayJunctionsHaveAStopLineOnTheRoadThatMeetsTheOtherTwo) {
    // The stem is the road at 100 degrees; the through road bends slightly (0 and 170 degrees).
    for (bool reverseFirst : {false, true}) {
        const Star s({0, 100, 170}, reverseFirst);
        EXPECT_FALSE(hasStopLine(s.layer, s.centre, s.curves[0]));
        EXPECT_TRUE(hasStopLine(s.layer, s.centre, s.curves[1]));
        EXPECT_FALSE(hasStopLine(s.layer, s.centre, s.curves[2]));
    }
    // A skewed Y: 40 and 180 degrees are the most opposite pair (140 degrees apart), so the
    // road at -70 degrees is the stem.
    const Star y({-70, 40, 180});
    EXPECT_TRUE(hasStopLine(y.layer, y.centre, y.curves[0]));
    EXPECT_FALSE(hasStopLine(y.layer, y.centre, y.curves[1]));
    EXPECT_FALSE(hasStopLine(y.layer, y.centre, y.curves[2]));
}

TEST(Junctions, PlainNodesHaveNoStopLineAndNoJunctionRadius) {
    const Star s({0, 180});
    for (ElementId c : s.curves) EXPECT_FALSE(hasStopLine(s.layer, s.centre, c));
    EXPECT_EQ(junctionRadius(s.layer, s.centre), 0.0);
    EXPECT_EQ(nodeDegree(s.layer, kNoElement), 0);
    EXPECT_FALSE(hasStopLine(s.layer, kNoElement, s.curves[0]));
    const Star five({0, 72, 144, 216, 288});
    for (ElementId c : five.curves) EXPECT_TRUE(hasStopLine(five.layer, five.centre, c));
}

TEST(Junctions, TheHandMadeJunctionSceneHasTheExpectedStopLines) {
    const Scene s = test::junctionsScene();
    const Layer& roads = s.layers[kRoadsLayer];
    // Node 0: the 4-way crossing; node 1: the T, whose stem is curve 5.
    for (ElementId c : roads.nodes[0].curves) EXPECT_TRUE(hasStopLine(roads, 0, c));
    for (ElementId c : roads.nodes[1].curves) EXPECT_EQ(hasStopLine(roads, 1, c), c == 5) << "curve " << c;
}

}  // namespace
}  // namespace lacet
