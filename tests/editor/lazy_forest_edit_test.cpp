// Edits of a scene file read lazily (§7, issue 23; editor/lazy_forest.h, editor/lazy_edits.h):
// random edits give the whole scene's tiles and undo restores them; a long road dragged and a road
// drawn are taken by the parts in memory where nothing else would be read; an edit of an element
// the file has not is refused. The scene of tests/editor/lazy_forest_fixture.h.
#include <algorithm>
#include <cmath>
#include <optional>

#include "tests/editor/lazy_forest_fixture.h"

namespace lacet {
namespace {

class LazyForestEditTest : public LazyForestTest {};

// The part (of level kPartLevel) holding point p.
QuadKey partAt(const Box& extent, Vec2 p) {
    const double n = double(1 << kPartLevel);
    const Vec2 cell = (p - extent.min) / extent.size() * n;
    return {kPartLevel, int(std::clamp(std::floor(cell.x), 0.0, n - 1.0)), int(std::clamp(std::floor(cell.y), 0.0, n - 1.0))};
}

// A road whose curve and nodes lie in one part, moved whole (its nodes and control points, one
// group) into the next part: the part it left and the one it enters give the whole scene's tiles,
// and so do both after the undo.
TEST_F(LazyForestEditTest, ARoadMovedFromOnePartIntoAnotherGivesTheWholeScenesTilesThereAndBack) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    const Scene& scene = whole.document().scene;
    const Box e = scene.extent;
    const double side = e.size().x / double(1 << kPartLevel);
    const Layer& roads = scene.layers[kRoadsLayer];
    // A road within a part that has a part to its right (the curves at its nodes follow them).
    ElementId pick = kNoElement;
    for (ElementId c = 0; c < roads.curves.size() && pick == kNoElement; ++c) {
        const Curve& curve = roads.curves[c];
        if (!curve.alive || curve.flags != 0 || roads.nodes[curve.start].roundabout > 0.0f || roads.nodes[curve.end].roundabout > 0.0f)
            continue;
        const Box hull = hullBox(curve);
        if (hull.size().x > 0.5 * side || partAt(e, hull.min) != partAt(e, hull.max) || std::get<1>(partAt(e, hull.min)) + 1 >= (1 << kPartLevel))
            continue;
        pick = c;
    }
    ASSERT_NE(pick, kNoElement) << "no road within one part";
    const Curve road = roads.curves[pick];
    const Box hull = hullBox(road);
    const QuadKey from = partAt(e, hull.min);
    const double right = e.min.x + double(std::get<1>(from) + 1) * side;
    const Vec2 shift(right - hull.min.x + 0.25 * side, 0.0);
    ASSERT_EQ(std::get<1>(partAt(e, hull.min + shift)), std::get<1>(from) + 1);
    const auto look = [&](const char* when) {
        SCOPED_TRACE(when);
        for (const Vec2 p : {hull.center(), hull.center() + shift}) {
            whole.frame({p.x, p.y, 60.0}, 0.0);
            lazy.frame({p.x, p.y, 60.0}, 0.0);
            expectSameTiles(lazy, whole);
        }
    };
    look("before");
    ASSERT_TRUE(lazy.lazyForest()->holds(from));
    // The targets from the positions before the move (`roads` is the whole session's, which moves).
    std::vector<Command> commands{MoveNodeCmd{kRoadsLayer, road.start, roads.nodes[road.start].p + shift},
                                  MoveNodeCmd{kRoadsLayer, road.end, roads.nodes[road.end].p + shift}};
    for (std::size_t i = 1; i + 1 < road.vertices.size(); ++i) commands.push_back(MoveVertexCmd{kRoadsLayer, pick, i, road.vertices[i].p + shift});
    for (EditSession* s : {&whole, &lazy}) {
        s->beginGroup();
        for (const Command& c : commands) s->execute(c);
        s->endGroup();
    }
    EXPECT_EQ(whole.document().scene.layers[kRoadsLayer].curves[pick].vertices.front().p, road.vertices.front().p + shift);
    look("moved");
    ASSERT_TRUE(whole.undo());
    ASSERT_TRUE(lazy.undo());
    look("undone");
}

// An edit whose parts were dropped for the budget before its undo (the viewer went elsewhere):
// the undo changes no part held, and the parts read again when the viewer comes back are the
// file's with the edit taken back: the whole scene's tiles.
TEST_F(LazyForestEditTest, TheUndoOfAnEditWhosePartsWereDroppedSinceGivesTheWholeScenesTilesWhenTheyAreReadAgain) {
    const auto [top, largest] = partSizes();
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(top + 2.2 * largest), sessionParams());  // room for two parts
    const Scene& scene = whole.document().scene;
    const Box e = scene.extent;
    const Layer& roads = scene.layers[kRoadsLayer];
    // A road's control point; the viewer then goes to the opposite side of the scene.
    ElementId pick = kNoElement;
    for (ElementId c = 0; c < roads.curves.size() && pick == kNoElement; ++c)
        if (roads.curves[c].alive && roads.curves[c].vertices.size() >= 3 && !roads.curves[c].vertices[1].onCurve) pick = c;
    ASSERT_NE(pick, kNoElement);
    const Vec2 here = roads.curves[pick].vertices[1].p;
    // The corner of the scene farthest from it, a little inside.
    const Vec2 there(here.x < e.center().x ? e.max.x - 0.05 * e.size().x : e.min.x + 0.05 * e.size().x,
                     here.y < e.center().y ? e.max.y - 0.05 * e.size().y : e.min.y + 0.05 * e.size().y);
    const QuadKey part = partAt(e, here);
    const auto view = [&](Vec2 p) {
        whole.frame({p.x, p.y, 30.0}, 0.0);
        lazy.frame({p.x, p.y, 30.0}, 0.0);
    };
    // With room for two parts the lazy session shows coarser quads where it could read none: the
    // tiles of the edit's part it made are compared, and they must be there.
    const auto samePartTiles = [&] {
        std::size_t compared = 0;
        for (const auto& [key, t] : lazy.tiles()) {
            const auto [level, x, y] = key;
            if (level < kPartLevel || t.dirty || QuadKey{kPartLevel, x >> (level - kPartLevel), y >> (level - kPartLevel)} != part) continue;
            const CachedTile* w = whole.tile(key);
            ASSERT_NE(w, nullptr) << level << "/" << x << "/" << y;
            EXPECT_EQ(t.texels(), w->texels()) << level << "/" << x << "/" << y;
            EXPECT_EQ(t.elevation.zm, w->elevation.zm) << level << "/" << x << "/" << y;
            ++compared;
        }
        EXPECT_GT(compared, 4u);
    };
    view(here);
    ASSERT_TRUE(lazy.lazyForest()->holds(part));
    const Command move = MoveVertexCmd{kRoadsLayer, pick, 1, roads.curves[pick].vertices[1].p + Vec2(25.0, -18.0)};
    whole.execute(move);
    lazy.execute(move);
    view(here);
    samePartTiles();
    view(there);
    ASSERT_FALSE(lazy.lazyForest()->holds(part)) << "the edit's part was not dropped: the test proves nothing";
    const std::size_t read = lazy.lazyForest()->stats().partsRead;
    ASSERT_TRUE(whole.undo());
    ASSERT_TRUE(lazy.undo());
    view(there);
    view(here);
    EXPECT_GT(lazy.lazyForest()->stats().partsRead, read) << "the edit's part was not read again";
    ASSERT_TRUE(lazy.lazyForest()->holds(part));
    samePartTiles();
}

// A river far from a part, under a long road the part holds (its read brought the river: the graph
// step's bridge), deleted and brought back by undo: the part is renewed both times (the undo
// names nothing it holds, and meets nowhere near it), so it keeps the road's bridge as the whole
// scene does.
TEST_F(LazyForestEditTest, ARiverUnderAFarPartsRoadDeletedAndBroughtBackRenewsThatPart) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    const Scene& scene = whole.document().scene;
    const Box e = scene.extent;
    const double side = e.size().x / double(1 << kPartLevel);
    // (road layer, road, river layer, river, part): the road meets the part's quad, the river its
    // hull and not the part's quad dilated by a quarter of a part.
    struct Case {
        LayerId riverLayer = 0;
        ElementId river = kNoElement;
        QuadKey part;
    };
    std::optional<Case> found;
    for (LayerId rl = 0; rl < scene.layers.size() && !found; ++rl) {
        if (scene.layers[rl].kind != LayerKind::Roads) continue;
        for (const Curve& road : scene.layers[rl].curves) {
            if (!road.alive || found) continue;
            const Box hull = hullBox(road);
            for (LayerId vl = 0; vl < scene.layers.size() && !found; ++vl) {
                if (scene.layers[vl].kind != LayerKind::Rivers) continue;
                for (ElementId v = 0; v < scene.layers[vl].curves.size() && !found; ++v) {
                    const Curve& river = scene.layers[vl].curves[v];
                    if (!river.alive || !river.areas.empty() || !hullBox(river).intersects(hull)) continue;
                    for (int x = 0; x < (1 << kPartLevel) && !found; ++x)
                        for (int y = 0; y < (1 << kPartLevel) && !found; ++y) {
                            const Box quad{e.min + Vec2(double(x), double(y)) * side, e.min + Vec2(double(x + 1), double(y + 1)) * side};
                            if (quad.intersects(hull) && !quad.dilated(0.25 * side).intersects(hullBox(river)))
                                found = Case{vl, v, QuadKey{kPartLevel, x, y}};
                        }
                }
            }
        }
    }
    ASSERT_TRUE(found) << "no river under a road far from a part the road crosses";
    const auto [l, x, y] = found->part;
    const Vec2 c = e.min + (Vec2(double(x), double(y)) + 0.5) * side;
    const auto look = [&](const char* when) {
        SCOPED_TRACE(when);
        whole.frame({c.x, c.y, 80.0}, 0.0);
        lazy.frame({c.x, c.y, 80.0}, 0.0);
        expectSameTiles(lazy, whole);
    };
    // The parts holding the river (the far one among them, through the road).
    const auto holding = [&] {
        std::size_t n = 0;
        lazy.lazyForest()->forEachPart([&](const SceneDocument& part) {
            n += localIdOf(part.scene.layers[found->riverLayer], ElementKind::Curve, found->river) != kNoElement;
        });
        return n;
    };
    look("before");
    ASSERT_TRUE(lazy.lazyForest()->holds(found->part));
    const std::size_t held = holding();
    ASSERT_GT(held, 0u);
    const Command del = DeleteCurveCmd{found->riverLayer, found->river};
    whole.execute(del);
    lazy.execute(del);
    look("deleted");
    const LazyStats before = lazy.lazyForest()->stats();
    ASSERT_TRUE(whole.undo());
    ASSERT_TRUE(lazy.undo());
    EXPECT_GT(lazy.lazyForest()->stats().partsRenewed, before.partsRenewed) << "the undo renewed no part";
    EXPECT_EQ(holding(), held) << "a part that held the river before the delete does not hold it after the undo";
    look("brought back");
}

TEST_F(LazyForestEditTest, EditsOfAPartialSceneGiveTheWholeScenesTilesAndUndoRestoresThem) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    // Under the sanitizers, 8 edits, each undone with a chance of one in two rather than one in
    // five, so that some are undone.
    const int edits = test::sanitizedOr(28, 8);
    const double undoChance = test::kSanitized ? 0.5 : 0.2;
    expectSameEdits(checkLazyEdits(lazy, whole, {.seed = 5, .edits = edits, .undoChance = undoChance}), false, std::size_t(edits));
    EXPECT_GT(lazy.lazyForest()->stats().partsRenewed, 0u);
}

// A road longer than the parts it crosses, its control points dragged: each part that holds it is
// updated in memory (no read) when every river its hull meets, found through the file's R-trees,
// is held; the tiles stay the whole scene's.
TEST_F(LazyForestEditTest, ARoadLongerThanItsPartsIsMovedInMemoryWhereTheRiversItsHullMeetsAreHeld) {
    constexpr int kLevel = 3;
    EditSession whole(loadScene(*path_), sessionParams());
    const Scene& s = whole.document().scene;
    const Box e = s.extent;
    const double side = e.size().x / double(1 << kLevel);
    const Layer& roads = s.layers[kRoadsLayer];
    std::size_t most = 0;
    ElementId longest = kNoElement;
    for (ElementId id = 0; id < roads.curves.size(); ++id) {
        if (!roads.curves[id].alive || (roads.curves[id].flags & kBridge)) continue;
        std::set<std::pair<int, int>> parts;
        for (const Vertex& v : roads.curves[id].vertices) parts.insert({int((v.p.x - e.min.x) / side), int((v.p.y - e.min.y) / side)});
        if (parts.size() > most) most = parts.size(), longest = id;
    }
    ASSERT_GE(most, 3u) << "no road crosses three parts";
    const std::vector<Vertex> along = roads.curves[longest].vertices;
    std::vector<std::size_t> controls;
    for (std::size_t i = 1; i + 1 < along.size(); ++i)
        if (!along[i].onCurve) controls.push_back(i);
    ASSERT_GE(controls.size(), 2u);
    LazyParams lp = lazyParams(1024.0);
    lp.partLevel = kLevel;
    EditSession lazy(*path_, lp, sessionParams());
    const auto frames = [&] {
        for (std::size_t k = 0; k < along.size(); k += std::max<std::size_t>(1, along.size() / 5)) {
            const glm::dvec3 viewer{along[k].p.x, along[k].p.y, 120.0};
            whole.frame(viewer, 0.0);
            lazy.frame(viewer, 0.0);
        }
    };
    frames();
    const LazyStats before = lazy.lazyForest()->stats();
    const int steps = test::sanitizedOr(4, 2);
    for (int step = 1; step <= steps; ++step)
        for (const std::size_t i : {controls.front(), controls.back()}) {
            const Command move = MoveVertexCmd{kRoadsLayer, longest, i, along[i].p + Vec2(3.0, -2.0) * double(step)};
            whole.execute(move);
            lazy.execute(move);
            frames();
        }
    const LazyStats& after = lazy.lazyForest()->stats();
    EXPECT_GT(after.partsMoved - before.partsMoved, 2u * steps);  // more than one part a step
    EXPECT_EQ(after.partsRefused, before.partsRefused);
    expectSameTiles(lazy, whole, kLevel);
}

// A road drawn (two new nodes and a curve between them, as the draw tool makes it) and taken
// back: each part that holds it takes it in memory, without a read, its tiles made again only
// where the road is, as in the whole scene; the tiles stay the whole scene's.
TEST_F(LazyForestEditTest, ARoadDrawnAndTakenBackUpdatesThePartsHoldingItInPlace) {
    EditSession whole(loadScene(*path_), sessionParams());
    LazyParams lp = lazyParams(1024.0);
    lp.topElevationOnly = true;  // the top holds the wide roads only: this one is not among them
    EditSession lazy(*path_, lp, sessionParams());
    const Box e = whole.document().scene.extent;
    const Vec2 a = e.center() + Vec2(35.0, -20.0), b = a + Vec2(140.0, 60.0);
    const glm::dvec3 viewer{a.x, a.y, 150.0};
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    const LazyStats before = lazy.lazyForest()->stats();
    std::size_t wholeDirty = 0, lazyDirty = 0;
    const auto both = [&](const Command& c) {
        wholeDirty += whole.execute(c).dirtyTiles;
        const CommandReport r = lazy.execute(c);
        lazyDirty += r.dirtyTiles;
        EXPECT_FALSE(r.topReadAgain);
    };
    for (EditSession* s : {&whole, &lazy}) s->beginGroup();
    Curve road;
    road.start = lazy.nextId(kRoadsLayer, ElementKind::Node);
    road.end = road.start + 1;
    ASSERT_EQ(road.start, whole.nextId(kRoadsLayer, ElementKind::Node));
    both(AddNodeCmd{kRoadsLayer, a});
    both(AddNodeCmd{kRoadsLayer, b});
    road.w = 4.0f;
    road.wf = 10.0f;
    road.vertices = {Vertex{a, true, false}, Vertex{(a + b) * 0.5 + Vec2(-10.0, 12.0), false, false}, Vertex{b, true, false}};
    both(AddCurveCmd{kRoadsLayer, road});
    for (EditSession* s : {&whole, &lazy}) s->endGroup();
    const LazyStats& drawn = lazy.lazyForest()->stats();
    ASSERT_GT(drawn.partsRenewed, before.partsRenewed);
    // Every part renewed took the road in memory: none was read again.
    EXPECT_EQ(drawn.partsRenewed - before.partsRenewed,
              (drawn.partsGrown - before.partsGrown) + (drawn.partsMoved - before.partsMoved));
    EXPECT_GT(drawn.partsGrown, before.partsGrown);
    EXPECT_EQ(drawn.partsUpdated, before.partsUpdated);
    EXPECT_LE(lazyDirty, wholeDirty + 8) << "the lazy session made dirty far more tiles than the whole one";
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    expectSameTiles(lazy, whole);
    const LazyStats undoneBefore = lazy.lazyForest()->stats();
    ASSERT_TRUE(whole.undo());
    ASSERT_TRUE(lazy.undo());
    const LazyStats& undone = lazy.lazyForest()->stats();
    EXPECT_EQ(undone.partsRenewed - undoneBefore.partsRenewed, undone.partsGrown - undoneBefore.partsGrown);
    EXPECT_EQ(undone.partsUpdated, undoneBefore.partsUpdated);
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    expectSameTiles(lazy, whole);
    const LazyStats redoneBefore = lazy.lazyForest()->stats();
    ASSERT_TRUE(whole.redo());
    ASSERT_TRUE(lazy.redo());
    EXPECT_EQ(lazy.lazyForest()->stats().partsUpdated, redoneBefore.partsUpdated);
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    expectSameTiles(lazy, whole);

    // A road drawn from a road's node (held, with its curves): the node's curves change in memory.
    const Layer& roads = whole.document().scene.layers[kRoadsLayer];
    ElementId from = kNoElement;
    for (ElementId n = 0; n < roads.nodes.size(); ++n)
        if (roads.nodes[n].alive && !roads.nodes[n].curves.empty() && roads.nodes[n].roundabout == 0.0f &&
            (from == kNoElement || glm::length(roads.nodes[n].p - a) < glm::length(roads.nodes[from].p - a)))
            from = n;
    ASSERT_NE(from, kNoElement);
    const Vec2 p = roads.nodes[from].p, q = p + Vec2(-70.0, 45.0);
    const LazyStats joinedBefore = lazy.lazyForest()->stats();
    for (EditSession* s : {&whole, &lazy}) s->beginGroup();
    Curve spur;
    spur.start = from;
    spur.end = lazy.nextId(kRoadsLayer, ElementKind::Node);
    both(AddNodeCmd{kRoadsLayer, q});
    spur.w = 4.0f;
    spur.wf = 10.0f;
    spur.vertices = {Vertex{p, true, false}, Vertex{q, true, false}};
    both(AddCurveCmd{kRoadsLayer, spur});
    for (EditSession* s : {&whole, &lazy}) s->endGroup();
    EXPECT_GT(lazy.lazyForest()->stats().partsGrown, joinedBefore.partsGrown);
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    expectSameTiles(lazy, whole);
    // A road wider than every road a part holds: the part's read would reach farther (its reach
    // follows the widest road), so the parts it touches are read again, not grown in memory.
    for (EditSession* s : {&whole, &lazy}) s->beginGroup();
    Curve wide;
    wide.start = lazy.nextId(kRoadsLayer, ElementKind::Node);
    wide.end = wide.start + 1;
    const Vec2 w0 = a + Vec2(-300.0, 250.0), w1 = w0 + Vec2(120.0, 0.0);
    both(AddNodeCmd{kRoadsLayer, w0});
    both(AddNodeCmd{kRoadsLayer, w1});
    wide.w = 60.0f;
    wide.wf = 400.0f;
    wide.vertices = {Vertex{w0, true, false}, Vertex{w1, true, false}};
    const LazyStats beforeWide = lazy.lazyForest()->stats();
    both(AddCurveCmd{kRoadsLayer, wide});
    for (EditSession* s : {&whole, &lazy}) s->endGroup();
    EXPECT_EQ(lazy.lazyForest()->stats().partsGrown, beforeWide.partsGrown);
    EXPECT_GT(lazy.lazyForest()->stats().partsRenewed, beforeWide.partsRenewed);
    whole.frame(viewer, 0.0);
    lazy.frame(viewer, 0.0);
    expectSameTiles(lazy, whole);
    for (int k = 0; k < 3; ++k) {  // the wide road, the spur, then the road
        ASSERT_TRUE(whole.undo());
        ASSERT_TRUE(lazy.undo());
        whole.frame(viewer, 0.0);
        lazy.frame(viewer, 0.0);
        expectSameTiles(lazy, whole);
    }
}

TEST_F(LazyForestEditTest, AnEditOfAnElementTheFileHasNotIsRefusedAndChangesNothing) {
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    const Box e = lazy.document().scene.extent;
    lazy.frame({e.center().x, e.center().y, 100.0}, 0.0);
    const std::size_t tiles = lazy.tiles().size();
    EXPECT_THROW(lazy.execute(MoveNodeCmd{kRoadsLayer, 99999999, e.center()}), SceneFileError);
    Curve toNowhere;
    toNowhere.start = toNowhere.end = 99999999;
    toNowhere.vertices = {Vertex{e.center(), true, false}, Vertex{e.center() + Vec2(10.0, 0.0), true, false}};
    EXPECT_THROW(lazy.execute(AddCurveCmd{kRoadsLayer, toNowhere}), SceneFileError);
    EXPECT_FALSE(lazy.undo());
    EXPECT_FALSE(lazy.redo());
    EXPECT_FALSE(lazy.modified());
    EXPECT_EQ(lazy.undoDepth(), 0u);
    EXPECT_EQ(lazy.tiles().size(), tiles);
    for (const auto& [key, t] : lazy.tiles()) EXPECT_FALSE(t.dirty);
}

}  // namespace
}  // namespace lacet
