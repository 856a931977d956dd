// The window-less editing session: random command sequences undone restore the scene and every
// tile exactly; redone, they give the edited scene again; tiles kept up to date by the live loop
// equal tiles made from scratch (incremental equals rebuild through the session).
#include "editor/edit_session.h"

#include <bit>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "io/scene_file.h"
#include "model/edits.h"
#include "model/quadtree_compare.h"
#include "model/work_clock.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/editor/session_checks.h"
#include "tests/same_bits.h"

namespace lacet {
namespace {

using test::expectTilesEqualFromScratch;
using test::syntheticDocument;

::testing::AssertionResult sameScene(const Scene& a, const Scene& b) {
    if (a.layers.size() != b.layers.size()) return ::testing::AssertionFailure() << "layer count";
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer& p = a.layers[l];
        const Layer& q = b.layers[l];
        if (p.nodes.size() != q.nodes.size() || p.curves.size() != q.curves.size() || p.areas.size() != q.areas.size())
            return ::testing::AssertionFailure() << "layer " << l << " slot counts";
        for (std::size_t i = 0; i < p.nodes.size(); ++i)
            if (!sameBits(p.nodes[i].p, q.nodes[i].p) || p.nodes[i].curves != q.nodes[i].curves || p.nodes[i].alive != q.nodes[i].alive ||
                !sameBits(p.nodes[i].roundabout, q.nodes[i].roundabout))
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
    const int kind = int(uniform01(rng) * 11.0);
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
        case 8: return SetCurveClassCmd{layer, c, std::uint16_t(uniform01(rng) * 3.0)};
        case 9:  // the graph step's roundabouts (refused where they do not fit)
            return SetRoundaboutCmd{layer, n, l.nodes[n].roundabout > 0.0f ? 0.0f : float(8.0 + uniform01(rng) * 17.0)};
        default: {  // and its bridges: a bridge, a tunnel, a ford, or none of them
            static constexpr std::uint16_t flags[] = {0, kBridge, kTunnel, kNoBridge};
            return SetCurveFlagsCmd{layer, c, flags[std::size_t(uniform01(rng) * 4.0) % 4]};
        }
    }
    return std::nullopt;
}

// Sessions of small tiles (32 texels) refined down to `maxLevel`.
SessionParams smallTiles(int maxLevel, std::size_t cacheTiles = SessionParams{}.cacheTiles) {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = maxLevel;
    params.cacheTiles = cacheTiles;
    return params;
}

TEST(EditSession, RandomCommandsUndoneRestoreTheSceneAndEveryTileExactly) {
    SessionParams params = smallTiles(9, 1u << 20);
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

// Issue 14: dragging a road's end across a river makes its bridge in the frame of the command
// that crosses (the deck is in the frame's tiles' objects, no footprint flattens the river there),
// dragging it back removes it, and undo restores the graph, bridges included, exactly.
TEST(EditSession, DraggingARoadAcrossARiverMakesTheBridgeInThatFrameAndUndoRemovesIt) {
    SceneDocument doc;
    doc.scene.extent = {{0.0, 0.0}, {1024.0, 1024.0}};
    doc.scene.layers.resize(2);
    doc.scene.layers[kRoadsLayer].kind = LayerKind::Roads;
    doc.scene.layers[kRiversLayer].kind = LayerKind::Rivers;
    Layer& rivers = doc.scene.layers[kRiversLayer];
    Curve river;
    river.vertices = {{{512.0, 1000.0}}, {{512.0, 20.0}}};
    river.start = rivers.addNode({512.0, 1000.0});
    river.end = rivers.addNode({512.0, 20.0});
    river.w = 12.0f;
    river.wf = 24.0f;
    rivers.addCurve(river);
    Layer& roads = doc.scene.layers[kRoadsLayer];
    Curve road;
    road.vertices = {{{100.0, 500.0}}, {{400.0, 500.0}}};
    road.start = roads.addNode({100.0, 500.0});
    const ElementId end = road.end = roads.addNode({400.0, 500.0});
    road.w = 6.0f;
    road.wf = 12.0f;
    roads.addCurve(road);
    std::vector<float> h(64 * 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) h[std::size_t(j * 64 + i)] = float(500.0 + 0.2 * std::abs((i + 0.5) * 16.0 - 512.0));
    doc.dem = Dem(doc.scene.extent, 64, 64, std::move(h));
    SessionParams params = smallTiles(6, 1u << 20);
    EditSession session(std::move(doc), params);
    const glm::dvec3 viewer(512.0, 500.0, 30.0);
    session.frame(viewer, 0.0);
    const Quadtree& qt = session.quadtree();
    EXPECT_EQ(qt.proceduralCount(kBridge), 0u);
    bool bridgeSeen = false;
    for (int step = 1; step <= 10; ++step) {  // from x = 400 to x = 700, one drag
        session.execute(MoveNodeCmd{kRoadsLayer, end, {400.0 + 30.0 * step, 500.0}}, true);
        const bool across = 400.0 + 30.0 * step > 512.0;  // the road reaches over the river's axis
        EXPECT_EQ(qt.proceduralCount(kBridge), across ? 1u : 0u) << step;
        session.frame(viewer, 0.0);
        if (!across) continue;
        std::size_t decks = 0;
        for (const auto& [key, tile] : session.tiles())
            if (!tile.dirty)
                for (const ObjectPart& part : tile.objects.parts) decks += part.kind == ObjectKind::Deck;
        EXPECT_GE(decks, 1u) << step;
        bridgeSeen = true;
    }
    EXPECT_TRUE(bridgeSeen);
    expectTilesEqualFromScratch(session, params, "after the drag");
    session.execute(MoveNodeCmd{kRoadsLayer, end, {450.0, 500.0}}, true);  // back to this bank
    EXPECT_EQ(qt.proceduralCount(kBridge), 0u);
    session.undo();  // the whole drag, one step
    session.frame(viewer, 0.0);
    EXPECT_EQ(qt.proceduralCount(kBridge), 0u);
    EXPECT_EQ(session.document().scene.layers[kRoadsLayer].nodes[end].p, Vec2(400.0, 500.0));
    session.redo();
    session.frame(viewer, 0.0);
    EXPECT_EQ(qt.proceduralCount(kBridge), 0u);
    expectTilesEqualFromScratch(session, params, "after undo and redo");
    // The road over the river again, then the river moved under it: the road is expanded again
    // by the graph step (not in the changeset), its pieces keep their ids with new shapes, and
    // what the curve data held for them must go (the tiles equal a rebuild).
    session.execute(MoveNodeCmd{kRoadsLayer, end, {700.0, 500.0}});
    session.frame(viewer, 0.0);
    ASSERT_EQ(qt.proceduralCount(kBridge), 1u);
    const Curve& r = session.document().scene.layers[kRiversLayer].curves[0];
    const ElementId top = r.start, bottom = r.end;
    session.execute(MoveNodeCmd{kRiversLayer, top, {600.0, 1000.0}});
    session.execute(MoveNodeCmd{kRiversLayer, bottom, {560.0, 20.0}});
    session.frame(viewer, 0.0);
    EXPECT_EQ(qt.proceduralCount(kBridge), 1u);
    expectTilesEqualFromScratch(session, params, "after the river moved under the road");
}

TEST(EditSession, AFrameBudgetLeavesTheRestPendingNearestFirst) {
    SessionParams params;
    params.refine.resolution = 64;
    params.view.maxLevel = 10;
    params.cacheTiles = 1u << 20;  // every leaf of the view shown
    // A budget read on a stepped clock (each reading 0.1 ms later): what it lets through does not
    // depend on the machine's speed. One quad's two jobs are made whatever the budget.
    params.clock = steppedClockMs(0.1);
    EditSession session(syntheticDocument(12, 1500), params);
    const Vec2 c = session.document().scene.extent.center();
    const FrameReport first = session.frame({c.x, c.y, 20.0}, 0.05);
    EXPECT_GE(first.produced, 1u);
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

// Issue 28: a refinement budget shorter than one subdivision still refines, a subdivision a
// frame at least, until the tree is the one an unbudgeted session makes; its tiles then equal
// that session's.
TEST(EditSession, ARefineBudgetShorterThanOneSubdivisionStillReachesTheCompleteTree) {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = 9;
    params.cacheTiles = 1u << 20;  // every leaf of the view shown
    const SceneDocument doc = syntheticDocument(12, 1500);
    EditSession complete(doc, params);
    params.refineBudgetMs = 1e-6;  // far less than one clock step
    params.clock = steppedClockMs(0.1);
    EditSession budgeted(doc, params);
    const Vec2 c = doc.scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 25.0);
    const FrameReport all = complete.frame(viewer, 0.0);
    EXPECT_FALSE(all.refineDeferred);
    const std::size_t subdivisions = (complete.quadtree().quadCount() - 1) / 4;
    std::size_t frames = 0;
    for (FrameReport r; frames == 0 || r.refineDeferred; ++frames) {
        ASSERT_LE(frames, subdivisions) << "a frame made no progress";
        const std::size_t before = budgeted.quadtree().quadCount();
        r = budgeted.frame(viewer, 0.0);
        EXPECT_EQ(budgeted.quadtree().quadCount(), before + 4) << "frame " << frames;
    }
    EXPECT_EQ(frames, subdivisions);
    EXPECT_EQ(compareQuadtrees(complete.quadtree(), budgeted.quadtree()).mismatches, 0u);
    budgeted.frame(viewer, 0.0);
    std::size_t compared = 0;
    complete.quadtree().forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        const CachedTile* a = complete.tile(keyOf(q));
        const CachedTile* b = budgeted.tile(keyOf(q));
        ASSERT_NE(a, nullptr);
        ASSERT_NE(b, nullptr);
        EXPECT_TRUE(a->appearance == b->appearance && a->elevation == b->elevation) << "L" << q.level << " " << q.tx << "," << q.ty;
        ++compared;
    });
    EXPECT_GT(compared, 20u);
}

// An inner vertex of a road of the session's scene with at least three vertices.
std::pair<ElementId, std::size_t> someInnerVertex(const Scene& s) {
    const Layer& l = s.layers[kRoadsLayer];
    for (ElementId id = 0; id < l.curves.size(); ++id)
        if (l.curves[id].alive && l.curves[id].vertices.size() >= 3) return {id, 1};
    return {kNoElement, 0};
}

TEST(EditSession, ADragIsOneUndoStepAndAGroupUndoesTogether) {
    SessionParams params = smallTiles(8);
    EditSession session(syntheticDocument(13, 800), params);
    const Scene original = session.document().scene;
    EXPECT_FALSE(session.modified());
    const auto [curve, index] = someInnerVertex(original);
    ASSERT_NE(curve, kNoElement);
    const Vec2 p0 = original.layers[kRoadsLayer].curves[curve].vertices[index].p;
    // A drag in 10 steps, merged: one undo step back to where it began.
    for (int k = 1; k <= 10; ++k)
        session.execute(MoveVertexCmd{kRoadsLayer, curve, index, p0 + Vec2(3.0 * k, -2.0 * k)}, true);
    EXPECT_EQ(session.undoDepth(), 1u);
    EXPECT_TRUE(session.modified());
    const Scene dragged = session.document().scene;
    EXPECT_EQ(dragged.layers[kRoadsLayer].curves[curve].vertices[index].p, p0 + Vec2(30.0, -20.0));
    ASSERT_TRUE(session.undo());
    EXPECT_TRUE(sameScene(session.document().scene, original));
    EXPECT_FALSE(session.modified());
    ASSERT_TRUE(session.redo());
    EXPECT_TRUE(sameScene(session.document().scene, dragged));
    // Without merging, each move is its own step; a move of another vertex never merges.
    session.execute(MoveVertexCmd{kRoadsLayer, curve, index, p0}, false);
    EXPECT_EQ(session.undoDepth(), 2u);
    // A group (a new road: two nodes and its curve) is undone and redone as one.
    const Scene beforeGroup = session.document().scene;
    const Vec2 a = original.extent.center(), b = a + Vec2(120.0, 35.0);
    session.beginGroup();
    session.execute(AddNodeCmd{kRoadsLayer, a});
    const ElementId na = ElementId(session.document().scene.layers[kRoadsLayer].nodes.size() - 1);
    session.execute(AddNodeCmd{kRoadsLayer, b});
    const ElementId nb = na + 1;
    Curve c;
    c.vertices = {{a}, {(a + b) * 0.5, false}, {b}};
    c.start = na, c.end = nb, c.w = 6.0f, c.wf = 12.0f;
    session.execute(AddCurveCmd{kRoadsLayer, c});
    session.endGroup();
    const Scene afterGroup = session.document().scene;
    EXPECT_EQ(session.undoDepth(), 5u);
    ASSERT_TRUE(session.undo());
    EXPECT_EQ(session.undoDepth(), 2u);
    EXPECT_TRUE(sameScene(session.document().scene, beforeGroup));
    ASSERT_TRUE(session.redo());
    EXPECT_TRUE(sameScene(session.document().scene, afterGroup));
}

TEST(EditSession, SavingMarksTheSceneUnmodifiedAndADragAfterItIsNewHistory) {
    SessionParams params = smallTiles(8);
    EditSession session(syntheticDocument(14, 600), params);
    const auto [curve, index] = someInnerVertex(session.document().scene);
    const Vec2 p0 = session.document().scene.layers[kRoadsLayer].curves[curve].vertices[index].p;
    session.execute(MoveVertexCmd{kRoadsLayer, curve, index, p0 + Vec2(5.0, 0.0)}, true);
    const std::string path = ::testing::TempDir() + "/lacet_session_save.gpkg";
    saveScene(path, session.document());
    session.markSaved();
    EXPECT_FALSE(session.modified());
    // The next drag step does not merge into the saved step: undoing it returns to the saved scene.
    session.execute(MoveVertexCmd{kRoadsLayer, curve, index, p0 + Vec2(9.0, 0.0)}, true);
    EXPECT_TRUE(session.modified());
    EXPECT_EQ(session.undoDepth(), 2u);
    session.undo();
    EXPECT_FALSE(session.modified());
    const SceneDocument loaded = loadScene(path);
    EXPECT_TRUE(sameScene(loaded.scene, session.document().scene));
    session.undo();
    EXPECT_TRUE(session.modified());
}

TEST(EditSession, OnlyVisibleLeavesAreMadeAndPrefetchingMakesThePredictedViewersTiles) {
    SessionParams params = smallTiles(10, 1u << 20);
    const SceneDocument doc = syntheticDocument(15, 1500);
    const Vec2 c = doc.scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 30.0);
    // Visible: the half of the scene east of the viewer.
    const QuadVisibility east = [&](const Quad& q) { return q.bounds.max.x > c.x; };
    EditSession session(SceneDocument(doc), params);
    const FrameReport r = session.frame(viewer, 0.0, east);
    EXPECT_GT(r.culled, 0u);
    EXPECT_EQ(r.pending, 0u);
    session.quadtree().forEachQuad([&](const Quad& q) {
        if (q.isLeaf()) {
            EXPECT_EQ(session.tile(keyOf(q)) != nullptr, east(q)) << q.level << " " << q.tx << " " << q.ty;
        }
    });
    // Prefetching: the view's leaves are the same as without, and the predicted viewer's leaves
    // get tiles too.
    EditSession plain(SceneDocument(doc), params), ahead(SceneDocument(doc), params);
    const glm::dvec3 later(c.x + 400.0, c.y + 300.0, 20.0);
    const FrameReport a = plain.frame(viewer, 0.0);
    const FrameReport b = ahead.frame(viewer, 0.0, {}, later);
    EXPECT_EQ(a.viewQuads, b.viewQuads);
    EXPECT_EQ(a.produced, b.produced);
    EXPECT_GT(b.prefetched, 0u);
    const FrameReport atLater = ahead.frame(later, 0.0);
    const FrameReport fresh = plain.frame(later, 0.0);
    EXPECT_LT(atLater.produced, fresh.produced);  // what was prefetched is not made again

    // Prefetching fills the cache's room only, and what it made survives the next frame's LRU
    // (before, tiles made ahead were the first evicted, and made again frame after frame).
    SessionParams small = params;
    small.cacheTiles = a.cached + 5;
    EditSession bounded(SceneDocument(doc), small);
    const FrameReport first = bounded.frame(viewer, 0.0, {}, later);
    EXPECT_EQ(first.prefetched, 5u);
    EXPECT_EQ(first.cached, small.cacheTiles);
    const FrameReport second = bounded.frame(viewer, 0.0, {}, later);
    EXPECT_EQ(second.produced, 0u);
    EXPECT_EQ(second.prefetched, 0u);  // no room left, and nothing evicted to make again
    EXPECT_EQ(second.cached, small.cacheTiles);
    // A cache full of tiles nobody shows any more (the view moved on) is room: it does not stop
    // prefetching. The budget is what the LRU may not evict at `later` (its view's tiles and
    // their ancestors') and 5 more.
    EditSession probe(SceneDocument(doc), params);
    probe.frame(viewer, 0.0);
    SessionParams room = params;
    room.cacheTiles = probe.frame(later, 0.0).kept + 5;
    EditSession full(SceneDocument(doc), room);
    full.frame(viewer, 0.0);
    EXPECT_EQ(full.frame(later, 0.0).cached, room.cacheTiles);  // full, of the old view's tiles too
    const FrameReport third = full.frame(later, 0.0, {}, glm::dvec3(later.x + 400.0, later.y + 300.0, 20.0));
    EXPECT_EQ(third.prefetched, 5u);
    EXPECT_EQ(third.cached, room.cacheTiles);
}

// Every visible leaf has a tile to draw, its own or its nearest ancestor's (as the window
// draws it), and that tile is clean.
void expectEveryLeafDrawsACleanTile(const EditSession& session, const QuadVisibility& visible, const std::string& when) {
    session.quadtree().forEachQuad([&](const Quad& q) {
        if (!q.isLeaf() || (visible && !visible(q))) return;
        const Quad* a = &q;
        while (a && !session.tile(keyOf(*a))) a = a->parent;
        ASSERT_NE(a, nullptr) << "a leaf with nothing to show, " << when;
        EXPECT_FALSE(session.tile(keyOf(*a))->dirty) << when << ", level " << q.level;
    });
}

TEST(EditSession, TheCacheNeverHoldsMoreThanItsBudgetAndEveryLeafStillHasATileToShow) {
    // A budget below what the view and its ancestors need (§9.1): the farthest quads are shown in
    // place of their children. Along a flight, with and without prefetching, behind a frustum-like
    // half-plane (parents with one visible child) and with edits, the cache stays within its
    // budget and every visible leaf is drawn with its tile or an ancestor's, never a dirty one.
    const SceneDocument doc = syntheticDocument(17, 1500);
    const Vec2 c = doc.scene.extent.center();
    SessionParams big = smallTiles(11, 1u << 20);
    EditSession unbounded(SceneDocument(doc), big);
    const FrameReport all = unbounded.frame({c.x, c.y, 15.0}, 0.0);
    ASSERT_EQ(all.replaced, 0u);
    const SessionParams params = smallTiles(11, all.kept / 3);
    for (const bool prefetch : {false, true}) {
        EditSession session(SceneDocument(doc), params);
        std::mt19937_64 rng(31);
        std::size_t replaced = 0, dirtied = 0;
        for (int f = 0; f < 40; ++f) {
            const glm::dvec3 viewer(c.x + 12.0 * f, c.y - 7.0 * f, 15.0 + 2.0 * f);
            const QuadVisibility visible = [&](const Quad& q) { return q.bounds.max.x + q.bounds.max.y > viewer.x + viewer.y - 150.0; };
            for (int e = 0; e < (f % 3 == 1 ? 4 : 0); ++e)  // edits: tiles go dirty
                if (const auto cmd = randomCommand(session.document().scene, rng)) {
                    try {
                        dirtied += session.execute(*cmd).dirtyTiles;
                    } catch (const EditError&) {
                    }
                }
            const auto ahead = prefetch ? std::optional(viewer + glm::dvec3(60.0, -35.0, 10.0)) : std::nullopt;
            const FrameReport r = session.frame(viewer, 0.0, visible, ahead);
            replaced += r.replaced;
            ASSERT_LE(r.cached, params.cacheTiles) << "frame " << f << ", prefetch " << prefetch;
            EXPECT_EQ(r.pending, 0u);
            expectEveryLeafDrawsACleanTile(session, visible, "frame " + std::to_string(f));
        }
        EXPECT_GT(replaced, 0u);
        EXPECT_GT(dirtied, 0u);
    }
}

TEST(EditSession, AnEditedLeafThatAnAncestorStandsInForIsNotDrawnStale) {
    // Far leaves get their own tiles while the view is small; then the whole view needs more
    // than the cache holds, ancestors stand in for them, and the one the cache has room for keeps
    // its clean tile. An edit then dirties that tile: the next frame must not leave it to be drawn.
    const SceneDocument doc = syntheticDocument(17, 1500);
    const Vec2 c = doc.scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 15.0);
    EditSession unbounded(SceneDocument(doc), smallTiles(11, 1u << 20));
    const std::size_t need = unbounded.frame(viewer, 0.0).kept;
    EditSession session(SceneDocument(doc), smallTiles(11, need / 3));
    const double far = 600.0;
    const QuadVisibility farOnly = [&](const Quad& q) { return Quadtree::viewDistance(q, viewer) > far; };
    ASSERT_EQ(session.frame(viewer, 0.0, farOnly).replaced, 0u);
    const FrameReport whole = session.frame(viewer, 0.0);
    ASSERT_GT(whole.replaced, 0u);
    // The farthest leaf that kept its tile (the cache had room for it), and a node inside it.
    const Quad* leaf = nullptr;
    session.quadtree().forEachQuad([&](const Quad& q) {
        if (q.isLeaf() && session.tile(keyOf(q)) && (!leaf || Quadtree::viewDistance(q, viewer) > Quadtree::viewDistance(*leaf, viewer)))
            leaf = &q;
    });
    ASSERT_NE(leaf, nullptr);
    ASSERT_GT(Quadtree::viewDistance(*leaf, viewer), far);
    // A node of a curve or area the leaf holds, moved by half a metre.
    std::optional<MoveNodeCmd> move;
    const auto& layers = session.document().scene.layers;
    for (LayerId l = 0; l < leaf->layers.size() && !move; ++l) {
        ElementId curve = kNoElement;
        if (!leaf->layers[l].curves.empty()) curve = rootCurveOf(leaf->layers[l].curves.begin()->first);
        else if (!leaf->layers[l].areas.empty()) curve = layers[l].areas[leaf->layers[l].areas.begin()->first].loops.front().front().curve;
        if (curve == kNoElement) continue;
        const ElementId node = layers[l].curves[curve].start;
        move = MoveNodeCmd{l, node, layers[l].nodes[node].p + Vec2(0.5, 0.25)};
    }
    ASSERT_TRUE(move.has_value());
    session.execute(*move);
    ASSERT_TRUE(session.tile(keyOf(*leaf)) && session.tile(keyOf(*leaf))->dirty);
    const FrameReport after = session.frame(viewer, 0.0);
    ASSERT_GT(after.replaced, 0u);
    EXPECT_EQ(session.tile(keyOf(*leaf)), nullptr) << "replaced, so not made again: dropped";
    expectEveryLeafDrawsACleanTile(session, {}, "after the edit");
}

TEST(EditSession, DisplayedHeightIsTheDeepestTilesHeightAndTheDemElsewhere) {
    SessionParams params = smallTiles(9);
    EditSession session(syntheticDocument(16, 800), params);
    const Vec2 c = session.document().scene.extent.center();
    session.frame({c.x, c.y, 20.0}, 0.0);
    const auto [q, t] = session.tileAt(c);
    ASSERT_NE(t, nullptr);
    EXPECT_TRUE(q->isLeaf());
    const ElevationTile& e = t->elevation;
    for (int j = 0; j < e.resolution; j += 5)
        for (int i = 0; i < e.resolution; i += 7)
            EXPECT_NEAR(session.displayedHeight(e.position(i, j)), e.zm[e.index(i, j)], 1e-3);
}

TEST(EditSession, AHiddenLayerLeavesTheTexturesAndShowingItAgainRestoresThemExactly) {
    SessionParams params = smallTiles(9, 1u << 20);
    EditSession session(syntheticDocument(17, 1200), params);
    const Vec2 c = session.document().scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 30.0);
    session.frame(viewer, 0.0);
    const std::map<QuadKey, CachedTile> shown = session.tiles();
    session.setLayerVisible(kRoadsLayer, false);
    EXPECT_FALSE(session.layerVisible(kRoadsLayer));
    const FrameReport hiddenFrame = session.frame(viewer, 0.0);
    EXPECT_GT(hiddenFrame.produced, 0u);
    // Every view tile is what the producers make without the roads; those with roads changed.
    SessionParams without = params;
    without.appearance.hiddenLayers = {true};
    without.elevation.hiddenLayers = {true};
    expectTilesEqualFromScratch(session, without, "roads hidden");
    std::size_t changed = 0;
    for (const auto& [key, tile] : shown) {
        const CachedTile* now = session.tile(key);
        ASSERT_NE(now, nullptr);
        changed += !(now->appearance == tile.appearance && now->elevation == tile.elevation);
    }
    EXPECT_GT(changed, 0u);
    session.setLayerVisible(kRoadsLayer, true);
    session.frame(viewer, 0.0);
    for (const auto& [key, tile] : shown) {
        const CachedTile* now = session.tile(key);
        ASSERT_NE(now, nullptr);
        EXPECT_TRUE(now->appearance == tile.appearance && now->elevation == tile.elevation);
    }
}

}  // namespace
}  // namespace lacet
