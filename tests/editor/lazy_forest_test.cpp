// A scene file read lazily (§7, issue 23; editor/lazy_forest.h): the session's tiles, wherever the
// viewer goes, are those of a session with the whole scene loaded, bit for bit; the parts' vector
// data stays within the budget (what no viewer wants goes first); a part that does not fit is
// refused and its quad drawn from the top tree, never a crash; a part read on the worker thread
// makes its quad's tile again when it arrives; edits over a pyramid read the top again only where
// it holds what changed (the other edits: lazy_forest_edit_test.cpp). The scene of
// tests/editor/lazy_forest_fixture.h.
#include "tests/editor/lazy_forest_fixture.h"

namespace lacet {
namespace {

TEST_F(LazyForestTest, TilesAreThoseOfTheWholeSceneWhereverTheViewerGoes) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0), sessionParams());
    ASSERT_NE(lazy.lazyForest(), nullptr);
    EXPECT_EQ(whole.lazyForest(), nullptr);
    std::size_t deep = 0;
    for (const glm::dvec3& v : viewers(whole.document().scene.extent, 6, 3)) {
        whole.frame(v, 0.0);
        const FrameReport r = lazy.frame(v, 0.0);
        EXPECT_EQ(r.pending, 0u);
        EXPECT_EQ(lazy.plan().items.size(), whole.plan().items.size());
        EXPECT_EQ(lazy.plan().deepest, whole.plan().deepest);
    }
    for (const auto& [key, t] : whole.tiles()) deep += std::get<0>(key) > kPartLevel;
    EXPECT_GT(deep, 50u);  // most tiles come from parts
    expectSameTiles(lazy, whole);
    const LazyStats& st = lazy.lazyForest()->stats();
    EXPECT_GT(st.partsRead, 3u);
    EXPECT_EQ(st.partsRefused, 0u);
    EXPECT_EQ(st.partsEvicted, 0u);
    // Without a pyramid the top tree reads every curve and area (the appearance of the levels down
    // to the part level needs them): the whole scene's vector data.
    const SceneDocument doc = loadScene(*path_);
    EXPECT_NEAR(st.topMiB, toMiB(memoryBytes(doc.scene)), 0.2 * toMiB(memoryBytes(doc.scene)));
}

// Hard cases of parts (issue 23), each viewed low and from a little higher by a whole and a lazy
// session: a road whose root crosses many parts, a roundabout at a node on a part's border, and a
// bridge near a part's border (its river read with the road that crosses it).
TEST_F(LazyForestTest, ARoadAcrossManyPartsARoundaboutOnABorderAndABridgeNearOneAreDrawnAsInTheWholeScene) {
    // The scene with a roundabout made at the junction nearest a border of the parts of level 3, its
    // ring across that border.
    constexpr int kLevel = 3;
    SceneDocument doc = loadScene(*path_);
    const Box e = doc.scene.extent;
    const double side = e.size().x / double(1 << kLevel);
    // Distance from p to the nearest part border inside the scene.
    const auto toBorder = [&](Vec2 p) {
        const Vec2 g = (p - e.min) / side;
        const double gx = std::round(g.x), gy = std::round(g.y);
        const bool inX = gx > 0 && gx < (1 << kLevel), inY = gy > 0 && gy < (1 << kLevel);
        return std::min(inX ? std::abs(g.x - gx) * side : 1e300, inY ? std::abs(g.y - gy) * side : 1e300);
    };
    Layer& junctions = doc.scene.layers[kRoadsLayer];
    ElementId ringNode = kNoElement;
    for (ElementId id = 0; id < junctions.nodes.size(); ++id) {
        const Node& n = junctions.nodes[id];
        if (n.alive && n.curves.size() >= 3 && n.roundabout == 0.0f &&
            (ringNode == kNoElement || toBorder(n.p) < toBorder(junctions.nodes[ringNode].p)))
            ringNode = id;
    }
    ASSERT_NE(ringNode, kNoElement);
    // A ring across the border: its radius past the junction's distance to it.
    const double across = toBorder(junctions.nodes[ringNode].p);
    ASSERT_LT(across, 60.0) << "no junction near a part border";
    junctions.nodes[ringNode].roundabout = float(std::max(20.0, across + 10.0));
    const std::string ringed = (*dir_ / "ringed.gpkg").string();
    saveScene(ringed, doc);
    EditSession whole(loadScene(ringed), sessionParams());
    const Scene& s = whole.document().scene;
    std::vector<Vec2> spots{s.layers[kRoadsLayer].nodes[ringNode].p};
    const Layer& roads = s.layers[kRoadsLayer];
    // The road whose vertices meet the most parts: along it.
    std::size_t most = 0;
    ElementId longest = kNoElement;
    for (ElementId id = 0; id < roads.curves.size(); ++id) {
        if (!roads.curves[id].alive) continue;
        std::set<std::pair<int, int>> parts;
        for (const Vertex& v : roads.curves[id].vertices)
            parts.insert({int((v.p.x - e.min.x) / side), int((v.p.y - e.min.y) / side)});
        if (parts.size() > most) most = parts.size(), longest = id;
    }
    ASSERT_GE(most, 3u) << "no road crosses three parts";
    const std::vector<Vertex>& along = roads.curves[longest].vertices;
    for (std::size_t k = 0; k < along.size(); k += std::max<std::size_t>(1, along.size() / 6)) spots.push_back(along[k].p);
    // The bridge (a procedural curve over a river) nearest a part border.
    whole.frame({e.center().x, e.center().y, 5000.0}, 0.0);
    double nearest = 1e300;
    Vec2 bridge{};
    whole.quadtree().forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;  // the root
        for (const auto& [a, pieces] : q.layers[kRoadsLayer].curves) {
            const ProceduralCurve* pc = whole.quadtree().proceduralCurve(kRoadsLayer, a);
            if (!pc || !(pc->curve.flags & kBridge) || pc->curve.vertices.empty()) continue;
            const Vec2 mid = pc->curve.vertices[pc->curve.vertices.size() / 2].p;
            if (toBorder(mid) < nearest) nearest = toBorder(mid), bridge = mid;
        }
    });
    ASSERT_LT(nearest, 1e300) << "no bridge";
    spots.push_back(bridge);
    LazyParams lp = lazyParams(1024.0);
    lp.partLevel = kLevel;
    EditSession lazy(ringed, lp, sessionParams());
    lazy.frame({e.center().x, e.center().y, 5000.0}, 0.0);  // as the whole session was
    for (const Vec2 p : spots)
        for (const double h : {15.0, 150.0}) {
            whole.frame({p.x, p.y, h}, 0.0);
            lazy.frame({p.x, p.y, h}, 0.0);
            EXPECT_EQ(lazy.plan().items.size(), whole.plan().items.size());
        }
    expectSameTiles(lazy, whole, kLevel);
    // The bridge's deck was made in the lazy session too (the objects are in the tiles compared).
    EXPECT_GT(lazy.objectCounters().bridges.load(), 0u);
    EXPECT_EQ(lazy.objectCounters().bridges.load(), whole.objectCounters().bridges.load());
}

TEST_F(LazyForestTest, UnderCachePressureAndNewRefinementTheTilesAreStillTheWholeScenes) {
    // A cache smaller than the views need: the farthest quads stand in for their children
    // (editor/cache_fit.h), a part's quad for its children through the top tree's parents.
    SessionParams params = sessionParams();
    params.cacheTiles = 60;
    EditSession whole(loadScene(*path_), params);
    EditSession lazy(*path_, lazyParams(1024.0), params);
    for (int round = 0; round < 2; ++round) {
        if (round == 1) {  // coarser textures: the top tree is read again for them
            RefineParams refine = params.refine;
            refine.resolution = 128;
            whole.setRefineParams(refine);
            lazy.setRefineParams(refine);
        }
        for (const glm::dvec3& v : viewers(whole.document().scene.extent, 4, 21 + std::uint32_t(round))) {
            const FrameReport w = whole.frame(v, 0.0);
            const FrameReport l = lazy.frame(v, 0.0);
            EXPECT_GT(w.replaced, 0u);
            EXPECT_EQ(l.replaced, w.replaced);
            EXPECT_EQ(l.shown, w.shown);
            const DrawPlan& wp = whole.plan();
            const DrawPlan& lp = lazy.plan();
            ASSERT_EQ(lp.items.size(), wp.items.size());
            for (std::size_t i = 0; i < wp.items.size(); ++i) {
                EXPECT_EQ(lp.items[i].leaf, wp.items[i].leaf);
                EXPECT_EQ(lp.items[i].tileKey, wp.items[i].tileKey);
                if (wp.items[i].tile && lp.items[i].tile && !lp.items[i].tile->dirty) {
                    EXPECT_EQ(lp.items[i].tile->texels(), wp.items[i].tile->texels());
                    EXPECT_EQ(lp.items[i].tile->elevation.zm, wp.items[i].tile->elevation.zm);
                }
            }
        }
    }
}

TEST_F(LazyForestTest, APartOfAFileChangedSinceItWasOpenedIsRefused) {
    const std::string copy = (*dir_ / "changed.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    EditSession lazy(copy, lazyParams(1024.0), sessionParams());
    SceneDocument other;
    other.scene = makeSyntheticScene({.seed = 12, .curves = 3000});
    other.dem = makeSyntheticDem(other.scene, {.seed = 12, .resolution = 1000});
    saveScene(copy, other);
    const Box e = lazy.document().scene.extent;
    const FrameReport r = lazy.frame({e.center().x, e.center().y, 50.0}, 0.0);
    EXPECT_EQ(r.pending, 0u);
    const LazyStats& st = lazy.lazyForest()->stats();
    EXPECT_EQ(st.partsRead, 0u);
    EXPECT_GT(st.partsRefused, 0u);
    EXPECT_NE(st.lastError.find("changed since it was opened"), std::string::npos) << st.lastError;
}

// A command, undo or redo whose read of the top fails (here: the file was saved over since it was
// opened) is refused by name and taken back whole: the history and the edits are as before it,
// and once the file is back the session goes on to the whole scene's tiles.
TEST_F(LazyForestTest, AStepWhoseReadOfTheTopFailsIsTakenBackWhole) {
    const std::string copy = (*dir_ / "rollback.gpkg").string();
    const std::string saved = (*dir_ / "rollback.saved.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    std::filesystem::copy_file(*path_, saved, std::filesystem::copy_options::overwrite_existing);
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(copy, lazyParams(1024.0), sessionParams());  // no pyramid: every step reads the top again
    const Scene& s = whole.document().scene;
    const Layer& roads = s.layers[kRoadsLayer];
    ElementId road = kNoElement;
    for (ElementId id = 0; id < roads.curves.size() && road == kNoElement; ++id)
        if (roads.curves[id].alive && roads.curves[id].vertices.size() > 2) road = id;
    ASSERT_NE(road, kNoElement);
    const Vec2 at = roads.curves[road].vertices[1].p;
    const auto move = [&](double dx) { return MoveVertexCmd{kRoadsLayer, road, 1, at + Vec2(dx, 0.0)}; };
    const glm::dvec3 viewer{at.x, at.y, 80.0};
    for (EditSession* e : {&whole, &lazy}) {
        e->execute(move(4.0), true);
        e->execute(move(8.0), true);  // one step: a drag
        e->frame(viewer, 0.0);
    }
    const auto overlay = lazy.lazyEdits()->overlay();
    // The file saved over since, with a field node far from the road moved: the edit's own read
    // finds what it found, the top's read finds another checksum.
    SceneDocument other = loadScene(*path_);
    Layer& fields = other.scene.layers[kFieldsLayer];
    ElementId far = kNoElement;
    for (ElementId id = 0; id < fields.nodes.size(); ++id)
        if (fields.nodes[id].alive && (far == kNoElement || glm::length(fields.nodes[id].p - at) > glm::length(fields.nodes[far].p - at))) far = id;
    ASSERT_NE(far, kNoElement);
    moveNode(other.scene, kFieldsLayer, far, fields.nodes[far].p + Vec2(1.0, 1.0));
    saveScene(copy, other);
    for (const int attempt : {0, 1, 2}) {
        SCOPED_TRACE(attempt);
        try {
            if (attempt == 0) lazy.execute(move(12.0), true);  // merged into the drag
            if (attempt == 1) lazy.undo();
            if (attempt == 2) lazy.execute(MoveVertexCmd{kRoadsLayer, road, 1, at + Vec2(0.0, 5.0)});  // a step of its own
            ADD_FAILURE() << "not refused";
        } catch (const SceneFileError& e) {
            EXPECT_NE(std::string(e.what()).find("changed since it was opened"), std::string::npos) << e.what();
        }
        EXPECT_EQ(lazy.undoDepth(), 1u);
        EXPECT_EQ(lazy.redoDepth(), 0u);
        const auto& now = lazy.lazyEdits()->overlay()->elements;
        ASSERT_EQ(now.size(), overlay->elements.size());
        for (const auto& [ref, e] : overlay->elements) {
            ASSERT_EQ(now.count(ref), 1u);
            EXPECT_TRUE(now.at(ref).value == e.value);
            EXPECT_EQ(now.at(ref).box.has_value(), e.box.has_value());
            if (e.box && now.at(ref).box) {
                EXPECT_EQ(now.at(ref).box->min, e.box->min);
                EXPECT_EQ(now.at(ref).box->max, e.box->max);
            }
        }
    }
    // The file back: the drag goes on from where it was, and undo takes all of it back.
    std::filesystem::copy_file(saved, copy + ".tmp", std::filesystem::copy_options::overwrite_existing);
    std::filesystem::rename(copy + ".tmp", copy);
    for (EditSession* e : {&whole, &lazy}) {
        e->execute(move(16.0), true);
        e->frame(viewer, 0.0);
    }
    expectSameTiles(lazy, whole);
    EXPECT_EQ(lazy.undoDepth(), 1u);
    for (EditSession* e : {&whole, &lazy}) {
        EXPECT_TRUE(e->undo());
        e->frame(viewer, 0.0);
    }
    EXPECT_TRUE(lazy.lazyEdits()->overlay()->elements.empty());
    expectSameTiles(lazy, whole);
}

TEST_F(LazyForestTest, TheBudgetDropsWhatNoViewerWantsFirstAndRefusesWhatDoesNotFit) {
    const auto [top, largest] = partSizes();
    ASSERT_GT(largest, 0.0);
    // Room for the largest part and a little more: each viewer's parts fit one by one, not all.
    const double room = 1.2 * largest;
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(top + room), sessionParams());
    for (const glm::dvec3& v : viewers(whole.document().scene.extent, 8, 5)) {
        // A viewer low over random points: the parts it wants fit one by one, not all, so those
        // of earlier viewers go, and some are refused.
        const glm::dvec3 low{v.x, v.y, 20.0};
        whole.frame(low, 0.0);
        lazy.frame(low, 0.0);
        const LazyStats& st = lazy.lazyForest()->stats();
        EXPECT_LE(st.heldMiB, room + 1e-9);
        EXPECT_LE(st.peakMiB, room + 1e-9);
    }
    const LazyStats& st = lazy.lazyForest()->stats();
    EXPECT_GT(st.partsEvicted, 0u);
    // A viewer that wants every part at once: those beyond the room are refused, and their quads
    // are drawn from the top tree (a tile for every visible leaf, no crash), the room kept.
    const Box e = whole.document().scene.extent;
    const FrameReport r = lazy.frame({e.center().x, e.center().y, 0.6 * e.size().x}, 0.0);
    EXPECT_EQ(r.pending, 0u);
    EXPECT_GT(lazy.lazyForest()->stats().partsRefused, 0u);
    EXPECT_LE(lazy.lazyForest()->stats().peakMiB, room + 1e-9);
    for (const DrawItem& item : lazy.plan().items)
        if (item.visible) {
            EXPECT_NE(item.tile, nullptr);
        }

    // A budget below the top tree's data: refused at opening, naming the file.
    try {
        EditSession tooSmall(*path_, lazyParams(0.5 * top), sessionParams());
        ADD_FAILURE() << "a budget below the top tree's vector data was accepted";
    } catch (const SceneFileError& err) {
        EXPECT_NE(std::string(err.what()).find(*path_), std::string::npos) << err.what();
    }
}

TEST_F(LazyForestTest, APartReadInTheBackgroundMakesItsQuadsTileAgainWhenItArrives) {
    EditSession whole(loadScene(*path_), sessionParams());
    EditSession lazy(*path_, lazyParams(1024.0, /*background=*/true), sessionParams());
    const Box e = whole.document().scene.extent;
    const glm::dvec3 v{e.min.x + 0.3 * e.size().x, e.min.y + 0.6 * e.size().x, 50.0};
    whole.frame(v, 0.0);
    // The first frame draws the part level's quads from the top tree; the frames after take the
    // parts as the worker gives them (no clock: a bounded number of frames, yielding between).
    FrameReport r = lazy.frame(v, 0.0);
    std::size_t arrived = r.partsArrived;
    for (int i = 0; i < 200000 && (r.refineDeferred || r.pending > 0); ++i) {
        std::this_thread::yield();
        r = lazy.frame(v, 0.0);
        arrived += r.partsArrived;
    }
    EXPECT_GT(arrived, 0u);  // tiles of the part level made from the top tree, made again
    EXPECT_FALSE(r.refineDeferred);
    EXPECT_EQ(lazy.plan().items.size(), whole.plan().items.size());
    expectSameTiles(lazy, whole);
}

// Issue 24: with background work, parts read on the worker and slow quads' tiles and
// subdivisions made on idle threads (every quad with an estimate, here), the views the frames
// complete have the whole scene's tiles; the work on a part's quads is stopped before a view that
// no longer wants the part lets it go.
TEST_F(LazyForestTest, TilesAndSubdivisionsMadeInTheBackgroundAreTheWholeScenes) {
    EditSession whole(loadScene(*path_), sessionParams());
    SessionParams params = sessionParams();
    params.backgroundMs = 1e-9;
    params.clock = steppedClockMs(0.05);
    EditSession lazy(*path_, lazyParams(1024.0, /*background=*/true), params);
    std::size_t begun = 0, subdivisions = 0;
    // Under the sanitizers, two viewers.
    for (const glm::dvec3& v : viewers(whole.document().scene.extent, test::sanitizedOr(4, 2), 9)) {
        whole.frame(v, 0.0);
        FrameReport r;
        for (int i = 0; i < 200000; ++i) {
            r = lazy.frame(v, 10.0);
            begun += r.backgroundStarted;
            subdivisions += r.backgroundSubdivisions;
            if (r.pending == 0 && !r.refineDeferred && !lazy.backgroundBusy()) break;
            lazy.waitForBackground();
            std::this_thread::yield();  // and the part reader
        }
        EXPECT_EQ(r.pending, 0u);
        EXPECT_EQ(lazy.plan().items.size(), whole.plan().items.size());
    }
    EXPECT_GT(begun, 20u);
    EXPECT_GT(subdivisions, 5u);
    expectSameTiles(lazy, whole, kPartLevel, /*anyMore=*/true);
}

TEST_F(LazyForestTest, APyramidOfTheFileGivesTheTopsAppearanceAndTheTopReadsOnlyItsElevation) {
    // Levels 0..3, L = 3: below the part level 2 and at it the appearance is the pyramid's.
    const std::string pyramid = buildTestPyramid("scene.pyramid.gpkg");
    const SceneDocument doc = loadScene(*path_);
    EditSession whole(SceneDocument(doc), sessionParams());
    whole.setPyramid(std::make_shared<PyramidReader>(pyramid, doc));
    LazyParams lp = lazyParams(1024.0);
    lp.topElevationOnly = true;
    EditSession lazy(*path_, lp, sessionParams());
    EXPECT_LT(lazy.lazyForest()->stats().topMiB, 0.5 * EditSession(*path_, lazyParams(1024.0), sessionParams()).lazyForest()->stats().topMiB);
    // The editor's link opens it for the session read lazily: its checksum is the file's stored one.
    PyramidLink link;
    link.setFiles(pyramid, *path_);
    link.sessionStarted();
    const PyramidOpened opened = link.open(lazy);
    ASSERT_TRUE(opened.levels.has_value()) << opened.error;
    EXPECT_EQ(opened.levels->vectorLevel, 3);
    for (const glm::dvec3& v : viewers(doc.scene.extent, 4, 9)) {
        whole.frame(v, 0.0);
        lazy.frame(v, 0.0);
    }
    EXPECT_GT(lazy.pyramidUse().read, 0u);
    EXPECT_EQ(lazy.pyramidUse().read, whole.pyramidUse().read);
    expectSameTiles(lazy, whole);
}

TEST_F(LazyForestTest, APartTheFileCannotGiveIsRefusedByNameAndItsQuadDrawnFromTheTop) {
    // A copy of the scene whose one field, in one quad of the part level (and maybe its
    // neighbours), has a spoilt ring blob: the top tree (elevation only) never reads fields.
    const std::string copy = (*dir_ / "spoilt.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    const SceneDocument doc = loadScene(*path_);
    const Box e = doc.scene.extent;
    const double side = e.size().x / double(1 << kPartLevel);
    const Box quad{e.min + Vec2(side, side), e.min + Vec2(2.0 * side, 2.0 * side)};  // 2/1/1
    ElementId spoilt = kNoElement;
    const Layer& fields = doc.scene.layers[kFieldsLayer];
    for (ElementId id = 0; id < fields.areas.size() && spoilt == kNoElement; ++id) {
        if (!fields.areas[id].alive) continue;
        for (const AreaEdge& edge : fields.areas[id].loops[0])
            for (const Vertex& v : fields.curves[edge.curve].vertices)
                if (quad.dilated(-0.1 * side).contains(v.p)) spoilt = id;
    }
    ASSERT_NE(spoilt, kNoElement);
    {
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(copy.c_str(), &db), SQLITE_OK);
        const std::string sql = "UPDATE lacet_areas SET loops = x'010203' WHERE layer = " + std::to_string(kFieldsLayer) +
                                " AND id = " + std::to_string(spoilt);
        EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
        sqlite3_close(db);
    }
    LazyParams lp = lazyParams(1024.0);
    lp.topElevationOnly = true;
    EditSession lazy(copy, lp, sessionParams());
    const Vec2 c = quad.center();
    const FrameReport r = lazy.frame({c.x, c.y, 50.0}, 0.0);
    EXPECT_EQ(r.pending, 0u);
    const LazyStats& st = lazy.lazyForest()->stats();
    EXPECT_GE(st.partsRefused, 1u);
    EXPECT_NE(st.lastError.find(copy), std::string::npos) << st.lastError;
    EXPECT_FALSE(lazy.lazyForest()->holds({kPartLevel, 1, 1}));
    // Drawn from the top tree: the quad is a leaf with its tile.
    const auto [q, tile] = lazy.tileAt(c);
    ASSERT_NE(q, nullptr);
    EXPECT_EQ(q->level, kPartLevel);
    EXPECT_NE(tile, nullptr);
    // The next frame does not read it again.
    const std::size_t refused = st.partsRefused;
    lazy.frame({c.x, c.y, 50.0}, 0.0);
    EXPECT_EQ(lazy.lazyForest()->stats().partsRefused, refused);
}

TEST_F(LazyForestTest, EditsOfAPartialSceneOverAPyramidReadTheTopAgainOnlyWhereItHoldsWhatChanged) {
    const std::string pyramid = buildTestPyramid("edits.pyramid.gpkg");
    const SceneDocument doc = loadScene(*path_);
    EditSession whole(SceneDocument(doc), sessionParams());
    whole.setPyramid(std::make_shared<PyramidReader>(pyramid, doc));
    LazyParams lp = lazyParams(1024.0);
    lp.topElevationOnly = true;
    EditSession lazy(*path_, lp, sessionParams());
    PyramidLink link;
    link.setFiles(pyramid, *path_);
    link.sessionStarted();
    ASSERT_TRUE(link.open(lazy).levels.has_value());
    const int edits = test::sanitizedOr(28, 9);
    expectSameEdits(checkLazyEdits(lazy, whole, {.seed = 8, .edits = edits, .appearanceFrom = 3, .topElevationOnly = true}),
                    true, std::size_t(edits));
}

}  // namespace
}  // namespace lacet
