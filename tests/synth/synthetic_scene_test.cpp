#include "synth/synthetic_scene.h"

#include <bit>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/graph.h"
#include "model/validate.h"
#include "tests/same_bits.h"

namespace lacet {
namespace {

// The 10k-curve scene of seed 1, generated once for the tests that only read it.
const Scene& scene10k() {
    static const Scene scene = makeSyntheticScene({1, 10000});
    return scene;
}


// Element by element, positions compared bitwise; reports the first difference.
::testing::AssertionResult identical(const Scene& a, const Scene& b) {
    auto differ = [](const std::string& what) { return ::testing::AssertionFailure() << what << " differs"; };
    if (!sameBits(a.extent.min, b.extent.min) || !sameBits(a.extent.max, b.extent.max)) return differ("extent");
    if (a.layers.size() != b.layers.size()) return differ("layer count");
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer& x = a.layers[l];
        const Layer& y = b.layers[l];
        const std::string at = "layer " + std::to_string(l) + " ";
        if (x.name != y.name || x.kind != y.kind) return differ(at + "name or kind");
        if (x.nodes.size() != y.nodes.size() || x.curves.size() != y.curves.size() || x.areas.size() != y.areas.size())
            return differ(at + "element count");
        for (std::size_t i = 0; i < x.nodes.size(); ++i)
            if (!sameBits(x.nodes[i].p, y.nodes[i].p) || x.nodes[i].curves != y.nodes[i].curves ||
                x.nodes[i].alive != y.nodes[i].alive)
                return differ(at + "node " + std::to_string(i));
        for (std::size_t i = 0; i < x.curves.size(); ++i) {
            const Curve& c = x.curves[i];
            const Curve& d = y.curves[i];
            bool same = c.vertices.size() == d.vertices.size() && c.start == d.start && c.end == d.end &&
                        std::bit_cast<std::uint32_t>(c.w) == std::bit_cast<std::uint32_t>(d.w) &&
                        std::bit_cast<std::uint32_t>(c.wf) == std::bit_cast<std::uint32_t>(d.wf) && c.cls == d.cls &&
                        c.flags == d.flags && c.areas == d.areas && c.alive == d.alive;
            for (std::size_t k = 0; same && k < c.vertices.size(); ++k)
                same = sameBits(c.vertices[k].p, d.vertices[k].p) && c.vertices[k].onCurve == d.vertices[k].onCurve &&
                       c.vertices[k].closing == d.vertices[k].closing;
            if (!same) return differ(at + "curve " + std::to_string(i));
        }
        for (std::size_t i = 0; i < x.areas.size(); ++i) {
            const Area& p = x.areas[i];
            const Area& q = y.areas[i];
            if (p.loops != q.loops || std::bit_cast<std::uint32_t>(p.wf) != std::bit_cast<std::uint32_t>(q.wf) ||
                p.cls != q.cls || p.axial != q.axial || p.alive != q.alive)
                return differ(at + "area " + std::to_string(i));
        }
    }
    return ::testing::AssertionSuccess();
}

std::size_t maxDegree(const Layer& layer) {
    std::size_t d = 0;
    for (const Node& n : layer.nodes) d = std::max(d, n.curves.size());
    return d;
}

TEST(SyntheticScene, ExtentSideFollowsThePapersDensity) {
    EXPECT_DOUBLE_EQ(syntheticExtentSide(600000), 100000.0);
    EXPECT_DOUBLE_EQ(syntheticExtentSide(150000), 50000.0);
    EXPECT_GT(syntheticExtentSide(0), 0.0);
    const Scene& s = scene10k();
    EXPECT_EQ(s.extent.min, Vec2(0.0));
    EXPECT_EQ(s.extent.max, Vec2(syntheticExtentSide(10000)));
}

TEST(SyntheticScene, IsValidForSeveralSeedsAndSizes) {
    for (std::size_t curves : {0u, 1u, 50u, 200u, 1000u, 3000u})
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            const Scene s = makeSyntheticScene({seed, curves});
            const auto problems = validate(s);
            EXPECT_TRUE(problems.empty()) << curves << " curves, seed " << seed << ": " << problems.size()
                                          << " problems, first: " << (problems.empty() ? "" : problems[0].where + ": " + problems[0].reason);
        }
    EXPECT_TRUE(validate(scene10k()).empty());
}

TEST(SyntheticScene, HasTheFixedLayerOrder) {
    const Scene& s = scene10k();
    ASSERT_EQ(s.layers.size(), 5u);
    EXPECT_EQ(s.layers[kRoadsLayer].kind, LayerKind::Roads);
    EXPECT_EQ(s.layers[kRiversLayer].kind, LayerKind::Rivers);
    EXPECT_EQ(s.layers[kLakesLayer].kind, LayerKind::Lakes);
    EXPECT_EQ(s.layers[kFieldsLayer].kind, LayerKind::Fields);
    EXPECT_EQ(s.layers[kForestsLayer].kind, LayerKind::Forests);
    for (std::size_t curves : {1000u, 10000u}) {
        const Scene small = curves == 10000u ? scene10k() : makeSyntheticScene({7, curves});
        for (const Layer& layer : small.layers) EXPECT_FALSE(layer.curves.empty()) << layer.name << " at " << curves;
        for (LayerId l : {kLakesLayer, kFieldsLayer, kForestsLayer})
            EXPECT_FALSE(small.layers[l].areas.empty()) << small.layers[l].name << " at " << curves;
    }
}

TEST(SyntheticScene, SameSeedGivesABitIdenticalScene) {
    const Scene a = makeSyntheticScene({42, 10000});
    const Scene b = makeSyntheticScene({42, 10000});
    EXPECT_TRUE(identical(a, b));
    EXPECT_TRUE(identical(makeSyntheticScene({1, 10000}), scene10k()));
}

TEST(SyntheticScene, FieldsMadeInPartsAndAppendedGiveTheWholeScene) {
    // lacet synth --out writes the fields a part at a time (SyntheticSceneParts): each part stands
    // alone (valid as a layer of its own), holds whole patches of about partCurves curves, and the
    // parts appended in order are the fields of makeSyntheticScene, bit for bit.
    for (const std::uint64_t seed : {1u, 7u})
        for (const std::size_t partCurves : {std::size_t(1), std::size_t(97), std::size_t(4000), std::size_t(1) << 40}) {
            SCOPED_TRACE("seed " + std::to_string(seed) + ", parts of " + std::to_string(partCurves));
            SyntheticSceneParts parts({seed, 10000});
            Scene scene = parts.takeScene();
            EXPECT_TRUE(scene.layers[kFieldsLayer].curves.empty());
            EXPECT_FALSE(scene.layers[kForestsLayer].curves.empty());
            std::vector<std::size_t> sizes;
            parts.fields([&](Layer&& part) {
                Scene alone;
                alone.extent = scene.extent;
                alone.layers.push_back(part);
                EXPECT_TRUE(validate(alone).empty()) << "part " << sizes.size();
                sizes.push_back(part.curves.size());
                appendLayerPart(scene.layers[kFieldsLayer], std::move(part));
            }, partCurves);
            ASSERT_FALSE(sizes.empty());
            for (std::size_t i = 0; i + 1 < sizes.size(); ++i) {
                EXPECT_GE(sizes[i], partCurves) << "part " << i;
                EXPECT_LT(sizes[i], partCurves + 41) << "part " << i;  // a patch has at most 40 curves
            }
            EXPECT_TRUE(identical(scene, seed == 1 ? scene10k() : makeSyntheticScene({seed, 10000})));
            EXPECT_THROW(parts.fields([](Layer&&) {}, 1), std::logic_error);
        }
}

TEST(SyntheticScene, DifferentSeedsGiveDifferentScenes) {
    const Scene a = makeSyntheticScene({1, 2000});
    const Scene b = makeSyntheticScene({2, 2000});
    EXPECT_FALSE(identical(a, b));
    for (LayerId l : {kRoadsLayer, kRiversLayer, kFieldsLayer})
        EXPECT_FALSE(sameBits(a.layers[l].nodes.at(0).p, b.layers[l].nodes.at(0).p)) << a.layers[l].name;
}

TEST(SyntheticScene, CountsAreNearTheTargetWithThePapersProportions) {
    const Scene& s = scene10k();
    const SceneCounts c = count(s);
    EXPECT_GE(c.curves, 9000u);
    EXPECT_LE(c.curves, 11000u);
    // Paper: 600k curves, 190k areas, 940k nodes and control points.
    const double areasPerCurve = double(c.areas) / double(c.curves);
    EXPECT_GT(areasPerCurve, 0.25);
    EXPECT_LT(areasPerCurve, 0.40);
    const double pointsPerCurve = double(c.nodes + c.controlPoints) / double(c.curves);
    EXPECT_GT(pointsPerCurve, 700.0 / 600.0);
    EXPECT_LT(pointsPerCurve, 1200.0 / 600.0);
    // Fields are most of the data (paper: 580k of the 600k curves, 185k of the 190k areas).
    EXPECT_GT(s.layers[kFieldsLayer].curves.size(), c.curves * 9 / 10);
    EXPECT_GT(s.layers[kFieldsLayer].areas.size(), c.areas * 9 / 10);
}

TEST(SyntheticScene, NeighbouringFieldsShareTheirBorderCurves) {
    const Layer& fields = scene10k().layers[kFieldsLayer];
    std::size_t shared = 0;
    for (std::size_t id = 0; id < fields.curves.size(); ++id) {
        const Curve& c = fields.curves[id];
        ASSERT_GE(c.areas.size(), 1u);
        ASSERT_LE(c.areas.size(), 2u);
        if (c.areas.size() != 2) continue;
        ++shared;
        // Walked forward by one parcel and backward by the other.
        int forward = 0, backward = 0;
        for (ElementId a : c.areas)
            for (const auto& loop : fields.areas[a].loops)
                for (const AreaEdge& e : loop)
                    if (e.curve == id) (e.reversed ? backward : forward)++;
        EXPECT_EQ(forward, 1);
        EXPECT_EQ(backward, 1);
    }
    EXPECT_GT(shared, fields.curves.size() / 4);
    for (const Area& a : fields.areas) {
        EXPECT_LE(a.cls, 5u);
        EXPECT_EQ(a.wf, 2.0f);
    }
}

TEST(SyntheticScene, RoadsHaveThreeAndFourWayJunctions) {
    for (std::size_t curves : {1000u, 10000u}) {
        const Scene s = curves == 10000u ? scene10k() : makeSyntheticScene({3, curves});
        const Layer& roads = s.layers[kRoadsLayer];
        std::size_t three = 0, four = 0;
        for (const Node& n : roads.nodes) {
            three += n.curves.size() == 3;
            four += n.curves.size() == 4;
        }
        EXPECT_GT(three, 0u) << curves;
        EXPECT_GT(four, 0u) << curves;
        EXPECT_LE(maxDegree(roads), 4u);
        for (const Curve& c : roads.curves) {
            ASSERT_LE(c.cls, 2u);
            const float w[3] = {7.0f, 5.0f, 3.0f}, wf[3] = {15.0f, 11.0f, 7.0f};
            EXPECT_EQ(c.w, w[c.cls]);
            EXPECT_EQ(c.wf, wf[c.cls]);
            EXPECT_GE(c.vertices.size(), 3u);  // curved
        }
    }
}

TEST(SyntheticScene, RiversAreTreesOrientedDownstream) {
    const Layer& rivers = scene10k().layers[kRiversLayer];
    EXPECT_GE(maxDegree(rivers), 3u);  // tributaries join at nodes
    for (std::size_t id = 0; id < rivers.nodes.size(); ++id) {
        // At most one curve leaves a node downstream; at a confluence it is wider than those
        // arriving.
        std::size_t out = 0;
        float outW = 0.0f, inW = 0.0f;
        for (ElementId c : rivers.nodes[id].curves) {
            const Curve& curve = rivers.curves[c];
            if (curve.start == id) ++out, outW = curve.w;
            else inW = std::max(inW, curve.w);
        }
        EXPECT_LE(out, 1u) << "node " << id;
        if (out == 1) {
            EXPECT_GE(outW, inW) << "node " << id;
        }
    }
    for (const Curve& c : rivers.curves) {
        EXPECT_GE(c.w, 2.0f);
        EXPECT_LE(c.w, 20.0f);
        EXPECT_EQ(c.wf, c.w + 10.0f);
    }
}

TEST(SyntheticScene, LakesAndForestsHaveHoles) {
    for (LayerId l : {kLakesLayer, kForestsLayer}) {
        const Layer& layer = scene10k().layers[l];
        std::size_t holes = 0;
        for (const Area& a : layer.areas) holes += a.loops.size() - 1;
        EXPECT_GT(holes, 0u) << layer.name;
    }
    for (const Area& a : scene10k().layers[kLakesLayer].areas) {
        EXPECT_GE(a.loops[0].size(), 3u);
        EXPECT_LE(a.loops[0].size(), 6u);
    }
}

TEST(SyntheticScene, EverythingLiesInsideTheExtent) {
    for (std::size_t curves : {200u, 10000u}) {
        const Scene s = curves == 10000u ? scene10k() : makeSyntheticScene({5, curves});
        for (const Layer& layer : s.layers) {
            for (const Node& n : layer.nodes) EXPECT_TRUE(s.extent.contains(n.p)) << layer.name;
            for (const Curve& c : layer.curves)
                for (const Vertex& v : c.vertices)  // controls too: a curve lies in their hull
                    ASSERT_TRUE(s.extent.contains(v.p)) << layer.name;
        }
    }
}

}  // namespace
}  // namespace lacet
