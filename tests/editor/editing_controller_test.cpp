// The editing controller in process, without a display: picking against a camera, the lock
// policy on every path a command can take, the draw tool's curve and its one undo step, drags,
// and the ground under a pixel.
#include "editor/editing_controller.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "editor/draw_curve.h"
#include "io/scene_file.h"
#include "io/scene_overlay.h"
#include "tests/io/gis_fixtures.h"
#include "model/bezier.h"
#include "model/roundabouts.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/editor/session_checks.h"

namespace lacet {
namespace {

using test::syntheticDocument;

SessionParams smallTiles() {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = 8;
    return params;
}

// A session, its controller, and a camera looking down steeply at the scene's centre.
struct Fixture {
    std::unique_ptr<EditSession> owned;
    EditSession& session;
    EditingController controller;
    std::vector<std::string> messages;

    Fixture() : Fixture(std::make_unique<EditSession>(syntheticDocument(7, 3000), smallTiles())) {}
    // `target`: the roads to look at (default: the session's document's).
    explicit Fixture(std::unique_ptr<EditSession> s, const Layer* target = nullptr) : owned(std::move(s)), session(*owned), controller(session) {
        controller.onMessage = [this](const std::string& m) { messages.push_back(m); };
        // Looking at the middle of the road with the most vertices, from 1500 m.
        const Layer& l = target ? *target : roads();
        const Curve* road = &l.curves.front();
        for (const Curve& c : l.curves)
            if (c.alive && c.vertices.size() > road->vertices.size()) road = &c;
        const Vec2 at = road->vertices[road->vertices.size() / 2].p;
        PickView v;
        v.camera.target = glm::dvec3(at.x, at.y, session.document().dem->sample(at));
        v.camera.distance = 1500.0;
        v.camera.pitch = 1.35;
        v.width = 1000, v.height = 800;
        const glm::dvec3 eye = v.camera.position();
        v.clip = Camera::clipRange(eye.z - session.document().dem->sample({eye.x, eye.y}));
        session.frame({eye.x, eye.y, eye.z - session.document().dem->sample({eye.x, eye.y})}, 0.0);
        controller.setView(v);
        controller.setCurrentLayer(kRoadsLayer);
        controller.buildOverlay();
    }
    const Layer& roads() const { return session.document().scene.layers[kRoadsLayer]; }
    // A pickable point of the overlay with no other pickable point within 3 pick radii.
    OverlayPoint isolated(Pick::Kind kind) const {
        const std::vector<OverlayPoint>& pts = controller.overlay().points;
        for (const OverlayPoint& p : pts) {
            if (p.pick.kind != kind) continue;
            bool alone = true;
            for (const OverlayPoint& q : pts) {
                // A node is listed once per curve end it holds: those are the same point.
                const bool same = q.pick.kind == p.pick.kind && q.pick.id == p.pick.id && q.pick.index == p.pick.index;
                if (!same && q.pick.kind != Pick::Kind::None && glm::length(q.pixel - p.pixel) < 3.0 * kPickPixels) alone = false;
            }
            if (alone && p.pixel.x > 50 && p.pixel.y > 50 && p.pixel.x < 950 && p.pixel.y < 750) return p;
        }
        throw std::runtime_error("no isolated point of that kind in view among " + std::to_string(pts.size()));
    }
};

TEST(EditingController, PicksThePointUnderThePixelAndTheCurveUnderItsPolygon) {
    Fixture f;
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    // The overlay's point is the vertex on the displayed ground (lifted a little above it), and its
    // pixel the camera's projection of it.
    EXPECT_EQ(Vec2(v.world), f.roads().curves[v.pick.id].vertices[v.pick.index].p);
    EXPECT_NEAR(v.world.z, f.controller.groundPoint(Vec2(v.world)).z, 1.0);
    const auto px = f.controller.project(v.world);
    ASSERT_TRUE(px);
    EXPECT_LT(glm::length(*px - v.pixel), 1e-9);
    for (const glm::dvec2 off : {glm::dvec2(0.0), glm::dvec2(6.0, 0.0), glm::dvec2(0.0, -7.0)}) {
        const Pick p = f.controller.pick(v.pixel + off, false);
        EXPECT_EQ(p.kind, Pick::Kind::Vertex);
        EXPECT_EQ(p.id, v.pick.id);
        EXPECT_EQ(p.index, v.pick.index);
        EXPECT_NEAR(p.pixels, glm::length(off), 1e-9);
    }
    // Beyond the pick radius from every point and polygon: nothing.
    EXPECT_EQ(f.controller.pick(v.pixel + glm::dvec2(3.0 * kPickPixels, 0.0), true).kind, Pick::Kind::None);
    const OverlayPoint n = f.isolated(Pick::Kind::Node);
    EXPECT_EQ(f.controller.pick(n.pixel, true).kind, Pick::Kind::Node);
    EXPECT_EQ(f.controller.pick(n.pixel, true).id, n.pick.id);
    // The middle of a control polygon segment of the vertex's curve picks the curve (not a point).
    const Curve& c = f.roads().curves[v.pick.id];
    const auto a = f.controller.project(f.controller.groundPoint(c.vertices[v.pick.index].p));
    const auto b = f.controller.project(f.controller.groundPoint(c.vertices[v.pick.index + 1].p));
    ASSERT_TRUE(a && b);
    if (glm::length(*b - *a) > 4.0 * kPickPixels) {
        const Pick p = f.controller.pick(0.5 * (*a + *b), false);
        EXPECT_EQ(p.kind, Pick::Kind::Curve);
        EXPECT_EQ(p.id, v.pick.id);
        EXPECT_EQ(f.controller.pick(0.5 * (*a + *b), true).kind, Pick::Kind::None);
    }
    // Another layer's points are drawn but not picked: the current layer decides.
    f.controller.setCurrentLayer(kRiversLayer);
    f.controller.buildOverlay();
    bool drawn = false;
    for (const OverlayPoint& p : f.controller.overlay().points)
        if (Vec2(p.world) == Vec2(v.world) && p.style == v.style) {
            drawn = true;
            EXPECT_FALSE(p.current);
            EXPECT_EQ(p.pick.kind, Pick::Kind::None);
        }
    EXPECT_TRUE(drawn);
    const Pick other = f.controller.pick(v.pixel, false);
    EXPECT_FALSE(other.kind == Pick::Kind::Vertex && other.layer == kRoadsLayer);
}

TEST(EditingController, TheGroundUnderAPixelProjectsBackToItOnTheDisplayedSurface) {
    Fixture f;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> x(0.0, 1000.0), y(300.0, 800.0);
    int found = 0;
    for (int i = 0; i < 40; ++i) {
        const glm::dvec2 pixel(x(rng), y(rng));
        const auto g = groundAlongRay(f.session, f.controller.view(), pixel);
        if (!g) continue;
        ++found;
        EXPECT_NEAR(g->z, f.session.displayedHeight({g->x, g->y}), 0.01);
        const auto back = f.controller.project(*g);
        ASSERT_TRUE(back);
        EXPECT_LT(glm::length(*back - pixel), 0.01);
    }
    EXPECT_GT(found, 30);
    // Straight up from under the horizon there is sky.
    PickView up = f.controller.view();
    up.camera.pitch = -0.5;
    EXPECT_FALSE(groundAlongRay(f.session, up, {500.0, 10.0}));
}

TEST(EditingController, ALockedLayerRefusesEveryEditButNotTheHistory) {
    Fixture f;
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    const Vec2 before = f.roads().curves[v.pick.id].vertices[v.pick.index].p;
    // An edit made before the lock can still be undone.
    ASSERT_TRUE(f.controller.execute(MoveVertexCmd{kRoadsLayer, v.pick.id, v.pick.index, before + Vec2(5.0, 0.0)}));
    f.controller.setLayerLocked(kRoadsLayer, true);
    const std::size_t depth = f.session.undoDepth();
    // A command (a panel's, a script's) is refused with a message, and changes nothing.
    EXPECT_FALSE(f.controller.execute(MoveVertexCmd{kRoadsLayer, v.pick.id, v.pick.index, before + Vec2(9.0, 0.0)}));
    ASSERT_FALSE(f.messages.empty());
    EXPECT_EQ(f.messages.back(), "Refused: the layer is locked");
    EXPECT_EQ(f.roads().curves[v.pick.id].vertices[v.pick.index].p, before + Vec2(5.0, 0.0));
    EXPECT_EQ(f.session.undoDepth(), depth);
    // Pointer tools: nothing can be picked, dragged, inserted or deleted; nothing is drawn.
    EXPECT_EQ(f.controller.pick(v.pixel, false).kind, Pick::Kind::None);
    EXPECT_FALSE(f.controller.press(v.pixel));
    EXPECT_FALSE(f.controller.dragging());
    f.controller.setTool(Tool::DeletePoint);
    f.controller.press(v.pixel);
    f.controller.setTool(Tool::Draw);
    f.controller.press({400.0, 500.0});
    f.controller.press({600.0, 500.0});
    EXPECT_TRUE(f.controller.drawing().empty());
    EXPECT_FALSE(f.controller.finishDrawing());
    f.controller.setTool(Tool::Select);
    EXPECT_FALSE(f.controller.deleteSelection());
    EXPECT_EQ(f.session.undoDepth(), depth);
    // Other layers stay editable.
    const Layer& rivers = f.session.document().scene.layers[kRiversLayer];
    ElementId river = 0;
    while (!rivers.curves[river].alive) ++river;
    EXPECT_TRUE(f.controller.execute(SetCurveWidthCmd{kRiversLayer, river, 3.0f, 9.0f}));
    f.controller.undo();
    // The history walks through the lock.
    EXPECT_TRUE(f.controller.undo());
    EXPECT_EQ(f.roads().curves[v.pick.id].vertices[v.pick.index].p, before);
    f.controller.setLayerLocked(kRoadsLayer, false);
    EXPECT_TRUE(f.controller.execute(MoveVertexCmd{kRoadsLayer, v.pick.id, v.pick.index, before + Vec2(9.0, 0.0)}));
}

TEST(EditingController, TheSelectedCurvesPropertiesAreOneUndoableCommandEach) {
    Fixture f;
    EXPECT_EQ(f.controller.selectedCurve(), nullptr);
    EXPECT_FALSE(f.controller.setSelectedWidth(4.0f)) << "nothing selected";
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    ASSERT_TRUE(f.controller.press(v.pixel));
    f.controller.release();
    const Curve* c = f.controller.selectedCurve();
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c, &f.roads().curves[v.pick.id]);
    const Curve before = *c;
    const std::size_t depth = f.session.undoDepth();
    // A width wider than the footprint takes the footprint with it; a narrower one leaves it.
    ASSERT_TRUE(f.controller.setSelectedWidth(before.wf + 4.0f));
    EXPECT_EQ(c->w, before.wf + 4.0f);
    EXPECT_EQ(c->wf, before.wf + 4.0f);
    ASSERT_TRUE(f.controller.setSelectedWidth(2.0f));
    EXPECT_EQ(c->w, 2.0f);
    EXPECT_EQ(c->wf, before.wf + 4.0f);
    // The footprint as given; one narrower than the width is refused by the command.
    ASSERT_TRUE(f.controller.setSelectedFootprint(30.0f));
    EXPECT_EQ(c->wf, 30.0f);
    EXPECT_FALSE(f.controller.setSelectedFootprint(1.0f));
    EXPECT_EQ(c->wf, 30.0f);
    // The class is clamped to 16 bits.
    ASSERT_TRUE(f.controller.setSelectedClass(70000));
    EXPECT_EQ(c->cls, 65535);
    ASSERT_TRUE(f.controller.setSelectedClass(-3));
    EXPECT_EQ(c->cls, 0);
    // A flag is set and cleared alone; a bridge flag makes the graph step bridge the curve.
    ASSERT_TRUE(f.controller.setSelectedFlag(kNoBridge, true));
    ASSERT_TRUE(f.controller.setSelectedFlag(kBridge, true));
    EXPECT_EQ(c->flags, before.flags | kNoBridge | kBridge);
    EXPECT_GT(f.controller.selectedBridges(), 0u);
    ASSERT_TRUE(f.controller.setSelectedFlag(kNoBridge, false));
    EXPECT_EQ(c->flags, before.flags | kBridge);
    EXPECT_EQ(f.session.undoDepth(), depth + 8);
    // A locked layer refuses each of them.
    f.controller.setLayerLocked(kRoadsLayer, true);
    EXPECT_FALSE(f.controller.setSelectedWidth(6.0f));
    EXPECT_FALSE(f.controller.setSelectedFlag(kTunnel, true));
    EXPECT_EQ(f.session.undoDepth(), depth + 8);
    f.controller.setLayerLocked(kRoadsLayer, false);
    // Undone one by one, the curve is as it was (undo clears the selection, not the curve).
    for (int i = 0; i < 8; ++i) ASSERT_TRUE(f.session.undo());
    const Curve& after = f.roads().curves[v.pick.id];
    EXPECT_EQ(after.w, before.w);
    EXPECT_EQ(after.wf, before.wf);
    EXPECT_EQ(after.cls, before.cls);
    EXPECT_EQ(after.flags, before.flags);
}

TEST(EditingController, ADragMovesThePointOntoTheGroundAsOneUndoStep) {
    Fixture f;
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    const Vec2 before = f.roads().curves[v.pick.id].vertices[v.pick.index].p;
    const std::size_t depth = f.session.undoDepth();
    ASSERT_TRUE(f.controller.press(v.pixel));
    ASSERT_TRUE(f.controller.dragging());
    EXPECT_EQ(f.controller.selection().kind, Pick::Kind::Curve);
    EXPECT_EQ(f.controller.selection().id, v.pick.id);
    glm::dvec2 last{};
    for (int i = 1; i <= 5; ++i) f.controller.drag(last = v.pixel + glm::dvec2(4.0 * i, 2.0 * i));
    f.controller.release();
    const auto ground = f.controller.groundAt(last);
    ASSERT_TRUE(ground);
    EXPECT_EQ(f.roads().curves[v.pick.id].vertices[v.pick.index].p, Vec2(ground->x, ground->y));
    EXPECT_EQ(f.session.undoDepth(), depth + 1);
    ASSERT_TRUE(f.controller.undo());
    EXPECT_EQ(f.roads().curves[v.pick.id].vertices[v.pick.index].p, before);
    // A press on the ground selects nothing and is left to the window (a pan).
    EXPECT_FALSE(f.controller.press(v.pixel + glm::dvec2(3.0 * kPickPixels, 3.0 * kPickPixels)));
    EXPECT_EQ(f.controller.selection().kind, Pick::Kind::None);
}

// A scene file read lazily (a vector budget; editor/lazy_forest.h) whose top holds only what
// elevation needs: the overlay shows the curves of the parts held too, by their ids in the file;
// a drag of one of them is a command in the file's ids, saved into the file in place.
TEST(EditingController, OnASceneReadLazilyTheCurvesOfThePartsAreEditedByTheirFileIdsAndSaved) {
    const std::filesystem::path dir = test::scratchDir("controller_lazy");
    const std::string path = (dir / "scene.gpkg").string();
    const SceneDocument whole = syntheticDocument(7, 3000);
    saveScene(path, whole);
    LazyParams lazy;
    lazy.partLevel = 2;
    lazy.vectorBudgetMiB = 1024.0;
    lazy.background = false;
    lazy.topElevationOnly = true;
    Fixture f(std::make_unique<EditSession>(path, lazy, smallTiles()), &whole.scene.layers[kRoadsLayer]);
    ASSERT_NE(f.session.lazyForest(), nullptr);
    ASSERT_GT(f.session.lazyForest()->stats().partsRead, 0u);
    // Some curves shown are held by a part only, not by the top document.
    const Layer& top = f.session.document().scene.layers[kRoadsLayer];
    std::size_t partsOnly = 0;
    for (const ElementId id : f.controller.overlay().curves) partsOnly += localIdOf(top, ElementKind::Curve, id) == kNoElement;
    EXPECT_GT(partsOnly, 0u);
    // Each point shown is where the file's element of its id has it.
    const Layer& file = whole.scene.layers[kRoadsLayer];
    for (const OverlayPoint& p : f.controller.overlay().points) {
        if (p.pick.kind == Pick::Kind::Vertex) {
            EXPECT_EQ(Vec2(p.world.x, p.world.y), file.curves[p.pick.id].vertices[p.pick.index].p);
        }
        if (p.pick.kind == Pick::Kind::Node) {
            EXPECT_EQ(Vec2(p.world.x, p.world.y), file.nodes[p.pick.id].p);
        }
    }
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    ASSERT_TRUE(f.controller.press(v.pixel));
    EXPECT_EQ(f.controller.selection().id, v.pick.id);
    ASSERT_NE(f.controller.selectedCurve(), nullptr);
    for (int i = 1; i <= 4; ++i) f.controller.drag(v.pixel + glm::dvec2(5.0 * i, 3.0 * i));
    f.controller.release();
    EXPECT_TRUE(f.messages.empty()) << f.messages.front();
    ASSERT_TRUE(f.session.modified());
    EXPECT_EQ(f.session.undoDepth(), 1u);
    const OverlayElement* moved = f.session.lazyEdits()->overlay()->find({kRoadsLayer, ElementKind::Curve, v.pick.id});
    ASSERT_NE(moved, nullptr);
    const Curve now = std::get<Curve>(moved->value);
    EXPECT_NE(now.vertices[v.pick.index].p, file.curves[v.pick.id].vertices[v.pick.index].p);
    // The panel's width goes through the same ids.
    ASSERT_TRUE(f.controller.setSelectedWidth(now.w + 1.0f));
    // A new curve drawn from a node shown to a new node: the file's next ids (those of the whole
    // scene's slots), its node and curve undone together.
    f.controller.buildOverlay();
    const OverlayPoint from = f.isolated(Pick::Kind::Node);
    f.controller.setTool(Tool::Draw);
    f.controller.newCurve = {6.0f, 14.0f, 2};
    f.controller.press(from.pixel);
    f.controller.press(from.pixel + glm::dvec2(70.0, 30.0));
    f.controller.press(from.pixel + glm::dvec2(140.0, 15.0));
    ASSERT_TRUE(f.controller.finishDrawing()) << (f.messages.empty() ? "" : f.messages.back());
    EXPECT_EQ(f.session.undoDepth(), 4u);  // the drag, the width, the node, the curve
    const ElementId drawn = ElementId(file.curves.size()), drawnEnd = ElementId(file.nodes.size());
    EXPECT_EQ(f.controller.selection().id, drawn);
    ASSERT_NE(f.controller.selectedCurve(), nullptr);  // held, by its file id
    EXPECT_EQ(f.session.nextId(kRoadsLayer, ElementKind::Curve), drawn + 1);
    ASSERT_TRUE(f.controller.undo());
    EXPECT_EQ(f.session.undoDepth(), 2u);
    EXPECT_EQ(f.session.nextId(kRoadsLayer, ElementKind::Curve), drawn);
    EXPECT_EQ(f.session.nextId(kRoadsLayer, ElementKind::Node), drawnEnd);
    ASSERT_TRUE(f.controller.redo());
    EXPECT_EQ(f.session.undoDepth(), 4u);
    // Saved into the file in place: it holds the drag, the width and the curve drawn, and nothing
    // else changed.
    f.session.saveEdits();
    EXPECT_FALSE(f.session.modified());
    const SceneDocument saved = loadScene(path);
    const Curve& c = saved.scene.layers[kRoadsLayer].curves[v.pick.id];
    EXPECT_EQ(c.vertices, now.vertices);
    EXPECT_EQ(c.w, now.w + 1.0f);
    const Layer& roads = saved.scene.layers[kRoadsLayer];
    ASSERT_EQ(roads.curves.size(), file.curves.size() + 1);
    ASSERT_EQ(roads.nodes.size(), file.nodes.size() + 1);
    EXPECT_EQ(roads.curves[drawn].start, from.pick.id);
    EXPECT_EQ(roads.curves[drawn].end, drawnEnd);
    EXPECT_EQ(roads.curves[drawn].w, 6.0f);
    EXPECT_EQ(roads.nodes[drawnEnd].curves, std::vector<ElementId>{drawn});
    std::size_t changed = 0;
    for (std::size_t l = 0; l < whole.scene.layers.size(); ++l)
        for (std::size_t k = 0; k < whole.scene.layers[l].curves.size(); ++k) {
            const Curve& a = whole.scene.layers[l].curves[k];
            const Curve& b = saved.scene.layers[l].curves[k];
            changed += a.vertices != b.vertices || a.w != b.w || a.wf != b.wf;
        }
    EXPECT_EQ(changed, 1u);
    std::filesystem::remove_all(dir);
}

TEST(EditingController, TheDrawToolMakesOneCurveThroughTheClicksJoiningASnappedNode) {
    Fixture f;
    const OverlayPoint n = f.isolated(Pick::Kind::Node);
    const std::size_t degree = f.roads().nodes[n.pick.id].curves.size();
    const std::size_t nodes = f.roads().nodes.size(), curves = f.roads().curves.size(), depth = f.session.undoDepth();
    f.controller.setTool(Tool::Draw);
    f.controller.newCurve = {5.0f, 12.0f, 3};
    // From the node, then two clicks on the ground beside it.
    const std::vector<glm::dvec2> clicks = {n.pixel, n.pixel + glm::dvec2(60.0, 25.0), n.pixel + glm::dvec2(130.0, 10.0)};
    for (const glm::dvec2 c : clicks) f.controller.press(c);
    ASSERT_EQ(f.controller.drawing().size(), 3u);
    EXPECT_EQ(f.controller.drawing()[0], f.roads().nodes[n.pick.id].p);
    ASSERT_TRUE(f.controller.finishDrawing());
    EXPECT_TRUE(f.controller.drawing().empty());
    ASSERT_EQ(f.roads().curves.size(), curves + 1);
    EXPECT_EQ(f.roads().nodes.size(), nodes + 1);  // one new node: the far end
    const Curve& c = f.roads().curves.back();
    EXPECT_EQ(c.start, n.pick.id);
    EXPECT_EQ(f.roads().nodes[n.pick.id].curves.size(), degree + 1);
    EXPECT_EQ(c.vertices.size(), 7u);
    EXPECT_EQ(c.w, 5.0f);
    EXPECT_EQ(c.wf, 12.0f);
    EXPECT_EQ(c.cls, 3);
    for (std::size_t k = 1; k < 3; ++k) {
        const auto g = f.controller.groundAt(clicks[k]);
        ASSERT_TRUE(g);
        EXPECT_EQ(c.vertices[3 * k].p, Vec2(g->x, g->y));
    }
    EXPECT_EQ(f.controller.selection().kind, Pick::Kind::Curve);
    EXPECT_EQ(f.controller.selection().id, ElementId(curves));
    // One undo step takes back the curve and the node made for it (two commands, one group).
    EXPECT_EQ(f.session.undoDepth(), depth + 2);
    ASSERT_TRUE(f.controller.undo());
    EXPECT_EQ(f.session.undoDepth(), depth);
    EXPECT_EQ(f.roads().curves.size(), curves);
    EXPECT_EQ(f.roads().nodes.size(), nodes);
    EXPECT_EQ(f.roads().nodes[n.pick.id].curves.size(), degree);
    // One click is no curve; Escape drops the points.
    f.controller.press(clicks[1]);
    EXPECT_FALSE(f.controller.finishDrawing());
    f.controller.press(clicks[1]);
    f.controller.press(clicks[2]);
    f.controller.cancel();
    EXPECT_TRUE(f.controller.drawing().empty());
}

TEST(EditingController, InsertAndDeletePointToolsEditThePickedCurve) {
    Fixture f;
    const OverlayPoint v = f.isolated(Pick::Kind::Vertex);
    const Curve before = f.roads().curves[v.pick.id];
    // Insert: a click on the control polygon, away from its points, adds an on-curve vertex there,
    // before the end of the nearest segment.
    const Curve& c = f.roads().curves[v.pick.id];
    const auto a = f.controller.project(f.controller.groundPoint(c.vertices[v.pick.index].p));
    const auto b = f.controller.project(f.controller.groundPoint(c.vertices[v.pick.index + 1].p));
    ASSERT_TRUE(a && b);
    ASSERT_GT(glm::length(*b - *a), 4.0 * kPickPixels) << "the segment is too short on screen to click between its points";
    const glm::dvec2 mid = 0.5 * (*a + *b);
    f.controller.setTool(Tool::Insert);
    ASSERT_TRUE(f.controller.press(mid));
    const Curve& inserted = f.roads().curves[v.pick.id];
    ASSERT_EQ(inserted.vertices.size(), before.vertices.size() + 1);
    const auto g = f.controller.groundAt(mid);
    ASSERT_TRUE(g);
    EXPECT_EQ(inserted.vertices[v.pick.index + 1].p, Vec2(g->x, g->y));
    EXPECT_TRUE(inserted.vertices[v.pick.index + 1].onCurve);
    EXPECT_EQ(f.controller.selection().id, v.pick.id);
    ASSERT_TRUE(f.controller.undo());
    // A click on the ground with the insert tool inserts nothing, and says so.
    f.controller.press(mid + glm::dvec2(3.0 * kPickPixels, 3.0 * kPickPixels));
    EXPECT_EQ(f.roads().curves[v.pick.id].vertices.size(), before.vertices.size());
    EXPECT_EQ(f.messages.back(), "Insert: click on a curve of the current layer");
    // Delete point: the picked inner vertex goes (or the edit is refused, with a message, when the
    // curve cannot lose it); nothing else changes.
    f.controller.buildOverlay();
    f.controller.setTool(Tool::DeletePoint);
    const std::size_t messages = f.messages.size();
    f.controller.press(v.pixel);
    const Curve& after = f.roads().curves[v.pick.id];
    if (after.vertices.size() == before.vertices.size()) {
        ASSERT_GT(f.messages.size(), messages);
        EXPECT_EQ(f.messages.back().rfind("Refused: ", 0), 0u);
    } else {
        ASSERT_LT(after.vertices.size(), before.vertices.size());
        for (const Vertex& w : after.vertices) EXPECT_NE(w.p, before.vertices[v.pick.index].p);
        ASSERT_TRUE(f.controller.undo());
        EXPECT_EQ(f.roads().curves[v.pick.id].vertices.size(), before.vertices.size());
    }
}

TEST(EditingController, ARefusedDrawnCurveTakesBackItsNodesForGood) {
    Fixture f;
    const std::size_t nodes = f.roads().nodes.size(), curves = f.roads().curves.size(), depth = f.session.undoDepth();
    f.controller.setTool(Tool::Draw);
    // A negative width, which the model refuses (after the nodes of the curve's ends were made).
    f.controller.newCurve.width = -1.0f;
    f.controller.press({450.0, 500.0});
    f.controller.press({550.0, 520.0});
    ASSERT_EQ(f.controller.drawing().size(), 2u);
    EXPECT_FALSE(f.controller.finishDrawing());
    ASSERT_FALSE(f.messages.empty());
    EXPECT_EQ(f.messages.back().rfind("Refused: ", 0), 0u) << f.messages.back();
    EXPECT_EQ(f.roads().curves.size(), curves);
    EXPECT_EQ(f.roads().nodes.size(), nodes);
    EXPECT_EQ(f.session.undoDepth(), depth);
    EXPECT_EQ(f.session.redoDepth(), 0u);  // redo cannot bring the orphan nodes back
    EXPECT_FALSE(f.controller.redo());
}

TEST(DrawCurve, PassesThroughEveryPointWithAContinuousTangent) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-500.0, 500.0);
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<Vec2> p;
        const int n = 2 + trial % 6;
        for (int i = 0; i < n; ++i) p.push_back(Vec2(u(rng), u(rng)) + Vec2(1e6, -2e6));
        const Curve c = curveThrough(p, {4.0f, 2.0f, 70000});
        ASSERT_EQ(c.vertices.size(), std::size_t(3 * (n - 1) + 1));
        EXPECT_EQ(c.w, 4.0f);
        EXPECT_EQ(c.wf, 4.0f);  // a footprint narrower than the road is raised to it
        EXPECT_EQ(c.cls, 65535);
        for (int i = 0; i < n; ++i) {
            EXPECT_EQ(c.vertices[std::size_t(3 * i)].p, p[std::size_t(i)]);
            EXPECT_TRUE(c.vertices[std::size_t(3 * i)].onCurve);
        }
        // At an inner point, the incoming and outgoing control points are on one line through it
        // (G1) and as far (C1: Catmull-Rom's tangent is the chord of the neighbours over 6).
        for (int i = 1; i + 1 < n; ++i) {
            const Vec2 in = c.vertices[std::size_t(3 * i)].p - c.vertices[std::size_t(3 * i - 1)].p;
            const Vec2 out = c.vertices[std::size_t(3 * i + 1)].p - c.vertices[std::size_t(3 * i)].p;
            EXPECT_LT(glm::length(in - out), 1e-9 * 1e6);
            EXPECT_NEAR(glm::length(in), glm::length(p[std::size_t(i + 1)] - p[std::size_t(i - 1)]) / 6.0, 1e-6);
        }
    }
    const std::vector<Vec2> one = {Vec2(1.0, 2.0)};
    EXPECT_THROW(curveThrough(one, {}), std::invalid_argument);
}

TEST(EditingController, TheRoundaboutToolMakesRefusesAndUndoesARing) {
    Fixture f;
    const OverlayPoint n = f.isolated(Pick::Kind::Node);
    const ElementId node = n.pick.id;
    const std::size_t depth = f.session.undoDepth();
    f.controller.setTool(Tool::Roundabout);
    // On the ground: nothing to make a ring of.
    f.controller.press(n.pixel + glm::dvec2(3.0 * kPickPixels, 3.0 * kPickPixels));
    ASSERT_FALSE(f.messages.empty());
    EXPECT_EQ(f.messages.back(), "Roundabout: click on a junction node of the current layer");
    // An absurd radius is refused with the reason, as the controller reports refusals.
    f.controller.roundaboutRadius = 1.0e4f;
    EXPECT_TRUE(f.controller.press(n.pixel));
    ASSERT_FALSE(f.messages.empty());
    EXPECT_EQ(f.messages.back().rfind("Refused: ", 0), 0u) << f.messages.back();
    EXPECT_NE(f.messages.back().find("larger than the largest allowed"), std::string::npos) << f.messages.back();
    EXPECT_EQ(f.roads().nodes[node].roundabout, 0.0f);
    EXPECT_EQ(f.session.undoDepth(), depth);
    // The largest of a few radii that fits at this node.
    float radius = 0.0f;
    for (float r : {20.0f, 12.0f, 8.0f, 5.0f, 3.0f})
        if (!roundaboutRefusal(f.session.document().scene, kRoadsLayer, node, r)) {
            radius = r;
            break;
        }
    ASSERT_GT(radius, 0.0f) << "no radius fits at node " << node;
    f.controller.roundaboutRadius = radius;
    ASSERT_TRUE(f.controller.press(n.pixel));
    EXPECT_EQ(f.roads().nodes[node].roundabout, radius);
    EXPECT_EQ(f.session.undoDepth(), depth + 1);
    EXPECT_GT(f.controller.lastCommand().changedQuads, 0u);
    // Exact undo and redo.
    ASSERT_TRUE(f.controller.undo());
    EXPECT_EQ(f.roads().nodes[node].roundabout, 0.0f);
    ASSERT_TRUE(f.controller.redo());
    EXPECT_EQ(f.roads().nodes[node].roundabout, radius);
    // Locked: refused, whether by the tool or the action.
    f.controller.setLayerLocked(kRoadsLayer, true);
    EXPECT_FALSE(f.controller.setRoundabout(node, 0.0f));
    EXPECT_EQ(f.messages.back(), "Refused: the layer is locked");
    EXPECT_EQ(f.roads().nodes[node].roundabout, radius);
    f.controller.setLayerLocked(kRoadsLayer, false);
    EXPECT_TRUE(f.controller.setRoundabout(node, 0.0f));
    EXPECT_EQ(f.roads().nodes[node].roundabout, 0.0f);
}

}  // namespace
}  // namespace lacet
