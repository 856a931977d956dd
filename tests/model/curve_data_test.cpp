#include "model/curve_data.h"

#include <cmath>
#include <iostream>
#include <set>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/quadtree_compare.h"
#include "synth/synthetic_scene.h"
#include "tests/model/split_roads.h"

namespace lacet {
namespace {

// Hilly terrain tilted towards -x, with bumps that a river must not climb.
class Hills : public HeightField {
public:
    double height(Vec2 p) const override { return 300.0 + 0.02 * p.x + 8.0 * std::sin(p.x / 90.0) * std::cos(p.y / 130.0); }
};

// Arc length of the ancestor from its start to parameter s, by dense sampling.
double denseU(const Curve& c, double s) {
    double u = 0.0;
    std::size_t k = 0;
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
        const double t1 = std::clamp(s - double(k), 0.0, 1.0);
        Vec2 prev = b.start();
        for (int i = 1; i <= 4000; ++i) {
            const Vec2 p = evaluate(b, t1 * i / 4000.0);
            u += glm::length(p - prev);
            prev = p;
        }
        ++k;
    });
    return u;
}

struct CurveFixture {
    Scene scene = makeSyntheticScene({3, 3000});
    Hills hills;
};

TEST(CurveData, NothingIsComputedUntilAskedAndUMatchesDenseArcLength) {
    CurveFixture f;
    Quadtree qt(f.scene);
    qt.refineForViewer({f.scene.extent.center().x, f.scene.extent.center().y, 20.0}, ViewParams{.maxLevel = 10});
    CurveDataCache cache(qt, f.hills);
    EXPECT_EQ(cache.counters().arcLengthTables, 0u);
    EXPECT_EQ(cache.counters().zProfiles, 0u);
    // u of every on-curve vertex of the road pieces in deep quads equals the ancestor's arc length.
    std::size_t checked = 0;
    qt.forEachQuad([&](const Quad& q) {
        if (q.level < 8) return;
        for (const auto& [a, pieces] : q.layers[kRoadsLayer].curves)
            for (const auto& piece : pieces)
                for (double s : piece.s) {
                    EXPECT_NEAR(cache.u(kRoadsLayer, a, s), denseU(qt.ancestorCurve(kRoadsLayer, a), s), 1e-3);
                    ++checked;
                }
    });
    EXPECT_GT(checked, 20u);
    EXPECT_GT(cache.counters().arcLengthTables, 0u);
    EXPECT_EQ(cache.counters().zProfiles, 0u);  // nobody asked for heights
}

TEST(CurveData, RiversNeverRiseAndCurvesShareTheirNodesHeight) {
    CurveFixture f;
    Quadtree qt(f.scene);
    CurveDataCache cache(qt, f.hills);
    for (LayerId l : {kRoadsLayer, kRiversLayer}) {
        const Layer& layer = f.scene.layers[l];
        for (ElementId c = 0; c < layer.curves.size(); ++c) {
            const ZProfile& z = cache.zProfile(l, c);
            EXPECT_EQ(z.z.front(), cache.nodeHeight(l, layer.curves[c].start));
            EXPECT_EQ(z.z.back(), cache.nodeHeight(l, layer.curves[c].end));
            EXPECT_NEAR(z.length, cache.length(l, c), 1e-9);
            if (l != kRiversLayer) continue;
            for (std::size_t i = 1; i < z.z.size(); ++i) EXPECT_LE(z.z[i], z.z[i - 1]) << "river " << c << " rises at " << i;
        }
    }
}

TEST(CurveData, ProfilesAreSmoothedTerrain) {
    CurveFixture f;
    Quadtree qt(f.scene);
    CurveDataCache cache(qt, f.hills, {5.0, 0.0});  // no smoothing: the profile is the terrain
    const Curve& road = f.scene.layers[kRoadsLayer].curves[0];
    const ZProfile& z = cache.zProfile(kRoadsLayer, 0);
    ASSERT_GT(z.z.size(), 10u);
    // Away from the ends, samples lie on the terrain under the curve.
    const Vec2 mid = evaluate(BezierPiece{3, {road.vertices[0].p, road.vertices[1].p, road.vertices[2].p, road.vertices[3].p}}, 0.5);
    double best = 1e300;
    for (std::size_t i = 1; i + 1 < z.z.size(); ++i) best = std::min(best, std::abs(z.z[i] - f.hills.height(mid)));
    EXPECT_LT(best, 1.0);
}

TEST(CurveData, LakesAreFlatAtTheirLowestBorderHeight) {
    CurveFixture f;
    Quadtree qt(f.scene);
    CurveDataCache cache(qt, f.hills);
    const Layer& lakes = f.scene.layers[kLakesLayer];
    ASSERT_FALSE(lakes.areas.empty());
    const double level = cache.lakeLevel(kLakesLayer, 0);
    for (const auto& e : lakes.areas[0].loops[0])
        for (const auto& v : lakes.curves[e.curve].vertices) {
            if (v.onCurve) {
                EXPECT_LE(level, f.hills.height(v.p) + 1e-9);
            }
        }
}

TEST(CurveData, AnEditDropsOnlyWhatItTouches) {
    CurveFixture f;
    Quadtree qt(f.scene);
    CurveDataCache cache(qt, f.hills);
    const Layer& roads = f.scene.layers[kRoadsLayer];
    for (ElementId c = 0; c < roads.curves.size(); ++c) cache.zProfile(kRoadsLayer, c);
    const std::size_t before = cache.counters().zProfiles;
    const ElementId node = roads.curves[0].start;
    const double oldHeight = cache.nodeHeight(kRoadsLayer, node);
    const auto cs = moveNode(f.scene, kRoadsLayer, node, roads.nodes[node].p + Vec2(150.0, 0.0));
    cache.invalidate(cs);
    qt.update(cs);
    for (ElementId c = 0; c < roads.curves.size(); ++c) cache.zProfile(kRoadsLayer, c);
    // Only the curves at the moved node were recomputed.
    EXPECT_EQ(cache.counters().zProfiles - before, roads.nodes[node].curves.size());
    EXPECT_NE(cache.nodeHeight(kRoadsLayer, node), oldHeight);
    EXPECT_EQ(cache.zProfile(kRoadsLayer, 0).z.front(), cache.nodeHeight(kRoadsLayer, node));
}

TEST(CurveData, RiversStayMonotoneAfterASourceMoves) {
    CurveFixture f;
    Quadtree qt(f.scene);
    CurveDataCache cache(qt, f.hills);
    const Layer& rivers = f.scene.layers[kRiversLayer];
    // Move a source node down into a valley: every profile downstream stays monotone afterwards.
    ElementId source = kNoElement;
    for (ElementId n = 0; n < rivers.nodes.size() && source == kNoElement; ++n)
        if (rivers.nodes[n].curves.size() == 1 && rivers.curves[rivers.nodes[n].curves[0]].start == n) source = n;
    ASSERT_NE(source, kNoElement);
    for (ElementId c = 0; c < rivers.curves.size(); ++c) cache.zProfile(kRiversLayer, c);
    const auto cs = moveNode(f.scene, kRiversLayer, source, rivers.nodes[source].p + Vec2(-400.0, 0.0));
    cache.invalidate(cs);
    for (ElementId c = 0; c < rivers.curves.size(); ++c) {
        const ZProfile& z = cache.zProfile(kRiversLayer, c);
        for (std::size_t i = 1; i < z.z.size(); ++i) EXPECT_LE(z.z[i], z.z[i - 1]);
        EXPECT_EQ(z.z.back(), cache.nodeHeight(kRiversLayer, rivers.curves[c].end));
    }
}

// Issue 13 item 3: proceduralId threw once a root curve id reached 2^23 (and for k >= 256), and
// invalidate() probed 256 procedural ids per curve. Two roads with ids 2^23 and 2^23 + 1 (after as
// many deleted slots), each cut into 300 procedural curves: UPDATE equals a rebuild, and the
// cache, invalidated before or after the update, drops exactly the moved road's curves.
TEST(CurveData, ProceduralCurvesOfRootCurveIdsAbove2To23AreUpdatedAndDropped) {
    constexpr ElementId kFirst = ElementId(1) << 23;
    Scene s;
    s.extent = {{0, 0}, {1000, 1000}};
    s.layers.resize(1);
    Layer& roads = s.layers[0];
    roads.kind = LayerKind::Roads;
    const ElementId a = roads.addNode({100, 100}), b = roads.addNode({500, 600}), c = roads.addNode({900, 150});
    Curve dead;
    dead.alive = false;
    roads.curves.reserve(kFirst + 2);
    roads.curves.assign(kFirst, dead);
    Curve road;
    road.w = 6;
    road.wf = 14;
    road.vertices = {{{100, 100}}, {{300, 450}}, {{500, 600}}};
    road.start = a;
    road.end = b;
    ASSERT_EQ(roads.addCurve(road), kFirst);
    road.vertices = {{{500, 600}}, {{700, 300}}, {{900, 150}}};
    road.start = b;
    road.end = c;
    ASSERT_EQ(roads.addCurve(road), kFirst + 1);

    test::CutRoadsIntoSegments step(150);
    constexpr std::size_t kPerRoad = 300;
    const Hills hills;
    Quadtree qt(s, {}, &step);
    CurveDataCache cache(qt, hills);
    qt.refineForViewer({500.0, 500.0, 5.0}, ViewParams{.maxLevel = 6});
    std::set<AncestorId> ancestors;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;
        for (const auto& [id, pieces] : q.layers[0].curves) ancestors.insert(id);
    });
    std::set<AncestorId> expected;
    for (ElementId root : {kFirst, kFirst + 1})
        for (std::size_t k = 0; k < kPerRoad; ++k) expected.insert(proceduralId(root, k));
    ASSERT_EQ(ancestors, expected);
    for (AncestorId id : ancestors) cache.zProfile(0, id);

    // Every cached profile and length is what a cache made now computes.
    auto expectFresh = [&](const char* when) {
        CurveDataCache fresh(qt, hills);
        for (AncestorId id : ancestors) {
            EXPECT_EQ(cache.zProfile(0, id).z, fresh.zProfile(0, id).z) << when << ": curve " << id;
            EXPECT_EQ(cache.length(0, id), fresh.length(0, id)) << when << ": curve " << id;
        }
    };
    // Invalidated before the update (as the editor does)...
    std::size_t before = cache.counters().zProfiles;
    const Changeset first = moveVertex(s, 0, kFirst, 1, {350, 420});
    EXPECT_EQ(cache.invalidate(first), (std::vector<ElementRef>{{0, ElementKind::Curve, kFirst}}));
    qt.update(first);
    Quadtree rebuilt(s, {}, &step);
    rebuilt.copyStructureOf(qt);
    const auto diff = compareQuadtrees(qt, rebuilt);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details[0]);
    expectFresh("invalidated before the update");
    EXPECT_EQ(cache.counters().zProfiles - before, kPerRoad);
    // ...or after it.
    before = cache.counters().zProfiles;
    const Changeset second = moveVertex(s, 0, kFirst + 1, 1, {720, 330});
    qt.update(second);
    EXPECT_EQ(cache.invalidate(second), (std::vector<ElementRef>{{0, ElementKind::Curve, kFirst + 1}}));
    expectFresh("invalidated after the update");
    EXPECT_EQ(cache.counters().zProfiles - before, kPerRoad);
}

// A V-shaped valley: z = a |x| + b y, its floor along x = 0 descending to the south.
class VValley : public HeightField {
public:
    static constexpr double kSideSlope = 0.4;   // a, m/m across the valley
    static constexpr double kDownSlope = 0.03;  // b, m/m along its floor
    double height(Vec2 p) const override { return kSideSlope * std::abs(p.x) + kDownSlope * p.y; }
};

// A river never stands above the valley floor it runs in, and never rises (§5.2). A main river
// down the floor of a V valley, in two curves (the first a cubic with its controls on the axis),
// and a tributary coming down the valley's side to the confluence: every profile sample is at or
// below the terrain under it. (Node heights were the mean over a disc, which counts the valley's
// sides: 7 m above the floor here, carried down the river by the clamp between node heights.)
// Within kernelRadius of a curve's downstream end, the smoothing kernel, whose indices are clamped
// at the end, averages the descent with copies of the end sample: the profile stands above the
// floor there by up to 0.4 slope x spacing for this kernel (computeProfile), which endAllowance
// bounds; elsewhere only the arc-length tolerance and rounding separate them.
TEST(CurveData, RiversInAVValleyNeverStandAboveItsFloorNorRise) {
    Scene s;
    s.extent = {{-700.0, -100.0}, {700.0, 1300.0}};
    s.layers.push_back({"rivers", LayerKind::Rivers, {}, {}, {}, {}});
    Layer& rivers = s.layers[0];
    const ElementId source = rivers.addNode({0.0, 1000.0}), confluence = rivers.addNode({0.0, 500.0}), mouth = rivers.addNode({0.0, 0.0});
    const ElementId spring = rivers.addNode({300.0, 650.0});
    auto addRiver = [&](ElementId a, ElementId b, std::vector<Vertex> inner, float w) {
        Curve c;
        c.vertices.push_back({rivers.nodes[a].p, true});
        for (const Vertex& v : inner) c.vertices.push_back(v);
        c.vertices.push_back({rivers.nodes[b].p, true});
        c.start = a;
        c.end = b;
        c.w = w;
        c.wf = 2.0f * w;
        return rivers.addCurve(std::move(c));
    };
    addRiver(source, confluence, {{{0.0, 800.0}, false}, {{0.0, 650.0}, false}}, 10.0f);
    addRiver(confluence, mouth, {}, 12.0f);
    addRiver(spring, confluence, {}, 4.0f);
    const VValley valley;
    Quadtree qt(s);
    CurveDataCache cache(qt, valley);
    const ZProfileParams& params = cache.params();
    constexpr double kRounding = 1e-4;        // metres: u within the arc-length tolerance, times the slope, and rounding
    constexpr double kEndBiasPerSlope = 0.4;  // of the slope x the sample spacing: this kernel's bias at a clamped end
    double worstInside = -1e300, worstEnd = -1e300;
    std::size_t samples = 0;
    for (ElementId c = 0; c < rivers.curves.size(); ++c) {
        const Curve& curve = rivers.curves[c];
        const ZProfile& z = cache.zProfile(0, c);
        const Vec2 a = curve.vertices.front().p, b = curve.vertices.back().p;  // straight curves
        const double slope = (valley.height(a) - valley.height(b)) / z.length;
        const double endAllowance = kEndBiasPerSlope * slope * z.spacing + kRounding;  // metres
        for (std::size_t i = 0; i < z.z.size(); ++i) {
            const double u = z.spacing * double(i);
            const double above = z.z[i] - valley.height(a + (b - a) * (u / z.length));
            if (z.length - u > params.kernelRadius) {
                worstInside = std::max(worstInside, above);
                EXPECT_LE(above, kRounding) << "river " << c << " above the floor at u " << u;
            } else {
                worstEnd = std::max(worstEnd, above);
                EXPECT_LE(above, endAllowance) << "river " << c << " above the floor at u " << u;
            }
            if (i > 0) {
                EXPECT_LE(z.z[i], z.z[i - 1]) << "river " << c << " rises at u " << u;
            }
            ++samples;
        }
        EXPECT_EQ(z.z.front(), cache.nodeHeight(0, curve.start));
        EXPECT_EQ(z.z.back(), cache.nodeHeight(0, curve.end));
    }
    // The nodes are on the floor: where it is lowest at them and along the curves flowing into them.
    EXPECT_NEAR(cache.nodeHeight(0, source), valley.height({0.0, 1000.0}), kRounding);
    EXPECT_NEAR(cache.nodeHeight(0, confluence), valley.height({0.0, 500.0}), kRounding);
    EXPECT_NEAR(cache.nodeHeight(0, mouth), valley.height({0.0, 0.0}), kRounding);
    std::cout << "[ figures  ] V valley: " << samples << " profile samples, at most " << worstInside
              << " m above the floor (more than kernelRadius from a curve's end), " << worstEnd << " m within it\n";
}

}  // namespace
}  // namespace lacet
