// The command history (editor/command_history.h) on its own, with no quadtree: a drag's moves
// merged into one undo step unless a save falls between them, groups undone and redone whole, a
// new command dropping the redo stack, a refused command leaving everything as it was, and each
// changeset handed on in order.
#include "editor/command_history.h"

#include <vector>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

struct Recorder {
    std::vector<Changeset> seen;
    CommandHistory::AfterEdit after() {
        return [this](const Changeset& cs, double ms) {
            EXPECT_GE(ms, 0.0);
            seen.push_back(cs);
        };
    }
};

ElementId firstAliveRoad(const Scene& s) {
    ElementId c = 0;
    while (!s.layers[kRoadsLayer].curves[c].alive) ++c;
    return c;
}

TEST(CommandHistory, ADragIsOneUndoStepUnlessASaveFallsInIt) {
    Scene scene = makeSyntheticScene({3, 300});
    const ElementId c = firstAliveRoad(scene);
    const Vec2 p0 = scene.layers[kRoadsLayer].curves[c].vertices[1].p;
    CommandHistory h;
    Recorder rec;
    EXPECT_FALSE(h.modified());
    for (int i = 1; i <= 3; ++i) h.execute(scene, MoveVertexCmd{kRoadsLayer, c, 1, p0 + Vec2(i, 0.0)}, true, rec.after());
    EXPECT_EQ(h.undoDepth(), 1u);
    EXPECT_EQ(rec.seen.size(), 3u) << "each move is handed on";
    EXPECT_TRUE(h.modified());
    h.markSaved();
    EXPECT_FALSE(h.modified());
    h.execute(scene, MoveVertexCmd{kRoadsLayer, c, 1, p0 + Vec2(9.0, 0.0)}, true, rec.after());
    EXPECT_EQ(h.undoDepth(), 2u) << "a save splits the drag";
    EXPECT_TRUE(h.modified());
    ASSERT_TRUE(h.undo(scene, rec.after()));
    EXPECT_FALSE(h.modified()) << "back to the saved state";
    EXPECT_EQ(scene.layers[kRoadsLayer].curves[c].vertices[1].p, p0 + Vec2(3.0, 0.0));
    ASSERT_TRUE(h.undo(scene, rec.after()));
    EXPECT_EQ(scene.layers[kRoadsLayer].curves[c].vertices[1].p, p0) << "undo restores the drag's start exactly";
    EXPECT_FALSE(h.undo(scene, rec.after()));
    EXPECT_EQ(h.redoDepth(), 2u);
    // A new command drops the redo stack.
    h.execute(scene, MoveVertexCmd{kRoadsLayer, c, 2, p0}, false, rec.after());
    EXPECT_EQ(h.redoDepth(), 0u);
    EXPECT_FALSE(h.redo(scene, rec.after()));
}

TEST(CommandHistory, AGroupIsUndoneAndRedoneWholeAndARefusedCommandChangesNothing) {
    Scene scene = makeSyntheticScene({3, 300});
    const std::size_t nodes = scene.layers[kRoadsLayer].nodes.size();
    CommandHistory h;
    Recorder rec;
    h.beginGroup();
    h.execute(scene, AddNodeCmd{kRoadsLayer, {10.0, 10.0}}, false, rec.after());
    h.execute(scene, AddNodeCmd{kRoadsLayer, {20.0, 10.0}}, false, rec.after());
    h.endGroup();
    EXPECT_EQ(h.undoDepth(), 2u);
    rec.seen.clear();
    ASSERT_TRUE(h.undo(scene, rec.after()));
    EXPECT_EQ(rec.seen.size(), 2u) << "both commands undone in one call";
    EXPECT_EQ(scene.layers[kRoadsLayer].nodes.size(), nodes) << "the added slots are gone";
    ASSERT_TRUE(h.redo(scene, rec.after()));
    ASSERT_EQ(scene.layers[kRoadsLayer].nodes.size(), nodes + 2);
    EXPECT_EQ(scene.layers[kRoadsLayer].nodes[nodes + 1].p, Vec2(20.0, 10.0));
    EXPECT_EQ(h.redoDepth(), 0u);
    // A refused command: the scene, the history and the caller see nothing.
    rec.seen.clear();
    EXPECT_THROW(h.execute(scene, DeleteCurveCmd{kRoadsLayer, kNoElement}, false, rec.after()), EditError);
    EXPECT_EQ(scene.layers[kRoadsLayer].nodes.size(), nodes + 2);
    EXPECT_EQ(h.undoDepth(), 2u);
    EXPECT_TRUE(rec.seen.empty());
}

}  // namespace
}  // namespace lacet
