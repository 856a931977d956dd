// Edits of a scene file read lazily (§7, issue 23; editor/lazy_forest.h, editor/lazy_edits.h):
// random edits give the whole scene's tiles and undo restores them; a long road dragged and a road
// drawn are taken by the parts in memory where nothing else would be read; an edit of an element
// the file has not is refused. The scene of tests/editor/lazy_forest_fixture.h.
#include "tests/editor/lazy_forest_fixture.h"

namespace lacet {
namespace {

class LazyForestEditTest : public LazyForestTest {};

TEST_F(LazyForestEditTest, EditsOfAPartialSceneGiveTheWholeScenesTilesAndUndoRestoresThem) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    expectSameEdits(checkLazyEdits(lazy, whole, {.seed = 5, .edits = 28}), false);
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
    for (int step = 1; step <= 4; ++step)
        for (const std::size_t i : {controls.front(), controls.back()}) {
            const Command move = MoveVertexCmd{kRoadsLayer, longest, i, along[i].p + Vec2(3.0, -2.0) * double(step)};
            whole.execute(move);
            lazy.execute(move);
            frames();
        }
    const LazyStats& after = lazy.lazyForest()->stats();
    EXPECT_GT(after.partsMoved - before.partsMoved, 8u);  // at least one part at each of the 8 steps
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
    for (int k = 0; k < 2; ++k) {  // the spur, then the road
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
