// Roundabouts (§4.3, Fig. 5 right): roads trimmed at the ring, the ring's arcs chained around the
// node, refusals, the edit, and the ring through the graph step and the quadtree.
#include "model/roundabouts.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/graph_step.h"
#include "model/quadtree.h"

namespace lacet {
namespace {

constexpr double kPi = std::numbers::pi;

// Roads meeting at one node: road k leaves at angles[k] (radians), a cubic that bends by up to
// `bend` metres sideways, `length` metres long; every other road is stored from its far end to
// the node (so the node is its end).
struct RoundaboutStar {
    Scene scene;
    ElementId centre = 0;
    std::vector<ElementId> roads;
    RoundaboutStar(Vec2 at, const std::vector<double>& angles, double length = 100.0, double bend = 15.0, unsigned seed = 1) {
        scene.extent = {at - 1000.0, at + 1000.0};
        scene.layers.resize(1);
        scene.layers[0].name = "roads";
        scene.layers[0].kind = LayerKind::Roads;
        Layer& l = scene.layers[0];
        centre = l.addNode(at);
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> side(-bend, bend);
        for (std::size_t k = 0; k < angles.size(); ++k) {
            const Vec2 dir(std::cos(angles[k]), std::sin(angles[k]));
            const Vec2 normal(-dir.y, dir.x);
            const Vec2 far = at + dir * length;
            const ElementId farNode = l.addNode(far);
            std::vector<Vertex> v = {{at},
                                     {at + dir * (0.35 * length) + normal * side(rng), false},
                                     {at + dir * (0.7 * length) + normal * side(rng), false},
                                     {far}};
            Curve c;
            const bool reversed = k % 2 == 1;
            if (reversed) std::reverse(v.begin(), v.end());
            c.vertices = v;
            c.start = reversed ? farNode : centre;
            c.end = reversed ? centre : farNode;
            c.w = float(5 + k);
            c.wf = c.w + 4.0f;
            c.cls = std::uint16_t(k);
            roads.push_back(l.addCurve(c));
        }
    }
};

std::vector<double> evenAngles(int degree, double jitterRadians, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-jitterRadians, jitterRadians);
    std::vector<double> a;
    for (int k = 0; k < degree; ++k) a.push_back(2.0 * kPi * k / degree + jitter(rng));
    return a;
}

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Checks the ring at `node`: every road end there is trimmed on the circle, its arc starts
// exactly where it is trimmed, the arcs chain end to start exactly around the full circle (2π),
// each on-curve vertex within `onCircle` metres of the circle, each piece at most 90 degrees and
// its midpoint within the cubic's error of the circle. Returns the arcs.
std::vector<ProceduralCurve> checkRing(const Scene& scene, LayerId layer, ElementId node, double onCircle) {
    const Layer& l = scene.layers[layer];
    const Vec2 c = l.nodes[node].p;
    const double r = double(l.nodes[node].roundabout);
    std::vector<ProceduralCurve> arcs;
    float widest = 0.0f;
    std::vector<ElementId> seen;
    for (ElementId id : l.nodes[node].curves) {
        if (std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
        seen.push_back(id);
        const Curve& road = l.curves[id];
        widest = std::max(widest, road.w);
        const auto cut = roundaboutCut(scene, layer, id);
        EXPECT_TRUE(cut.has_value()) << "road " << id;
        if (!cut) continue;
        if (road.start == node) {
            EXPECT_TRUE(cut->trimmedStart);
        }
        if (road.end == node) {
            EXPECT_TRUE(cut->trimmedEnd);
        }
        EXPECT_LT(cut->s0, cut->s1);
        EXPECT_EQ(cut->arcs.size(), std::size_t(cut->trimmedStart) + std::size_t(cut->trimmedEnd));
        const std::vector<Vertex> kept = subSpline(road.vertices, cut->s0, cut->s1);
        // The arcs come in the order of the road's ends: its start's ring first.
        for (const bool atStart : {true, false}) {
            if ((atStart ? road.start : road.end) != node) continue;
            const ProceduralCurve& arc = cut->arcs.at(atStart ? 0 : cut->arcs.size() - 1);
            EXPECT_EQ(arc.ringAtStart, node);
            const Vec2 trimmed = atStart ? kept.front().p : kept.back().p;
            EXPECT_NEAR(glm::length(trimmed - c), r, onCircle);
            EXPECT_NEAR(glm::length(trimmed - arc.curve.vertices.front().p), 0.0, onCircle)
                << "road " << id << (atStart ? " start" : " end");
            arcs.push_back(arc);
        }
    }
    double total = 0.0;
    for (const ProceduralCurve& pc : arcs) {
        EXPECT_EQ(pc.curve.flags, kRoundabout);
        EXPECT_EQ(pc.ringAtStart, node);
        EXPECT_EQ(pc.ringAtEnd, node);
        EXPECT_EQ(pc.curve.start, kNoElement);
        EXPECT_EQ(pc.curve.end, kNoElement);
        EXPECT_FALSE(pc.followsRoot());
        EXPECT_TRUE(std::isnan(pc.rootS1));
        EXPECT_EQ(pc.curve.w, widest);
        // Exactly one arc starts where this one ends.
        const Vec2 end = pc.curve.vertices.back().p;
        EXPECT_EQ(std::count_if(arcs.begin(), arcs.end(),
                                [&](const ProceduralCurve& o) { return o.curve.vertices.front().p == end; }),
                  1);
        forEachPiece(pc.curve.vertices, [&](const BezierPiece& b, std::size_t) {
            EXPECT_EQ(b.degree, 3);
            const Vec2 a0 = b.start() - c, a1 = b.end() - c;
            EXPECT_NEAR(glm::length(a0), r, onCircle);
            EXPECT_NEAR(glm::length(a1), r, onCircle);
            const double sweep = std::atan2(cross(a0, a1), glm::dot(a0, a1));
            EXPECT_GT(sweep, 0.0);  // counter-clockwise
            EXPECT_LE(sweep, kPi / 2.0 + 1e-12);
            total += sweep;
            EXPECT_NEAR(glm::length(evaluate(b, 0.5) - c), r, 2.8e-4 * r);
        });
    }
    EXPECT_NEAR(total, 2.0 * kPi, 1e-9);
    return arcs;
}

TEST(Roundabouts, DegreeOneThroughSixArcsChainAroundTheFullCircle) {
    for (int degree = 1; degree <= 6; ++degree) {
        SCOPED_TRACE(degree);
        RoundaboutStar s({300.0, 200.0}, evenAngles(degree, 0.15, unsigned(degree)), 100.0, 15.0, unsigned(degree));
        EXPECT_EQ(roundaboutCut(s.scene, 0, s.roads[0]), std::nullopt);  // no ring yet
        ASSERT_EQ(roundaboutRefusal(s.scene, 0, s.centre, 15.0f), std::nullopt);
        setNodeRoundabout(s.scene, 0, s.centre, 15.0f);
        const auto arcs = checkRing(s.scene, 0, s.centre, 1e-9);
        EXPECT_EQ(arcs.size(), std::size_t(degree));
        if (degree == 1) {
            EXPECT_EQ(arcs[0].curve.vertices.front().p, arcs[0].curve.vertices.back().p);
            EXPECT_EQ(arcs[0].curve.vertices.size(), 13u);  // four quarter circles
        }
        // A pure function of the scene.
        const Scene copy = s.scene;
        for (ElementId id : s.roads) {
            const auto a = roundaboutCut(s.scene, 0, id), b = roundaboutCut(copy, 0, id);
            ASSERT_TRUE(a && b);
            EXPECT_EQ(a->s0, b->s0);
            EXPECT_EQ(a->s1, b->s1);
            ASSERT_EQ(a->arcs.size(), b->arcs.size());
            for (std::size_t k = 0; k < a->arcs.size(); ++k)
                EXPECT_EQ(a->arcs[k].curve.vertices, b->arcs[k].curve.vertices);
        }
    }
}

TEST(Roundabouts, RandomStarsEitherFitWithAChainedRingOrAreRefused) {
    std::mt19937 rng(2008);
    std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi), radius(3.0, 40.0);
    std::uniform_int_distribution<int> degree(1, 6);
    int fitted = 0, refused = 0;
    for (int trial = 0; trial < 60; ++trial) {
        std::vector<double> angles(std::size_t(degree(rng)));
        for (double& a : angles) a = angle(rng);
        RoundaboutStar s({5000.0, -3000.0}, angles, 60.0, 20.0, unsigned(trial));
        const auto r = float(radius(rng));
        s.scene.layers[0].nodes[s.centre].roundabout = r;  // bypassing the edit: the cut refuses alike
        if (roundaboutRefusal(s.scene, 0, s.centre, r)) {
            ++refused;
            for (ElementId id : s.roads) EXPECT_EQ(roundaboutCut(s.scene, 0, id), std::nullopt);
            EXPECT_THROW(setNodeRoundabout(s.scene, 0, s.centre, r), EditError);
        } else {
            ++fitted;
            SCOPED_TRACE(trial);
            checkRing(s.scene, 0, s.centre, 1e-9);
        }
    }
    EXPECT_GT(fitted, 20);
    EXPECT_GT(refused, 5);
}

TEST(Roundabouts, AClosedRoadAtTheNodeCarriesTwoArcs) {
    // A loop leaving the node eastwards and coming back from the north, plus a road to the west.
    Scene scene;
    scene.extent = {{-500, -500}, {500, 500}};
    scene.layers.resize(1);
    scene.layers[0].kind = LayerKind::Roads;
    Layer& l = scene.layers[0];
    const ElementId n = l.addNode({0, 0}), w = l.addNode({-80, 0});
    Curve loop;
    loop.vertices = {{{0, 0}}, {{120, 0}, false}, {{0, 120}, false}, {{0, 0}}};
    loop.start = loop.end = n;
    loop.w = 6;
    loop.wf = 10;
    const ElementId loopId = l.addCurve(loop);
    Curve west;
    west.vertices = {{{0, 0}}, {{-80, 0}}};
    west.start = n;
    west.end = w;
    west.w = 8;
    west.wf = 12;
    l.addCurve(west);
    setNodeRoundabout(scene, 0, n, 10.0f);
    const auto arcs = checkRing(scene, 0, n, 1e-9);
    EXPECT_EQ(arcs.size(), 3u);
    const auto cut = roundaboutCut(scene, 0, loopId);
    ASSERT_TRUE(cut);
    EXPECT_TRUE(cut->trimmedStart && cut->trimmedEnd);
    EXPECT_EQ(cut->arcs.size(), 2u);
    EXPECT_EQ(arcs[0].curve.w, 8.0f);  // the widest road's
}

TEST(Roundabouts, ARadiusLargerThanAConnectedRoadIsRefusedWithTheReason) {
    RoundaboutStar s({0.0, 0.0}, {0.0, 2.0}, 100.0, 0.0);
    // A short third road: both its ends within 20 m of the node.
    Layer& l = s.scene.layers[0];
    const ElementId near = l.addNode({-5.0, -12.0});
    Curve shortRoad;
    shortRoad.vertices = {{{0, 0}}, {{-5, -12}}};
    shortRoad.start = s.centre;
    shortRoad.end = near;
    shortRoad.w = 4;
    shortRoad.wf = 6;
    const ElementId shortId = l.addCurve(shortRoad);
    const auto reason = roundaboutRefusal(s.scene, 0, s.centre, 20.0f);
    ASSERT_TRUE(reason);
    EXPECT_NE(reason->find("road " + std::to_string(shortId)), std::string::npos) << *reason;
    EXPECT_NE(reason->find("does not leave"), std::string::npos) << *reason;
    EXPECT_NE(reason->find("20 m"), std::string::npos) << *reason;
    const Scene before = s.scene;
    try {
        setNodeRoundabout(s.scene, 0, s.centre, 20.0f);
        ADD_FAILURE() << "not refused";
    } catch (const EditError& e) {
        EXPECT_NE(std::string(e.what()).find(*reason), std::string::npos) << e.what();
    }
    EXPECT_EQ(s.scene.layers[0].nodes[s.centre].roundabout, 0.0f);
    EXPECT_EQ(s.scene.layers[0].nodes.size(), before.layers[0].nodes.size());
    // 10 m fits (the short road is 13 m long).
    EXPECT_EQ(roundaboutRefusal(s.scene, 0, s.centre, 10.0f), std::nullopt);
    // Nonsense radii.
    for (float r : {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 501.0f})
        EXPECT_TRUE(roundaboutRefusal(s.scene, 0, s.centre, r)) << r;
    EXPECT_EQ(roundaboutRefusal(s.scene, 0, s.centre, 0.0f), std::nullopt);
    EXPECT_TRUE(roundaboutRefusal(s.scene, 0, 999, 5.0f));
    s.scene.layers[0].kind = LayerKind::Rivers;
    EXPECT_TRUE(roundaboutRefusal(s.scene, 0, s.centre, 5.0f));
}

TEST(Roundabouts, TwoRoadsEnteringWithinTheSameArcAreRefused) {
    // Straight roads 5 degrees apart: 1.75 m apart on a ring of 20 m, less than the 4 m asked.
    const double d = 5.0 * kPi / 180.0;
    RoundaboutStar s({0.0, 0.0}, {0.0, d, kPi}, 100.0, 0.0);
    const auto reason = roundaboutRefusal(s.scene, 0, s.centre, 20.0f);
    ASSERT_TRUE(reason);
    EXPECT_NE(reason->find("roads " + std::to_string(s.roads[0]) + " and " + std::to_string(s.roads[1])),
              std::string::npos)
        << *reason;
    EXPECT_NE(reason->find("apart along the ring"), std::string::npos) << *reason;
    EXPECT_THROW(setNodeRoundabout(s.scene, 0, s.centre, 20.0f), EditError);
    // A larger separation allowed by the parameters... and a ring where they are far enough apart.
    EXPECT_EQ(roundaboutRefusal(s.scene, 0, s.centre, 20.0f, {.minEntrySeparation = 1.0}), std::nullopt);
    EXPECT_EQ(roundaboutRefusal(s.scene, 0, s.centre, 60.0f), std::nullopt);
}

TEST(Roundabouts, ARoadBetweenTwoRingsMustKeepSomeRoad) {
    Scene scene;
    scene.extent = {{-500, -500}, {500, 500}};
    scene.layers.resize(1);
    scene.layers[0].kind = LayerKind::Roads;
    Layer& l = scene.layers[0];
    const ElementId a = l.addNode({0, 0}), b = l.addNode({50, 0}), ea = l.addNode({-60, 0}), eb = l.addNode({110, 0});
    auto road = [&](ElementId from, ElementId to) {
        Curve c;
        c.vertices = {{l.nodes[from].p}, {l.nodes[to].p}};
        c.start = from;
        c.end = to;
        c.w = 6;
        c.wf = 8;
        return l.addCurve(c);
    };
    const ElementId ab = road(a, b);
    road(ea, a);
    road(b, eb);
    setNodeRoundabout(scene, 0, a, 20.0f);
    EXPECT_TRUE(roundaboutRefusal(scene, 0, b, 35.0f));  // 20 + 35 > 50
    setNodeRoundabout(scene, 0, b, 25.0f);
    const auto cut = roundaboutCut(scene, 0, ab);
    ASSERT_TRUE(cut);
    EXPECT_TRUE(cut->trimmedStart && cut->trimmedEnd);
    EXPECT_NEAR(cut->s0, 20.0 / 50.0, 1e-12);
    EXPECT_NEAR(cut->s1, 25.0 / 50.0, 1e-12);
    EXPECT_EQ(cut->arcs.size(), 2u);
    checkRing(scene, 0, a, 1e-9);
    checkRing(scene, 0, b, 1e-9);
}

TEST(Roundabouts, TheEditReportsTheNodeAndEveryCurveAtIt) {
    RoundaboutStar s({0.0, 0.0}, evenAngles(3, 0.0, 1), 100.0, 10.0);
    const Changeset cs = setNodeRoundabout(s.scene, 0, s.centre, 12.0f);
    EXPECT_EQ(s.scene.layers[0].nodes[s.centre].roundabout, 12.0f);
    std::vector<ElementRef> expected = {{0, ElementKind::Node, s.centre}};
    for (ElementId id : s.roads) expected.push_back({0, ElementKind::Curve, id});
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(cs.added, expected);
    EXPECT_EQ(cs.removed, expected);
    setNodeRoundabout(s.scene, 0, s.centre, -0.0f);
    EXPECT_EQ(roundaboutCut(s.scene, 0, s.roads[0]), std::nullopt);
    EXPECT_FALSE(std::signbit(s.scene.layers[0].nodes[s.centre].roundabout));
    EXPECT_THROW(setNodeRoundabout(s.scene, 0, 999, 5.0f), EditError);
}

TEST(Roundabouts, HugeCoordinatesKeepTheRingOnTheCircle) {
    // 1e7 m from the origin a double's spacing is 1.9e-9 m: the points are on the circle to it.
    for (int degree : {1, 3, 5}) {
        SCOPED_TRACE(degree);
        RoundaboutStar s({1.0e7 + 0.123, -1.0e7 + 0.456}, evenAngles(degree, 0.2, 7), 100.0, 15.0, 7);
        setNodeRoundabout(s.scene, 0, s.centre, 18.5f);
        checkRing(s.scene, 0, s.centre, 5e-9);
    }
}

// The pieces of the ring in the leaves of a tree built with the graph step: on the circle (the
// clipped vertices lie on the arcs), on both sides of each border the ring crosses.
void checkRingInLeaves(const Quadtree& tree, LayerId layer, Vec2 c, double r, std::size_t expectedArcs) {
    std::vector<const Quad*> leaves;
    std::vector<const Quad*> stack = {&tree.root()};
    while (!stack.empty()) {
        const Quad* q = stack.back();
        stack.pop_back();
        if (q->isLeaf()) leaves.push_back(q);
        else
            for (const auto& ch : q->children) stack.push_back(ch.get());
    }
    std::vector<AncestorId> arcIds;
    std::size_t quadsWithRing = 0;
    for (const Quad* q : leaves) {
        bool any = false;
        for (const auto& [id, pieces] : q->layers[layer].curves) {
            const ProceduralCurve* pc = tree.proceduralCurve(layer, id);
            if (!pc || !(pc->curve.flags & kRoundabout)) continue;
            any = true;
            if (std::find(arcIds.begin(), arcIds.end(), id) == arcIds.end()) arcIds.push_back(id);
            for (const ClippedCurve& cc : pieces)
                for (const Vertex& v : cc.vertices)
                    if (v.onCurve) {
                        EXPECT_NEAR(glm::length(v.p - c), r, 2.8e-4 * r);
                    }
        }
        quadsWithRing += any ? 1 : 0;
    }
    EXPECT_EQ(arcIds.size(), expectedArcs);
    EXPECT_GE(quadsWithRing, 2u);
}

TEST(Roundabouts, NearAQuadBorderTheRingIsClippedOnBothSides) {
    // The node 3 m left of the vertical border x = 1000 and 2 m below y = 1000 of a 2 km root: the
    // ring of 25 m lies in the four children.
    RoundaboutStar s({997.0, 998.0}, evenAngles(4, 0.1, 3), 200.0, 20.0, 3);
    s.scene.extent = {{0.0, 0.0}, {2000.0, 2000.0}};
    setNodeRoundabout(s.scene, 0, s.centre, 25.0f);
    GraphStep step(s.scene);
    Quadtree tree(s.scene, {}, &step);
    tree.subdivide(tree.root());
    for (auto& ch : tree.root().children) tree.subdivide(*ch);
    checkRingInLeaves(tree, 0, s.scene.layers[0].nodes[s.centre].p, 25.0, 4);
    for (ElementId id : s.roads) {
        const auto expansion = tree.expansionOf(0, id);
        ASSERT_EQ(expansion.size(), 2u);  // the trimmed road, its arc
        const ProceduralCurve* road = tree.proceduralCurve(0, expansion[0]);
        ASSERT_TRUE(road);
        EXPECT_TRUE(road->curve.flags & (kYieldAtStart | kYieldAtEnd));
    }
    std::size_t quadsWithRing = 0;
    for (const auto& ch : tree.root().children)
        for (const auto& [id, pieces] : ch->layers[0].curves) {
            const ProceduralCurve* pc = tree.proceduralCurve(0, id);
            if (pc && (pc->curve.flags & kRoundabout)) {
                ++quadsWithRing;
                break;
            }
        }
    EXPECT_EQ(quadsWithRing, 4u);
}

TEST(Roundabouts, MovingTheNodeMovesTheRing) {
    RoundaboutStar s({500.0, 500.0}, evenAngles(3, 0.1, 5), 150.0, 10.0, 5);
    s.scene.extent = {{0.0, 0.0}, {1000.0, 1000.0}};
    setNodeRoundabout(s.scene, 0, s.centre, 20.0f);
    GraphStep step(s.scene);
    Quadtree tree(s.scene, {}, &step);
    tree.subdivide(tree.root());
    const Vec2 moved(507.0, 493.5);
    const Changeset cs = moveNode(s.scene, 0, s.centre, moved);
    tree.update(cs);
    checkRing(s.scene, 0, s.centre, 1e-9);
    checkRingInLeaves(tree, 0, moved, 20.0, 3);
    // The tree's procedural curves are those a fresh expansion makes.
    for (ElementId id : s.roads) {
        const auto cut = roundaboutCut(s.scene, 0, id);
        ASSERT_TRUE(cut);
        const auto expansion = tree.expansionOf(0, id);
        ASSERT_EQ(expansion.size(), 2u);
        const ProceduralCurve* arc = tree.proceduralCurve(0, expansion[1]);
        ASSERT_TRUE(arc);
        EXPECT_EQ(arc->curve.vertices, cut->arcs.at(0).curve.vertices);
    }
}

}  // namespace
}  // namespace lacet
