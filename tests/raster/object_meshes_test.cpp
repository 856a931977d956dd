// The object meshes (§5.3): one mesh per bridge, built from its ancestor curve and owned by one
// quad per level however deep the tree is clipped; trees at regular u along their curves, the same
// set over many quads as over few, each once; nothing built where nothing asks for it; pillars in
// the river bed under the deck; the deck clear of the water.
#include "raster/object_meshes.h"

#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "model/curve_data.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "raster/dem.h"
#include "raster/dem_height_field.h"

namespace lacet {
namespace {

constexpr LayerId kRoads = 0, kRivers = 1, kFields = 2, kForests = 3;
constexpr double kSide = 2048.0;
constexpr double kRiverY = 1024.0;

Scene emptyScene() {
    Scene s;
    s.extent = {Vec2(0.0), Vec2(kSide)};
    const std::pair<const char*, LayerKind> layers[] = {
        {"roads", LayerKind::Roads}, {"rivers", LayerKind::Rivers}, {"fields", LayerKind::Fields}, {"forests", LayerKind::Forests}};
    for (const auto& [name, kind] : layers) {
        s.layers.emplace_back();
        s.layers.back().name = name;
        s.layers.back().kind = kind;
    }
    return s;
}

// A curve through `pts` (on-curve unless `controls` says which are control points).
ElementId curve(Scene& s, LayerId l, std::vector<Vec2> pts, float w, float wf, std::uint16_t cls = 0, std::uint16_t flags = 0,
                std::vector<bool> controls = {}) {
    Layer& L = s.layers[l];
    Curve c;
    for (std::size_t i = 0; i < pts.size(); ++i) c.vertices.push_back({pts[i], controls.empty() || !controls[i]});
    c.start = L.addNode(pts.front());
    c.end = L.addNode(pts.back());
    c.w = w, c.wf = wf, c.cls = cls, c.flags = flags;
    return L.addCurve(c);
}

// A river flowing east along y = kRiverY, `w` wide.
ElementId river(Scene& s, float w, float wf) { return curve(s, kRivers, {{8.0, kRiverY}, {kSide - 8.0, kRiverY}}, w, wf); }

// A V-shaped valley along the river, sloping down to the east: 8 m cells.
Dem valley() {
    const int n = 257;
    std::vector<float> z(std::size_t(n) * std::size_t(n));
    const double cell = kSide / n;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = (i + 0.5) * cell, y = (j + 0.5) * cell;
            z[std::size_t(j) * std::size_t(n) + std::size_t(i)] = float(200.0 + 0.08 * std::abs(y - kRiverY) - 0.01 * x);
        }
    return Dem({Vec2(0.0), Vec2(kSide)}, n, n, std::move(z));
}

// A scene's quadtree with the graph step and its curve data.
struct World {
    Scene scene;
    Dem dem = valley();
    DemHeightField heights{dem};
    std::unique_ptr<GraphStep> step;
    std::unique_ptr<Quadtree> tree;
    std::unique_ptr<CurveDataCache> data;
    explicit World(Scene s) : scene(std::move(s)) {
        step = std::make_unique<GraphStep>(scene);
        tree = std::make_unique<Quadtree>(scene, RefineParams{}, step.get());
        data = std::make_unique<CurveDataCache>(*tree, heights);
    }
    // Subdivides the root, then every quad holding a curve of `layer`, down to `level`.
    void subdivideAlong(LayerId layer, int level) {
        std::function<void(Quad&)> go = [&](Quad& q) {
            if (q.level >= level) return;
            if (q.parent && (q.layers.size() <= layer || q.layers[layer].curves.empty())) return;
            tree->subdivide(q);
            for (auto& c : q.children) go(*c);
        };
        go(tree->root());
    }
    std::vector<const Quad*> quads(const std::function<bool(const Quad&)>& f) const {
        std::vector<const Quad*> out;
        tree->forEachQuad([&](const Quad& q) {
            if (f(q)) out.push_back(&q);
        });
        return out;
    }
};

// The parts of `mesh` of an ancestor's bridge, with their world vertices.
struct BridgeParts {
    std::vector<ObjectPart> parts;
    const ObjectMesh* mesh = nullptr;
};
BridgeParts bridgeOf(const ObjectMesh& mesh, AncestorId a) {
    BridgeParts b;
    b.mesh = &mesh;
    for (const ObjectPart& p : mesh.parts)
        if (p.ancestor == a && p.kind != ObjectKind::Tree) b.parts.push_back(p);
    return b;
}

::testing::AssertionResult sameBridge(const BridgeParts& x, const BridgeParts& y, double tolerance) {
    if (x.parts.size() != y.parts.size()) return ::testing::AssertionFailure() << x.parts.size() << " parts vs " << y.parts.size();
    for (std::size_t i = 0; i < x.parts.size(); ++i) {
        const ObjectPart& p = x.parts[i];
        const ObjectPart& q = y.parts[i];
        if (p.kind != q.kind || p.index != q.index || p.vertexCount != q.vertexCount || p.indexCount != q.indexCount)
            return ::testing::AssertionFailure() << "part " << i << " differs in kind, index or size";
        if (glm::length(p.anchor - q.anchor) > tolerance) return ::testing::AssertionFailure() << "part " << i << " anchor";
        for (std::uint32_t v = 0; v < p.vertexCount; ++v) {
            const double d = glm::length(x.mesh->world(p.firstVertex + v) - y.mesh->world(q.firstVertex + v));
            if (d > tolerance) return ::testing::AssertionFailure() << "part " << i << " vertex " << v << " is " << d << " m away";
            const ObjectVertex& a = x.mesh->vertices[p.firstVertex + v];
            const ObjectVertex& b = y.mesh->vertices[q.firstVertex + v];
            if (glm::length(a.normal - b.normal) > 1e-5f || a.colour != b.colour)
                return ::testing::AssertionFailure() << "part " << i << " vertex " << v << " normal or colour";
        }
        for (std::uint32_t k = 0; k < p.indexCount; ++k)
            if (x.mesh->indices[p.firstIndex + k] - p.firstVertex != y.mesh->indices[q.firstIndex + k] - q.firstVertex)
                return ::testing::AssertionFailure() << "part " << i << " index " << k;
    }
    return ::testing::AssertionSuccess();
}

ObjectParams bridgesOnly() {
    ObjectParams p;
    p.trees.clear();
    return p;
}

TEST(ObjectMeshes, OneMeshPerBridgeWhateverTheQuads) {
    // A long curved bridge (imported: kBridge) across the valley and its river.
    Scene s = emptyScene();
    river(s, 12.0f, 24.0f);
    curve(s, kRoads, {{1000.0, 700.0}, {1160.0, 900.0}, {880.0, 1150.0}, {1040.0, 1350.0}}, 6.0f, 12.0f, 0, kBridge,
          {false, true, true, false});
    World w(std::move(s));
    const ObjectParams params = bridgesOnly();
    w.subdivideAlong(kRoads, 6);  // 32 m quads along a 700 m bridge

    // Which ancestor the bridge is (the graph step keeps an imported bridge as one curve).
    std::set<AncestorId> bridges;
    w.tree->forEachQuad([&](const Quad& q) {
        if (q.layers.size() > kRoads)
            for (const auto& [a, pieces] : q.layers[kRoads].curves)
                if (w.tree->ancestorCurve(kRoads, a).flags & kBridge) bridges.insert(a);
    });
    ASSERT_EQ(bridges.size(), 1u);
    const AncestorId bridge = *bridges.begin();

    std::map<int, std::vector<std::pair<const Quad*, ObjectMesh>>> owners;  // level -> quads owning it
    std::size_t holders = 0;
    ObjectCounters counters;
    w.tree->forEachQuad([&](const Quad& q) {
        if (!q.parent) return;
        const bool holds = q.layers[kRoads].curves.count(bridge) > 0;
        holders += holds && q.level == 6;
        ObjectMesh m = produceObjects(q, *w.tree, *w.data, w.dem, nullptr, params, &counters);
        if (!holds) {
            EXPECT_TRUE(m.empty());
            return;
        }
        if (!bridgeOf(m, bridge).parts.empty()) owners[q.level].push_back({&q, std::move(m)});
    });
    EXPECT_GT(holders, 15u) << "the bridge should be clipped into many leaves";
    for (int level = 1; level <= 6; ++level) ASSERT_EQ(owners[level].size(), 1u) << "level " << level;
    EXPECT_EQ(counters.bridges, 6u);
    // The leaf's bridge is the root's children's, vertex for vertex (in scene coordinates; each
    // mesh is stored relative to its own quad).
    const BridgeParts top = bridgeOf(owners[1][0].second, bridge);
    ASSERT_GE(top.parts.size(), 3u);  // a deck and two abutments at least
    EXPECT_EQ(top.parts.front().kind, ObjectKind::Deck);
    for (int level = 2; level <= 6; ++level)
        EXPECT_TRUE(sameBridge(top, bridgeOf(owners[level][0].second, bridge), 2e-3)) << "level " << level;
    // The owner contains the bridge's middle, and the leaf owner is a leaf.
    const Quad* leaf = owners[6][0].first;
    EXPECT_TRUE(leaf->isLeaf());
    EXPECT_TRUE(leaf->bounds.contains(Vec2(top.parts.front().anchor)));
}

TEST(ObjectMeshes, OwnershipIsHalfOpen) {
    const Box root{Vec2(0.0), Vec2(kSide)};
    const Box left{Vec2(0.0), Vec2(1024.0, kSide)}, right{Vec2(1024.0, 0.0), Vec2(kSide)};
    EXPECT_FALSE(ownsPoint(left, root, {1024.0, 5.0}));
    EXPECT_TRUE(ownsPoint(right, root, {1024.0, 5.0}));
    EXPECT_TRUE(ownsPoint(right, root, {kSide, kSide}));  // the root's max sides are closed
    EXPECT_FALSE(ownsPoint(right, root, {kSide + 1e-9, 5.0}));
}

TEST(ObjectMeshes, TreesAcrossQuadBordersAreThoseOfTheWholeCurve) {
    Scene s = emptyScene();
    // An alley (class 1) winding across the quads of levels 1 to 6, and a square field whose
    // borders get hedges, across the root's centre lines.
    const ElementId alley = curve(s, kRoads, {{100.0, 300.0}, {600.0, 700.0}, {1400.0, 0.0}, {1900.0, 420.0}}, 5.0f, 10.0f, 1, 0,
                                  {false, true, true, false});
    curve(s, kRoads, {{100.0, 1800.0}, {1900.0, 1700.0}}, 8.0f, 16.0f, 0);  // class 0: no trees
    {
        Layer& f = s.layers[kFields];
        const Vec2 c[4] = {{800.0, 1200.0}, {1300.0, 1200.0}, {1300.0, 1600.0}, {800.0, 1600.0}};
        ElementId n[4];
        for (int i = 0; i < 4; ++i) n[i] = f.addNode(c[i]);
        Area a;
        a.loops.emplace_back();
        for (int i = 0; i < 4; ++i) {
            Curve e;
            e.vertices = {{c[i]}, {c[(i + 1) % 4]}};
            e.start = n[i], e.end = n[(i + 1) % 4];
            e.wf = 2.0f;
            a.loops[0].push_back({f.addCurve(e), false});
        }
        a.wf = 2.0f;
        f.addArea(a);
    }
    World w(std::move(s));
    ObjectParams params;
    for (TreeRule& r : params.trees) r.maxQuadSize = 1e9;  // trees at every level, so the root's children hold them all
    const TreeRule& alleyRule = params.trees[0];
    ASSERT_EQ(alleyRule.kind, LayerKind::Roads);
    ASSERT_EQ(alleyRule.cls, 1);

    using Key = std::tuple<LayerId, AncestorId, std::int64_t, int>;
    auto treesOf = [&](const std::vector<const Quad*>& quads, ObjectCounters* counters) {
        std::map<Key, glm::dvec3> trees;
        for (const Quad* q : quads) {
            const ObjectMesh m = produceObjects(*q, *w.tree, *w.data, w.dem, nullptr, params, counters);
            for (const ObjectPart& p : m.parts) {
                EXPECT_EQ(p.kind, ObjectKind::Tree);
                EXPECT_TRUE(ownsPoint(q->bounds, w.tree->root().bounds, Vec2(p.anchor)));
                const bool fresh = trees.emplace(Key{p.layer, p.ancestor, p.index, p.side}, p.anchor).second;
                EXPECT_TRUE(fresh) << "tree " << p.index << " side " << p.side << " built twice";
            }
        }
        return trees;
    };
    w.tree->subdivide(w.tree->root());
    const auto coarse = treesOf(w.quads([](const Quad& q) { return q.level == 1; }), nullptr);
    w.subdivideAlong(kRoads, 6);
    w.subdivideAlong(kFields, 6);
    ObjectCounters counters;
    const std::vector<const Quad*> leaves = w.quads([](const Quad& q) { return q.isLeaf(); });
    EXPECT_GT(leaves.size(), 200u);
    const auto fine = treesOf(leaves, &counters);
    EXPECT_EQ(counters.trees, fine.size());

    // The same trees, at the same places, bit for bit.
    ASSERT_EQ(coarse.size(), fine.size());
    for (const auto& [key, anchor] : coarse) {
        const auto it = fine.find(key);
        ASSERT_NE(it, fine.end());
        EXPECT_EQ(Vec2(it->second), Vec2(anchor));
    }
    // None lost: every k of the curve's length, on both sides of the alley, on the field borders.
    std::size_t expected = 0;
    for (const auto& [layer, a] : std::vector<std::pair<LayerId, AncestorId>>{
             {kRoads, alley}, {kFields, 0}, {kFields, 1}, {kFields, 2}, {kFields, 3}}) {
        const TreeRule& r = params.trees[layer == kRoads ? 0 : 1];
        const double L = w.data->length(layer, a);
        std::size_t n = 0;
        for (std::int64_t k = 0; double(k) * r.spacing <= L; ++k) {
            const double u = double(k) * r.spacing;
            if (u >= r.endClearance && u <= L - r.endClearance) ++n;
        }
        expected += n * (r.offsetFraction > 0.0 ? 2 : 1);
    }
    EXPECT_EQ(fine.size(), expected);
    // Trees of the alley at its wf / 2 on either side, spacing apart along it.
    for (const auto& [key, anchor] : fine) {
        const auto& [layer, a, k, side] = key;
        if (layer != kRoads) continue;
        EXPECT_NE(side, 0);
        const auto next = fine.find(Key{layer, a, k + 1, side});
        if (next == fine.end()) continue;
        const double d = glm::length(Vec2(next->second) - Vec2(anchor));
        EXPECT_GT(d, 0.5 * alleyRule.spacing);
        EXPECT_LT(d, 2.0 * alleyRule.spacing);
    }
}

TEST(ObjectMeshes, NothingToBuildCostsNothing) {
    // Rivers, a class-0 road and a forest: no bridge (the road ends before the river), no tree rule.
    Scene s = emptyScene();
    river(s, 10.0f, 20.0f);
    curve(s, kRoads, {{200.0, 100.0}, {1800.0, 600.0}}, 8.0f, 16.0f, 0);
    {
        Layer& f = s.layers[kForests];
        const Vec2 c[3] = {{300.0, 1300.0}, {900.0, 1300.0}, {600.0, 1800.0}};
        ElementId n[3];
        for (int i = 0; i < 3; ++i) n[i] = f.addNode(c[i]);
        Area a;
        a.loops.emplace_back();
        for (int i = 0; i < 3; ++i) {
            Curve e;
            e.vertices = {{c[i]}, {c[(i + 1) % 3]}};
            e.start = n[i], e.end = n[(i + 1) % 3];
            e.wf = 5.0f;
            a.loops[0].push_back({f.addCurve(e), false});
        }
        a.wf = 5.0f;
        f.addArea(a);
    }
    World w(std::move(s));
    w.subdivideAlong(kRivers, 4);
    w.subdivideAlong(kRoads, 4);
    ObjectCounters counters;
    std::size_t withCurves = 0;
    w.tree->forEachQuad([&](const Quad& q) {
        for (const QuadLayer& l : q.layers) withCurves += !l.curves.empty();
        const ObjectMesh m = produceObjects(q, *w.tree, *w.data, w.dem, nullptr, ObjectParams{}, &counters);
        EXPECT_TRUE(m.empty());
        EXPECT_TRUE(m.parts.empty());
    });
    EXPECT_GT(withCurves, 20u);
    EXPECT_EQ(counters.meshesBuilt, 0u);
    EXPECT_EQ(counters.bridges, 0u);
    EXPECT_EQ(counters.pillars, 0u);
    EXPECT_EQ(counters.trees, 0u);
    EXPECT_EQ(w.data->counters().zProfiles, 0u);  // no curve data asked either
}

// A straight road (x = 1024, north) over a wide river: the graph step makes it a bridge.
struct WideRiver {
    World w;
    ElementId riverId = 0, road = 0;
    AncestorId bridge = 0;
    const ProceduralCurve* pc = nullptr;
    ObjectMesh mesh;
    ObjectParams params = bridgesOnly();
    WideRiver() : w(makeScene()) {
        params.pillarSpacing = 12.0;
        w.tree->subdivide(w.tree->root());
        for (AncestorId a : w.tree->expansionOf(kRoads, 0))
            if (w.tree->ancestorCurve(kRoads, a).flags & kBridge) bridge = a, pc = w.tree->proceduralCurve(kRoads, a);
        if (!pc) return;
        w.tree->forEachQuad([&](const Quad& q) {
            if (q.level != 1) return;
            ObjectMesh m = produceObjects(q, *w.tree, *w.data, w.dem, nullptr, params);
            if (!m.empty()) mesh = std::move(m);
        });
    }
    static Scene makeScene() {
        Scene s = emptyScene();
        curve(s, kRoads, {{1024.0 + 3.0, 600.0}, {1024.0 - 3.0, 1450.0}}, 6.0f, 12.0f, 0);
        river(s, 40.0f, 60.0f);
        return s;
    }
    double water() const { return w.data->zProfile(kRivers, 0).at(w.data->u(kRivers, 0, pc->spans.at(0).overS)); }
};

TEST(ObjectMeshes, PillarsStandInTheRiverBedUnderTheDeck) {
    WideRiver r;
    ASSERT_NE(r.pc, nullptr) << "the graph step made no bridge";
    ASSERT_FALSE(r.mesh.empty());
    const ZProfile& deck = r.w.data->zProfile(kRoads, r.bridge);
    const Curve& bc = r.w.tree->ancestorCurve(kRoads, r.bridge);
    const Vec2 start = bc.vertices.front().p, dir = glm::normalize(bc.vertices.back().p - start);
    const double dt = r.params.deckThickness, water = r.water();
    std::size_t pillars = 0, inWater = 0;
    for (const ObjectPart& p : r.mesh.parts) {
        if (p.kind != ObjectKind::Pillar) continue;
        ++pillars;
        double lo = 1e30, hi = -1e30;
        for (std::uint32_t v = 0; v < p.vertexCount; ++v) {
            lo = std::min(lo, r.mesh.world(p.firstVertex + v).z);
            hi = std::max(hi, r.mesh.world(p.firstVertex + v).z);
        }
        const Vec2 at(p.anchor);
        EXPECT_NEAR(lo, p.anchor.z, 2e-3);
        // Its foot: footDepth below the ground under it (and below the water in the river).
        const double ground = r.w.dem.sample(at);
        EXPECT_LE(lo, ground - r.params.footDepth + 2e-3);
        EXPECT_GE(lo, std::min(ground, water) - r.params.footDepth - 0.5);
        const bool wet = std::abs(at.y - kRiverY) < 20.0;
        inWater += wet;
        if (wet) { EXPECT_LE(lo, water - r.params.footDepth + 2e-3); }
        // Its top: the deck's underside there (the highest over the pillar's thickness).
        const double u = glm::dot(at - start, dir);
        const double underside = deck.at(u) - dt;
        EXPECT_GE(hi, underside - 2e-3);
        EXPECT_LE(hi, underside + 0.2);
        EXPECT_GT(hi - lo, r.params.minPillarHeight);
    }
    EXPECT_GE(pillars, 2u);
    EXPECT_GE(inWater, 1u) << "a pillar in the 40 m river";
}

TEST(ObjectMeshes, DeckClearsTheWater) {
    WideRiver r;
    ASSERT_NE(r.pc, nullptr) << "the graph step made no bridge";
    ASSERT_FALSE(r.pc->spans.empty());
    const GraphStepParams g;
    const double water = r.water();
    const ZProfile& deck = r.w.data->zProfile(kRoads, r.bridge);
    for (const BridgeSpan& span : r.pc->spans) {
        EXPECT_EQ(span.over, AncestorId(0));
        EXPECT_GE(deck.at(span.u) - r.params.deckThickness, water + g.clearance - 1e-6);
    }
    // The mesh: every deck vertex over the water stands clearance above it.
    std::size_t over = 0;
    for (const ObjectPart& p : r.mesh.parts) {
        if (p.kind != ObjectKind::Deck) continue;
        for (std::uint32_t v = 0; v < p.vertexCount; ++v) {
            const glm::dvec3 q = r.mesh.world(p.firstVertex + v);
            if (std::abs(q.y - kRiverY) > 20.0) continue;
            ++over;
            EXPECT_GE(q.z, water + g.clearance - 1e-2);
        }
    }
    EXPECT_GT(over, 20u);
}

TEST(ObjectMeshes, TreesStandOnTheElevationTile) {
    // Without a tile the DEM; with one, z_m bilinear (what the terrain shows).
    Scene s = emptyScene();
    curve(s, kRoads, {{100.0, 300.0}, {1900.0, 420.0}}, 5.0f, 10.0f, 1);
    World w(std::move(s));
    w.subdivideAlong(kRoads, 2);
    const Quad* q = nullptr;
    w.tree->forEachQuad([&](const Quad& x) {
        if (x.level == 2 && !x.layers[kRoads].curves.empty() && !q) q = &x;
    });
    ASSERT_NE(q, nullptr);
    ElevationTile t;
    t.bounds = q->bounds, t.resolution = 4, t.border = 0, t.delta = q->bounds.size().x / 4, t.stride = 5;
    t.zm.assign(25, 42.0f);
    const ObjectMesh m = produceObjects(*q, *w.tree, *w.data, w.dem, &t, ObjectParams{});
    ASSERT_FALSE(m.parts.empty());
    for (const ObjectPart& p : m.parts) EXPECT_DOUBLE_EQ(p.anchor.z, 42.0);
    const ObjectMesh d = produceObjects(*q, *w.tree, *w.data, w.dem, nullptr, ObjectParams{});
    ASSERT_EQ(d.parts.size(), m.parts.size());
    for (const ObjectPart& p : d.parts) EXPECT_NEAR(p.anchor.z, w.dem.sample(Vec2(p.anchor)), 1e-9);
}

TEST(ObjectMeshes, ParamsAreChecked) {
    ObjectParams p;
    EXPECT_NO_THROW(p.validate());
    p.pillarSpacing = 0.0;
    EXPECT_THROW(p.validate(), std::invalid_argument);
    p = ObjectParams{};
    p.trees[1].offsetFraction = 1.5;
    EXPECT_THROW(p.validate(), std::invalid_argument);
    EXPECT_EQ(ObjectParams{}.deckThickness, GraphStepParams{}.deckThickness);
}

}  // namespace
}  // namespace lacet
