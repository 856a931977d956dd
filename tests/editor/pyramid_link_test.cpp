// The editor's pyramid link (editor/pyramid_link.h): the scene's pyramid opened for a session,
// updated after a save to the scene's own file (not after a save elsewhere), one update at a time
// with the next save queued, reopened with the save's edit count; a pyramid of another scene
// refused and forgotten; an update of a session left behind not applied to the next one.
#include "editor/pyramid_link.h"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "pyramid/pyramid_build.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

SceneDocument smallDocument() {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({5, 600});
    doc.dem = makeSyntheticDem(doc.scene, {5, 600});
    return doc;
}

SessionParams linkSessionParams() {
    SessionParams params;
    params.view.maxLevel = 5;
    return params;
}

// A road's first control point moved by `d` metres east, as a drag would.
void moveARoad(EditSession& s, double d) {
    const Layer& roads = s.document().scene.layers[kRoadsLayer];
    ElementId c = 0;
    while (!roads.curves[c].alive) ++c;
    s.execute(MoveVertexCmd{kRoadsLayer, c, 1, roads.curves[c].vertices[1].p + Vec2(d, 0.0)});
}

class PyramidLinkTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::scratchDir("pyramid_link");
        scene_ = (dir_ / "scene.gpkg").string();
        saveScene(scene_, smallDocument());
        PyramidParams params;
        params.maxLevel = 3;
        params.vectorLevels = 1;
        params.encoding.format = TileFormat::Png;
        buildPyramid(smallDocument(), defaultPyramidPath(scene_), params, /*force=*/true, nullptr);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }
    std::filesystem::path dir_;
    std::string scene_;
};

TEST_F(PyramidLinkTest, UpdatesAfterSavesToItsSceneOneAtATimeAndReopensAtTheSavesEditCount) {
    EditSession session(loadScene(scene_), linkSessionParams());
    PyramidLink link;
    link.setDefaultFiles(scene_);
    EXPECT_EQ(link.path(), defaultPyramidPath(scene_));
    link.sessionStarted();
    const PyramidOpened opened = link.open(session);
    ASSERT_TRUE(opened.levels) << opened.error;
    EXPECT_EQ(opened.levels->vectorLevel, 3);
    EXPECT_EQ(opened.levels->minLevel, 0);
    EXPECT_NE(session.pyramid(), nullptr);

    // A save elsewhere is another scene: nothing is updated.
    moveARoad(session, 20.0);
    const std::string other = (dir_ / "other.gpkg").string();
    saveScene(other, session.document());
    EXPECT_NE(link.afterSave(session, other).find("another file"), std::string::npos);
    EXPECT_FALSE(link.updating());
    EXPECT_FALSE(link.poll(session, true));

    // A save to the scene: updated in the background; a second save meanwhile waits its turn.
    saveScene(scene_, session.document());
    EXPECT_NE(link.afterSave(session, scene_).find("Updating the pyramid"), std::string::npos);
    EXPECT_TRUE(link.updating());
    moveARoad(session, 15.0);
    saveScene(scene_, session.document());
    EXPECT_NE(link.afterSave(session, scene_).find("after the update in flight"), std::string::npos);
    const std::optional<PyramidUpdateResult> first = link.poll(session, true);
    ASSERT_TRUE(first);
    EXPECT_TRUE(first->ok()) << first->error;
    EXPECT_TRUE(first->updated);
    EXPECT_EQ(first->madeAt, 1u);
    EXPECT_GT(first->quadsChanged, 0u);
    EXPECT_LT(first->quadsChanged, first->quads);
    EXPECT_TRUE(link.updating()) << "the queued save's update started";
    const std::optional<PyramidUpdateResult> second = link.poll(session, true);
    ASSERT_TRUE(second);
    EXPECT_TRUE(second->ok()) << second->error;
    EXPECT_EQ(second->madeAt, 2u);
    EXPECT_FALSE(link.updating());
    ASSERT_TRUE(link.last());
    EXPECT_EQ(link.last()->madeAt, 2u);
    // The pyramid as updated holds the saved scene: an update finds nothing to do.
    const PyramidStats again = updatePyramid(loadScene(scene_), defaultPyramidPath(scene_), nullptr);
    EXPECT_EQ(again.quadsChanged, 0u) << "the link's updates left nothing to update";
}

TEST_F(PyramidLinkTest, AnUpdateOfASessionLeftBehindIsNotAppliedToTheNext) {
    EditSession first(loadScene(scene_), linkSessionParams());
    PyramidLink link;
    link.setDefaultFiles(scene_);
    link.sessionStarted();
    ASSERT_TRUE(link.open(first).levels);
    moveARoad(first, 20.0);
    saveScene(scene_, first.document());
    link.afterSave(first, scene_);
    EditSession next(loadScene(scene_), linkSessionParams());
    link.sessionStarted();
    EXPECT_FALSE(link.poll(next, true)) << "the first session's update is not the next one's";
    EXPECT_FALSE(link.last());
    EXPECT_FALSE(link.updating());
}

TEST_F(PyramidLinkTest, APyramidOfAnotherSceneIsRefusedAndForgotten) {
    SceneDocument moved = smallDocument();
    moved.scene.extent.max += Vec2(1.0, 1.0);
    EditSession session(std::move(moved), linkSessionParams());
    PyramidLink link;
    link.setFiles(defaultPyramidPath(scene_), scene_);
    link.sessionStarted();
    const PyramidOpened o = link.open(session);
    EXPECT_FALSE(o.levels);
    EXPECT_NE(o.error.find("extent"), std::string::npos) << o.error;
    EXPECT_TRUE(link.path().empty());
    EXPECT_FALSE(link.levels());
    EXPECT_EQ(session.pyramid(), nullptr);
    EXPECT_TRUE(link.afterSave(session, scene_).empty()) << "no pyramid: a save updates nothing";
    // No pyramid beside a scene: none opened, no error.
    link.setDefaultFiles((dir_ / "alone.gpkg").string());
    EXPECT_TRUE(link.path().empty());
    const PyramidOpened none = link.open(session);
    EXPECT_FALSE(none.levels);
    EXPECT_TRUE(none.error.empty());
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// A session reading the scene file lazily: its save in place (EditSession::saveEdits) updates the
// pyramid from the file, which is reopened with the file's stored checksum after the save; two
// saves in a row, the second while the first's update runs, end with the pyramid of the second.
TEST_F(PyramidLinkTest, ASceneReadLazilyIsUpdatedFromItsFileAfterEachSaveInPlace) {
    LazyParams lazy;
    lazy.partLevel = 1;
    lazy.vectorBudgetMiB = 256.0;
    lazy.background = false;
    lazy.topElevationOnly = true;
    EditSession session(scene_, lazy, linkSessionParams());
    PyramidLink link;
    link.setDefaultFiles(scene_);
    link.sessionStarted();
    ASSERT_TRUE(link.open(session).levels);
    const SceneDocument whole = loadScene(scene_);
    const Layer& roads = whole.scene.layers[kRoadsLayer];
    ElementId c = 0;
    while (!roads.curves[c].alive) ++c;
    for (double d : {25.0, 45.0}) {
        session.execute(MoveVertexCmd{kRoadsLayer, c, 1, roads.curves[c].vertices[1].p + Vec2(d, 0.0)});
        session.saveEdits();
        EXPECT_NE(link.afterSave(session, scene_).find("Updating"), std::string::npos);
    }
    while (link.updating()) {
        const std::optional<PyramidUpdateResult> r = link.poll(session, true);
        ASSERT_TRUE(r);
        EXPECT_TRUE(r->ok()) << r->error;
    }
    ASSERT_NE(session.pyramid(), nullptr);
    EXPECT_EQ(session.pyramid()->sceneChecksum(), session.storedChecksum());
    // The pyramid is the one a build of the file saved makes.
    const SceneDocument saved = loadScene(scene_);
    EXPECT_EQ(session.storedChecksum(), sceneChecksumText(saved));
    EXPECT_NO_THROW(PyramidReader(defaultPyramidPath(scene_), saved));
}

}  // namespace
}  // namespace lacet
