// The window-less editing session: random command sequences undone restore the scene and every
// tile exactly; redone, they give the edited scene again; tiles kept up to date by the live loop
// equal tiles made from scratch (incremental equals rebuild through the session).
#include "editor/edit_session.h"

#include <bit>
#include <random>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/random_edits.h"
#include "model/synthetic_scene.h"
#include "raster/synthetic_dem.h"

namespace lacet {
namespace {

bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool sameBits(Vec2 a, Vec2 b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y); }

::testing::AssertionResult sameScene(const Scene& a, const Scene& b) {
    if (a.layers.size() != b.layers.size()) return ::testing::AssertionFailure() << "layer count";
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer& p = a.layers[l];
        const Layer& q = b.layers[l];
        if (p.nodes.size() != q.nodes.size() || p.curves.size() != q.curves.size() || p.areas.size() != q.areas.size())
            return ::testing::AssertionFailure() << "layer " << l << " slot counts";
        for (std::size_t i = 0; i < p.nodes.size(); ++i)
            if (!sameBits(p.nodes[i].p, q.nodes[i].p) || p.nodes[i].curves != q.nodes[i].curves || p.nodes[i].alive != q.nodes[i].alive)
                return ::testing::AssertionFailure() << "layer " << l << " node " << i;
        for (std::size_t i = 0; i < p.curves.size(); ++i) {
            const Curve& c = p.curves[i];
            const Curve& d = q.curves[i];
            bool same = c.start == d.start && c.end == d.end && sameBits(c.w, d.w) && sameBits(c.wf, d.wf) && c.cls == d.cls &&
                        c.flags == d.flags && c.areas == d.areas && c.alive == d.alive && c.vertices.size() == d.vertices.size();
            for (std::size_t k = 0; same && k < c.vertices.size(); ++k)
                same = sameBits(c.vertices[k].p, d.vertices[k].p) && c.vertices[k].onCurve == d.vertices[k].onCurve &&
                       c.vertices[k].closing == d.vertices[k].closing;
            if (!same) return ::testing::AssertionFailure() << "layer " << l << " curve " << i;
        }
        for (std::size_t i = 0; i < p.areas.size(); ++i)
            if (p.areas[i].loops != q.areas[i].loops || !sameBits(p.areas[i].wf, q.areas[i].wf) || p.areas[i].cls != q.areas[i].cls ||
                p.areas[i].axial != q.areas[i].axial || p.areas[i].alive != q.areas[i].alive)
                return ::testing::AssertionFailure() << "layer " << l << " area " << i;
    }
    return ::testing::AssertionSuccess();
}

template <class T>
ElementId randomAlive(const std::vector<T>& v, std::mt19937_64& rng) {
    if (v.empty()) return kNoElement;
    for (int tries = 0; tries < 50; ++tries) {
        const ElementId id = ElementId(uniform01(rng) * double(v.size())) % ElementId(v.size());
        if (v[id].alive) return id;
    }
    return kNoElement;
}

// A random command of any kind on the roads or rivers layer (it may be refused: EditError).
std::optional<Command> randomCommand(const Scene& s, std::mt19937_64& rng) {
    const LayerId layer = uniform01(rng) < 0.7 ? kRoadsLayer : kRiversLayer;
    const Layer& l = s.layers[layer];
    const auto offset = [&] { return Vec2(uniform01(rng) * 40.0 - 20.0, uniform01(rng) * 40.0 - 20.0); };
    const int kind = int(uniform01(rng) * 9.0);
    const ElementId c = randomAlive(l.curves, rng);
    const ElementId n = randomAlive(l.nodes, rng);
    if (c == kNoElement || n == kNoElement) return std::nullopt;
    const auto& v = l.curves[c].vertices;
    const std::size_t inner = v.size() > 2 ? 1 + std::size_t(uniform01(rng) * double(v.size() - 2)) : 0;
    switch (kind) {
        case 0: if (inner) return MoveVertexCmd{layer, c, inner, v[inner].p + offset()}; break;
        case 1: {
            const std::size_t i = 1 + std::size_t(uniform01(rng) * double(v.size() - 1));
            return InsertVertexCmd{layer, c, i, {(v[i - 1].p + v[i].p) * 0.5 + offset() * 0.1, true}};
        }
        case 2: if (inner) return DeleteVertexCmd{layer, c, inner}; break;
        case 3: return MoveNodeCmd{layer, n, l.nodes[n].p + offset()};
        case 4: return AddNodeCmd{layer, l.nodes[n].p + offset()};
        case 5: {
            const ElementId m = randomAlive(l.nodes, rng);
            if (m == kNoElement || m == n || l.nodes[m].p == l.nodes[n].p) break;
            Curve curve;
            curve.vertices = {{l.nodes[n].p}, {l.nodes[m].p}};
            curve.start = n;
            curve.end = m;
            curve.w = 4.0f;
            curve.wf = 9.0f;
            return AddCurveCmd{layer, curve};
        }
        case 6: return DeleteCurveCmd{layer, c};
        case 7: {
            const float w = float(2.0 + uniform01(rng) * 8.0);
            return SetCurveWidthCmd{layer, c, w, w + 5.0f};
        }
        default: return SetCurveClassCmd{layer, c, std::uint16_t(uniform01(rng) * 3.0)};
    }
    return std::nullopt;
}

SceneDocument syntheticDocument(std::uint64_t seed, std::size_t curves) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({seed, curves});
    doc.dem = makeSyntheticDem(doc.scene, {seed, 1000});
    return doc;
}

// Every leaf of the session's view has a clean tile equal to one made from scratch.
void expectTilesEqualFromScratch(const EditSession& session, const SessionParams& params, const char* when) {
    Quadtree fresh(session.document().scene, params.refine);
    fresh.copyStructureOf(session.quadtree());
    DemHeightField heights(*session.document().dem);
    CurveDataCache data(fresh, heights);
    std::size_t compared = 0;
    fresh.forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        const CachedTile* t = session.tile(keyOf(q));
        ASSERT_NE(t, nullptr) << when;
        EXPECT_FALSE(t->dirty) << when;
        EXPECT_TRUE(t->appearance == produceAppearance(q, fresh, data, *session.document().dem, params.appearance)) << when;
        EXPECT_TRUE(t->elevation == produceElevation(q, fresh, data, *session.document().dem, params.elevation)) << when;
        ++compared;
    });
    EXPECT_GT(compared, 50u);
}

TEST(EditSession, RandomCommandsUndoneRestoreTheSceneAndEveryTileExactly) {
    SessionParams params;
    params.refine.resolution = 32;
    params.maxLevel = 9;
    params.cacheTiles = 1u << 20;
    EditSession session(syntheticDocument(11, 1500), params);
    const Vec2 c = session.document().scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 40.0);
    session.frame(viewer, 0.0);
    const Scene original = session.document().scene;
    const std::map<QuadKey, CachedTile> originalTiles = session.tiles();
    std::mt19937_64 rng(21);
    std::size_t applied = 0, refused = 0, dirtied = 0;
    for (int i = 0; i < 120 && applied < 50; ++i) {
        const auto cmd = randomCommand(session.document().scene, rng);
        if (!cmd) continue;
        try {
            dirtied += session.execute(*cmd).dirtyTiles;
            ++applied;
        } catch (const EditError&) {
            ++refused;
            continue;
        }
        session.frame(viewer, 0.0);
    }
    EXPECT_GE(applied, 40u);
    EXPECT_GT(dirtied, 0u);
    expectTilesEqualFromScratch(session, params, "after the commands");
    const Scene edited = session.document().scene;
    std::size_t undone = 0;
    while (session.undo()) {
        ++undone;
        session.frame(viewer, 0.0);
    }
    EXPECT_EQ(undone, applied);
    EXPECT_TRUE(sameScene(session.document().scene, original));
    for (const auto& [key, tile] : originalTiles) {
        const CachedTile* now = session.tile(key);
        ASSERT_NE(now, nullptr);
        EXPECT_TRUE(now->appearance == tile.appearance && now->elevation == tile.elevation) << "tile " << std::get<0>(key);
    }
    while (session.redo()) session.frame(viewer, 0.0);
    EXPECT_TRUE(sameScene(session.document().scene, edited));
    expectTilesEqualFromScratch(session, params, "after redo");
    std::cout << "[ figures  ] " << applied << " commands applied (" << refused << " refused), " << dirtied
              << " tiles made dirty, all undone and redone exactly\n";
}

TEST(EditSession, AFrameBudgetLeavesTheRestPendingNearestFirst) {
    SessionParams params;
    params.refine.resolution = 64;
    params.maxLevel = 10;
    EditSession session(syntheticDocument(12, 1500), params);
    const Vec2 c = session.document().scene.extent.center();
    const FrameReport first = session.frame({c.x, c.y, 20.0}, 1e-6);  // one batch only
    EXPECT_GT(first.pending, 0u);
    EXPECT_EQ(first.produced + first.pending, first.viewQuads);
    // The quad under the viewer is among the first made.
    const Quad* q = &session.quadtree().root();
    while (!q->isLeaf())
        for (const auto& child : q->children)
            if (child->bounds.contains(c)) {
                q = child.get();
                break;
            }
    EXPECT_NE(session.tile(keyOf(*q)), nullptr);
    const FrameReport rest = session.frame({c.x, c.y, 20.0}, 0.0);
    EXPECT_EQ(rest.pending, 0u);
    EXPECT_EQ(first.produced + rest.produced, first.viewQuads);
}

}  // namespace
}  // namespace lacet
