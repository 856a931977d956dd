#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/validate.h"
#include "tests/model/small_scene.h"

namespace lacet {
namespace {

using test::smallScene;

TEST(Validate, AcceptsAWellFormedScene) { EXPECT_TRUE(validate(smallScene()).empty()); }

TEST(Validate, RejectsNaNAndInfinity) {
    Scene s = smallScene();
    s.layers[0].curves[0].vertices[1].p.x = std::numeric_limits<double>::quiet_NaN();
    s.layers[1].nodes[2].p.y = std::numeric_limits<double>::infinity();
    const auto problems = validate(s);
    ASSERT_GE(problems.size(), 2u);
    EXPECT_EQ(problems[0].where, "layer 'roads' curve 0");
    EXPECT_EQ(problems[0].reason, "vertex 1 has a non-finite or out-of-range coordinate");
    EXPECT_THROW(validateOrThrow(s), ValidationError);
}

TEST(Validate, RejectsDanglingReferencesAndOpenLoops) {
    Scene s = smallScene();
    s.layers[0].curves[0].end = 77;
    s.layers[1].areas[0].loops[0].pop_back();  // opens the loop
    const auto problems = validate(s);
    bool dangling = false, open = false;
    for (const auto& p : problems) {
        dangling |= p.where == "layer 'roads' curve 0" && p.reason == "start or end node is missing or deleted";
        open |= p.where == "layer 'fields' area 0" && p.reason.find("is open") != std::string::npos;
    }
    EXPECT_TRUE(dangling);
    EXPECT_TRUE(open);
}

TEST(Validate, RejectsAdjacencyThatDisagreesWithTheGraphAndANonSquareExtent) {
    Scene s = smallScene();
    s.layers[0].nodes[0].curves.clear();      // the road still starts there
    s.layers[1].curves[6].areas = {0};        // the shared border is used by areas 0 and 1
    s.extent.max.x = 2000;
    const auto problems = validate(s);
    ASSERT_EQ(problems.size(), 3u);
    EXPECT_EQ(problems[0].where, "scene");
    EXPECT_EQ(problems[1].where, "layer 'roads' node 0");
    EXPECT_EQ(problems[1].reason, "its list of curves differs from the curves that end there");
    EXPECT_EQ(problems[2].where, "layer 'fields' curve 6");
}

TEST(Validate, RejectsAbsurdCoordinates) {
    Scene s = smallScene();
    s.layers[0].nodes[1].p.x = 1e200;
    s.layers[0].curves[0].vertices.back().p.x = 1e200;
    EXPECT_FALSE(validate(s).empty());
}

TEST(Validate, RejectsMalformedSplinesAndWidths) {
    Scene s = smallScene();
    auto& v = s.layers[0].curves[0].vertices;
    v.insert(v.begin() + 1, Vertex{{150, 150}, false});  // three controls in a row
    s.layers[1].curves[0].w = 5;                         // w > wf
    const auto problems = validate(s);
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_EQ(problems[0].reason, "more than 2 control points in a row at vertex 3");
    EXPECT_NE(problems[1].reason.find("0 <= w <= wf"), std::string::npos);
}

TEST(Edits, MoveVertexReportsTheCurveAndItsAreas) {
    Scene s = smallScene();
    const auto cs = moveVertex(s, 0, 0, 1, {310, 410});
    EXPECT_EQ(cs.removed, cs.added);
    ASSERT_EQ(cs.added.size(), 1u);
    EXPECT_EQ(cs.added[0], (ElementRef{0, ElementKind::Curve, 0}));
    // The shared border: both fields change.
    const auto ns = moveNode(s, 1, 1, {410, 490});
    EXPECT_EQ(std::count_if(ns.added.begin(), ns.added.end(), [](const ElementRef& r) { return r.kind == ElementKind::Area; }), 2);
    EXPECT_EQ(s.layers[1].curves[0].vertices.back().p, Vec2(410, 490));
    EXPECT_EQ(s.layers[1].curves[6].vertices.front().p, Vec2(410, 490));
    EXPECT_TRUE(validate(s).empty());
}

TEST(Edits, BadArgumentsThrowAndLeaveTheSceneUntouched) {
    Scene s = smallScene();
    const auto before = s.layers[0].curves[0].vertices;
    EXPECT_THROW(moveVertex(s, 0, 0, 1, {std::nan(""), 0}), EditError);
    EXPECT_THROW(moveVertex(s, 0, 0, 0, {1, 1}), EditError);  // an end vertex belongs to its node
    EXPECT_THROW(insertVertex(s, 0, 0, 2, Vertex{{5, 5}, false}), EditError);  // 3 controls in a row
    EXPECT_THROW(deleteCurve(s, 1, 6), EditError);                              // used by areas
    EXPECT_THROW(deleteNode(s, 0, 0), EditError);                               // has curves
    EXPECT_THROW(setCurveWidth(s, 0, 0, 10, 5), EditError);
    EXPECT_THROW(moveNode(s, 0, 99, {0, 0}), EditError);
    try {
        moveVertex(s, 0, 0, 1, {std::nan(""), 0});
    } catch (const EditError& e) {
        EXPECT_STREQ(e.what(), "layer 'roads' curve 0: position is not finite or beyond 1e9 m");
    }
    EXPECT_EQ(s.layers[0].curves[0].vertices, before);
    EXPECT_TRUE(validate(s).empty());
}

TEST(Edits, AddAndDeleteKeepAdjacency) {
    Scene s = smallScene();
    ElementId n;
    addNode(s, 0, {500, 900}, &n);
    Curve c;
    c.vertices = {{{900, 120}}, {{500, 900}}};
    c.start = 1;
    c.end = n;
    c.w = 3;
    c.wf = 5;
    ElementId id;
    const auto cs = addCurve(s, 0, c, &id);
    EXPECT_EQ(s.layers[0].nodes[1].curves.size(), 2u);
    EXPECT_EQ(std::count_if(cs.added.begin(), cs.added.end(), [](const ElementRef& r) { return r.kind == ElementKind::Node; }), 2);
    deleteCurve(s, 0, id);
    EXPECT_EQ(s.layers[0].nodes[1].curves.size(), 1u);
    deleteNode(s, 0, n);
    deleteArea(s, 1, 0);
    EXPECT_EQ(s.layers[1].curves[6].areas, std::vector<ElementId>{1});
    EXPECT_TRUE(validate(s).empty());
}

}  // namespace
}  // namespace lacet
