// A scene read lazily saves its edits into its file, in place (issue 23; io/scene_save_edits.h,
// EditSession::saveEdits): the file saved holds the whole session's document (its rows sum to the
// same checksum, and loadScene checks it), its feature tables and R-trees are those a whole save
// writes, attributes kept; undo and redo go on over the file saved; a file changed since it was
// opened is refused and left as it is. A synthetic scene of 3,000 curves, copied for each test.
#include "io/scene_save_edits.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "editor/edit_session.h"
#include "editor/lazy_edit_check.h"
#include "io/dem_lod.h"
#include "io/gpkg_dem.h"
#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

SessionParams savingSessionParams() {
    SessionParams params;
    params.view.maxLevel = 6;
    params.cacheTiles = 1u << 20;
    return params;
}

LazyParams lazyParams() {
    LazyParams lazy;
    lazy.partLevel = 2;
    lazy.vectorBudgetMiB = 1024.0;
    lazy.background = false;
    return lazy;
}

// The feature tables of a scene file as comparable text: per table (kFeatureIndexTable's rows but
// the largest wf, which an edit only raises), each feature by its element id with every column but
// fid, its geometry in hex, and its R-tree box; GDAL's count. A table without features is left out:
// a save in place leaves a table it emptied (of curves added, then taken back), a whole save
// writes none.
using FeatureDump = std::map<std::string, std::vector<std::string>>;

FeatureDump dumpFeatures(const std::string& path) {
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    FeatureDump out;
    std::vector<std::string> tables;
    {
        auto s = db.prepare(std::string("SELECT table_name, layer, polygons, tolerance FROM ") + kFeatureIndexTable + " ORDER BY table_name");
        while (s.step()) {
            if (db.queryInteger("SELECT COUNT(*) FROM \"" + s.text(0) + "\"") == 0) continue;
            tables.push_back(s.text(0));
            out["index"].push_back(s.text(0) + " " + s.text(1) + " " + s.text(2) + " " + s.text(3));
        }
    }
    for (const std::string& t : tables) {
        std::vector<std::string> columns;
        {
            auto c = db.prepare("SELECT name FROM pragma_table_info(?) ORDER BY name");
            c.bindText(1, t);
            while (c.step())
                if (c.text(0) != "fid") columns.push_back(c.text(0));
        }
        std::string select = "SELECT t.lacet_id, r.minx, r.maxx, r.miny, r.maxy";
        for (const std::string& c : columns) select += ", quote(t.\"" + c + "\")";
        auto s = db.prepare(select + " FROM \"" + t + "\" t LEFT JOIN \"" + featureRtreeName(t) + "\" r ON r.id = t.fid ORDER BY t.lacet_id");
        std::vector<std::string>& rows = out[t];
        while (s.step()) {
            std::string row = s.text(0) + " box " + s.text(1) + " " + s.text(2) + " " + s.text(3) + " " + s.text(4);
            for (std::size_t k = 0; k < columns.size(); ++k)
                if (s.text(int(k) + 5) != "NULL") row += " " + columns[k] + "=" + s.text(int(k) + 5);
            rows.push_back(row);
        }
        rows.push_back("rtree rows " + std::to_string(db.queryInteger("SELECT COUNT(*) FROM \"" + featureRtreeName(t) + "\"")));
        if (db.hasTable("gpkg_ogr_contents")) {
            auto c = db.prepare("SELECT feature_count FROM gpkg_ogr_contents WHERE table_name = ?");
            c.bindText(1, t);
            if (c.step()) rows.push_back("count " + c.text(0));
        }
    }
    return out;
}

void expectSameFeatures(const FeatureDump& a, const FeatureDump& b, const std::string& when) {
    ASSERT_EQ(a.size(), b.size()) << when;
    for (const auto& [table, rows] : a) {
        const auto it = b.find(table);
        ASSERT_NE(it, b.end()) << when << ": table " << table;
        ASSERT_EQ(rows.size(), it->second.size()) << when << ": table " << table;
        for (std::size_t k = 0; k < rows.size(); ++k) EXPECT_EQ(rows[k], it->second[k]) << when << ": table " << table;
    }
}

class LazySaveTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::filesystem::path(test::scratchDir("lazy_save"));
        SceneDocument doc;
        doc.scene = makeSyntheticScene({.seed = 21, .curves = 3000, .roundaboutFraction = 0.3});
        doc.dem = makeSyntheticDem(doc.scene, {.seed = 21, .resolution = 1000});
        // Source attributes on some roads, so that a feature deleted and made again keeps them.
        const ElementId named = ElementId(std::min<std::size_t>(40, doc.scene.layers[0].curves.size()));
        for (ElementId c = 0; c < named; ++c) {
            doc.attributes.push_back({0, ElementKind::Curve, c, "name", std::string("Road ").append(std::to_string(c))});
            if (c % 3 == 0) doc.attributes.push_back({0, ElementKind::Curve, c, "ref", std::string("N").append(std::to_string(c))});
        }
        original_ = new std::string((*dir_ / "original.gpkg").string());
        saveScene(*original_, doc);
    }
    static void TearDownTestSuite() {
        std::filesystem::remove_all(*dir_);
        delete original_;
        delete dir_;
    }
    // A copy of the scene to edit, as `name`.
    static std::string copy(const std::string& name) {
        const std::string path = (*dir_ / name).string();
        std::filesystem::copy_file(*original_, path, std::filesystem::copy_options::overwrite_existing);
        return path;
    }
    // What saveScene writes for the document the file at `path` holds, as `name`.
    static std::string savedWhole(const std::string& path, const std::string& name) {
        const std::string out = (*dir_ / name).string();
        saveScene(out, loadScene(path));
        return out;
    }
    static std::filesystem::path* dir_;
    static std::string* original_;
};
std::filesystem::path* LazySaveTest::dir_ = nullptr;
std::string* LazySaveTest::original_ = nullptr;

TEST_F(LazySaveTest, RandomEditsSavedNowAndThenSumToTheWholeSceneAndUndoGoesOnOverTheFileSaved) {
    const std::string path = copy("random.gpkg");
    EditSession whole(loadScene(path), savingSessionParams());
    EditSession lazy(path, lazyParams(), savingSessionParams());
    constexpr int kSaveEvery = 4;
    const int edits = test::sanitizedOr(30, 5);
    const LazyEditCheckReport r = checkLazyEdits(lazy, whole, {.seed = 17, .edits = edits, .saveEvery = kSaveEvery});
    for (const std::string& d : r.details) ADD_FAILURE() << d;
    EXPECT_EQ(r.mismatches, 0u);
    EXPECT_GE(r.saves, std::size_t(edits / kSaveEvery + 1));  // while editing, and once when all is undone
    EXPECT_GT(r.undos, 0u);
    EXPECT_GT(r.tilesCompared, 30 * r.edits);
    // All undone and saved: the file holds what it held when opened, values and checksum.
    SceneDocument now = loadScene(path);
    EXPECT_EQ(sceneChecksumText(now), sceneChecksumText(loadScene(*original_)));
    expectSameFeatures(dumpFeatures(path), dumpFeatures(savedWhole(path, "random.whole.gpkg")), "all undone");
}

TEST_F(LazySaveTest, AFileSavedInPlaceHasTheFeatureTablesOfAWholeSaveAttributesKept) {
    const std::string path = copy("features.gpkg");
    const SceneDocument doc = loadScene(path);
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const Layer& roads = doc.scene.layers[0];
    ASSERT_EQ(roads.kind, LayerKind::Roads);
    // Roads with attributes deleted, moved, widened, made bridges; a node dragged; a field's
    // border moved (its area's polygon changes).
    std::size_t deleted = 0;
    for (ElementId c = 0; c < roads.curves.size() && deleted < 4; ++c)
        if (roads.curves[c].alive) {
            lazy.execute(DeleteCurveCmd{0, c});
            ++deleted;
        }
    ASSERT_EQ(deleted, 4u);
    for (ElementId c = 5; c < roads.curves.size(); c += 3) {
        const Curve& cv = roads.curves[c];
        if (!cv.alive || cv.vertices.size() < 3) continue;
        lazy.execute(MoveVertexCmd{0, c, 1, cv.vertices[1].p + Vec2(35.0, -20.0)});
        lazy.execute(SetCurveWidthCmd{0, c, cv.w * 2.0f, cv.wf * 2.0f});
        lazy.execute(SetCurveFlagsCmd{0, c, std::uint16_t(cv.flags ^ kBridge)});
    }
    const ElementId node = roads.curves[roads.curves.size() - 1].start;
    lazy.execute(MoveNodeCmd{0, node, roads.nodes[node].p + Vec2(-25.0, 30.0)});
    bool movedBorder = false;
    for (std::size_t l = 1; l < doc.scene.layers.size() && !movedBorder; ++l) {
        const Layer& layer = doc.scene.layers[l];
        for (ElementId c = 0; c < layer.curves.size() && !movedBorder; ++c) {
            const Curve& cv = layer.curves[c];
            if (!cv.alive || cv.areas.empty() || cv.vertices.size() < 3) continue;
            lazy.execute(MoveVertexCmd{LayerId(l), c, 1, cv.vertices[1].p + Vec2(8.0, 8.0)});
            movedBorder = true;
        }
    }
    ASSERT_TRUE(movedBorder);
    ASSERT_TRUE(lazy.modified());
    const SceneEditsSaved saved = lazy.saveEdits();
    EXPECT_FALSE(lazy.modified());
    EXPECT_EQ(saved.features.deleted, 4u);
    EXPECT_FALSE(saved.summedWhole);  // updated by the rows' digests
    EXPECT_GT(saved.features.updated, 5u);
    EXPECT_EQ(saved.checksum, sceneChecksumText(loadScene(path)));  // loadScene checks the stored one too
    expectSameFeatures(dumpFeatures(path), dumpFeatures(savedWhole(path, "features.whole.gpkg")), "edited");
    // Undone and saved again: the deleted roads' features are made again, with their attributes.
    while (lazy.undo()) {
    }
    ASSERT_TRUE(lazy.modified());
    const SceneEditsSaved back = lazy.saveEdits();
    EXPECT_EQ(back.features.inserted, 4u);
    EXPECT_EQ(back.checksum, sceneChecksumText(doc));
    expectSameFeatures(dumpFeatures(path), dumpFeatures(*original_), "undone");
    // And redone over the file saved: the edited file again.
    while (lazy.redo()) {
    }
    lazy.saveEdits();
    expectSameFeatures(dumpFeatures(path), dumpFeatures(savedWhole(path, "features.redone.gpkg")), "redone");
    EXPECT_EQ(sceneChecksumText(loadScene(path)), saved.checksum);
}

TEST_F(LazySaveTest, ASaveOverAFileChangedSinceItWasOpenedIsRefusedAndLeavesItAsItIs) {
    const std::string path = copy("changed.gpkg");
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const SceneDocument opened = loadScene(path);
    const Layer& roads = opened.scene.layers[0];
    const ElementId node = roads.curves[3].start;
    lazy.execute(MoveNodeCmd{0, node, roads.nodes[node].p + Vec2(10.0, 10.0)});
    SceneDocument other;
    other.scene = makeSyntheticScene({.seed = 22, .curves = 500});
    other.dem = makeSyntheticDem(other.scene, {.seed = 22, .resolution = 200});
    saveScene(path, other);
    const std::string before = sceneChecksumText(loadScene(path));
    try {
        lazy.saveEdits();
        ADD_FAILURE() << "saved over a file changed since it was opened";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("changed since"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(lazy.modified());
    EXPECT_EQ(sceneChecksumText(loadScene(path)), before);
}

// The file at `path` as a format-1 file wrote it: its version and that form of its checksum, without
// the parts (io/scene_checksum.h).
void makeFormat1(const std::string& path) {
    const SceneDocument doc = loadScene(path);
    SqliteDb db(path, SqliteDb::Mode::ReadWrite);
    db.exec("UPDATE lacet_meta SET value = '1' WHERE key = 'format_version'");
    db.exec("UPDATE lacet_meta SET value = '" + sceneChecksumText(doc, 1) + "' WHERE key = 'checksum'");
    db.exec("DELETE FROM lacet_meta WHERE key IN ('checksum_head', 'checksum_elements')");
    db.close();
}

std::string metaValue(const std::string& path, const std::string& key) {
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    return db.queryText("SELECT value FROM lacet_meta WHERE key = '" + key + "'");
}

TEST_F(LazySaveTest, AFileOfFormat1LoadsAndItsFirstSaveInPlaceMakesItFormat2) {
    const std::string path = copy("format1.gpkg");
    const SceneDocument doc = loadScene(path);
    makeFormat1(path);
    EXPECT_EQ(sceneChecksumText(loadScene(path)), sceneChecksumText(doc));  // loads, its format-1 checksum checked
    EXPECT_NE(sceneChecksumText(doc, 1), sceneChecksumText(doc));
    {
        // Damage is still caught in format 1.
        const std::string damaged = copy("format1.damaged.gpkg");
        makeFormat1(damaged);
        SqliteDb db(damaged, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE lacet_curves SET w = 7.5 WHERE layer = 0 AND id = 0");
        db.close();
        EXPECT_THROW(loadScene(damaged), SceneFileError);
    }
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const Layer& roads = doc.scene.layers[0];
    const ElementId node = roads.curves[2].start;
    lazy.execute(MoveNodeCmd{0, node, roads.nodes[node].p + Vec2(12.0, -9.0)});
    const SceneEditsSaved first = lazy.saveEdits();
    EXPECT_TRUE(first.summedWhole);
    EXPECT_EQ(metaValue(path, "format_version"), "2");
    const SceneDocument once = loadScene(path);
    EXPECT_EQ(first.checksum, sceneChecksumText(once));
    // From then on the checksum is updated by the rows saved, not summed whole.
    lazy.execute(SetCurveWidthCmd{0, 2, roads.curves[2].w + 1.0f, roads.curves[2].wf + 1.0f});
    const SceneEditsSaved second = lazy.saveEdits();
    EXPECT_FALSE(second.summedWhole);
    EXPECT_EQ(second.checksum, sceneChecksumText(loadScene(path)));
    const SceneChecksumParts parts = sceneChecksumParts(loadScene(path));
    EXPECT_EQ(metaValue(path, "checksum_head"), SceneChecksum::hex(parts.head));
    EXPECT_EQ(metaValue(path, "checksum_elements"), SceneChecksum::hex(parts.elements));
    // Stored parts that do not give the checksum are not trusted: summed whole again (with the
    // attributes and the DEM the head holds), the file loads.
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE lacet_meta SET value = '0000000000000001' WHERE key = 'checksum_head'");
        db.close();
    }
    lazy.execute(SetCurveWidthCmd{0, 2, roads.curves[2].w + 2.0f, roads.curves[2].wf + 2.0f});
    const SceneEditsSaved third = lazy.saveEdits();
    EXPECT_TRUE(third.summedWhole);
    EXPECT_EQ(third.checksum, sceneChecksumText(loadScene(path)));
    EXPECT_EQ(metaValue(path, "checksum_head"), SceneChecksum::hex(sceneChecksumParts(loadScene(path)).head));
}

TEST_F(LazySaveTest, ASaveThatFailsLeavesTheFileAsItWasAndTheEditsToSaveAgain) {
    const std::string path = copy("failing.gpkg");
    const std::string before = sceneChecksumText(loadScene(path));
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const SceneDocument opened = loadScene(path);
    const Layer& roads = opened.scene.layers[0];
    const ElementId node = roads.curves[1].start;
    lazy.execute(MoveNodeCmd{0, node, roads.nodes[node].p + Vec2(20.0, 5.0)});
    {
        // A failure at the last write of the save (the checksum): everything before it is taken back.
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("CREATE TRIGGER fail_save BEFORE UPDATE ON lacet_meta BEGIN SELECT RAISE(ABORT, 'injected failure'); END");
        db.close();
    }
    try {
        lazy.saveEdits();
        ADD_FAILURE() << "the save went through its injected failure";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find("injected failure"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    EXPECT_TRUE(lazy.modified());
    EXPECT_EQ(sceneChecksumText(loadScene(path)), before);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("DROP TRIGGER fail_save");
        db.close();
    }
    const SceneEditsSaved saved = lazy.saveEdits();  // the same edits, saved now
    EXPECT_NE(saved.checksum, before);
    EXPECT_EQ(sceneChecksumText(loadScene(path)), saved.checksum);
}

TEST_F(LazySaveTest, AWriterKilledInItsTransactionLeavesTheFileAsItWasToTheNextRead) {
    // A writer killed in the middle of its transaction (a save in place) leaves a hot journal; the
    // next read, a read-only one, rolls it back (io/sqlite_db.h) and finds the file as it was: here
    // another process's (`lacet render`), as after a crash. Without that roll back, the read fails
    // ("attempt to write a readonly database"; checked).
    const std::string path = copy("killed.gpkg");
    const std::string before = sceneChecksumText(loadScene(path));
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("PRAGMA cache_size = 1");  // the changes spill into the file before the commit: the journal is hot
        db.exec("BEGIN IMMEDIATE");
        db.exec("UPDATE lacet_curves SET w = w + 1");
        db.exec("UPDATE lacet_meta SET value = 'torn' WHERE key = 'checksum'");
        ::_exit(0);  // no commit, no rollback: as if killed
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_TRUE(std::filesystem::exists(path + "-journal"));
    const std::string render = std::string(LACET_BINARY) + " render --scene " + path + " --out " + path + ".png > " + path + ".txt 2>&1";
    EXPECT_EQ(std::system(render.c_str()), 0) << render;
    EXPECT_FALSE(std::filesystem::exists(path + "-journal"));
    EXPECT_EQ(sceneChecksumText(loadScene(path)), before);
}

TEST_F(LazySaveTest, CurvesDrawnLazilyTakeTheWholeScenesIdsAndTheirRowsGoWhenTakenBackAfterASave) {
    // New nodes and curves on a scene read lazily, as the draw tool makes them (a node, a node, a
    // curve between the two: nodes without curves, which no feature's box finds), and one from a
    // node the file has; the same commands on the whole scene. Saved, the file sums to the whole
    // session's document; taken back after the save, their rows and features go, and the ids they
    // had are given again.
    const std::string path = copy("drawn.gpkg");
    const SceneDocument opened = loadScene(path);
    EditSession whole(loadScene(path), savingSessionParams());
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const Layer& roads = opened.scene.layers[0];
    const ElementId firstNode = ElementId(roads.nodes.size()), firstCurve = ElementId(roads.curves.size());
    const auto both = [&](const Command& c) {
        whole.execute(c);
        lazy.execute(c);
    };
    const auto draw = [&](Vec2 a, Vec2 b, ElementId from) {
        for (EditSession* s : {&whole, &lazy}) s->beginGroup();
        ElementId start = from;
        if (start == kNoElement) {
            start = lazy.nextId(0, ElementKind::Node);
            EXPECT_EQ(start, whole.nextId(0, ElementKind::Node));
            both(AddNodeCmd{0, a});
        }
        const ElementId end = lazy.nextId(0, ElementKind::Node);
        EXPECT_EQ(end, whole.nextId(0, ElementKind::Node));
        both(AddNodeCmd{0, b});
        Curve c;
        c.start = start;
        c.end = end;
        c.w = 6.0f;
        c.wf = 15.0f;
        c.vertices = {Vertex{a, true, false}, Vertex{(a + b) * 0.5 + Vec2(5.0, -5.0), false, false}, Vertex{b, true, false}};
        EXPECT_EQ(lazy.nextId(0, ElementKind::Curve), whole.nextId(0, ElementKind::Curve));
        both(AddCurveCmd{0, c});
        for (EditSession* s : {&whole, &lazy}) s->endGroup();
    };
    const Vec2 mid = opened.scene.extent.center();
    draw(mid, mid + Vec2(150.0, 40.0), kNoElement);
    const ElementId joined = roads.curves[5].end;
    draw(roads.nodes[joined].p, roads.nodes[joined].p + Vec2(-60.0, 90.0), joined);
    // A curve drawn, then dragged by its new node.
    both(MoveNodeCmd{0, firstNode + 1, mid + Vec2(160.0, 60.0)});
    const SceneEditsSaved saved = lazy.saveEdits();
    EXPECT_EQ(saved.added, 5u);  // 3 nodes, 2 curves
    EXPECT_TRUE(saved.headSummed);
    EXPECT_EQ(saved.features.inserted, 2u);
    EXPECT_EQ(saved.checksum, sceneChecksumText(whole.document()));
    {
        const SceneDocument file = loadScene(path);  // its ids 0, 1, 2... and its checksum checked
        ASSERT_EQ(file.scene.layers[0].curves.size(), roads.curves.size() + 2);
        EXPECT_EQ(file.scene.layers[0].curves[firstCurve].start, firstNode);
        EXPECT_EQ(file.scene.layers[0].curves[firstCurve + 1].start, joined);
    }
    expectSameFeatures(dumpFeatures(path), dumpFeatures(savedWhole(path, "drawn.whole.gpkg")), "drawn");
    // The second curve taken back after the save: its rows go, its ids are given again.
    ASSERT_TRUE(whole.undo() && lazy.undo());  // the drag
    ASSERT_TRUE(whole.undo() && lazy.undo());  // the second curve and its node
    EXPECT_EQ(lazy.nextId(0, ElementKind::Curve), firstCurve + 1);
    EXPECT_EQ(lazy.nextId(0, ElementKind::Node), firstNode + 2);
    const SceneEditsSaved back = lazy.saveEdits();
    EXPECT_EQ(back.removed, 2u);
    EXPECT_EQ(back.checksum, sceneChecksumText(whole.document()));
    EXPECT_EQ(loadScene(path).scene.layers[0].curves.size(), roads.curves.size() + 1);
    // Redone over the file saved, then a new curve in the ids given again, everything undone: the
    // file as it was opened.
    ASSERT_TRUE(whole.redo() && lazy.redo());
    ASSERT_TRUE(whole.undo() && lazy.undo());
    draw(mid + Vec2(-300.0, 0.0), mid + Vec2(-200.0, 50.0), kNoElement);
    EXPECT_EQ(lazy.nextId(0, ElementKind::Curve), firstCurve + 2);
    EXPECT_EQ(lazy.saveEdits().checksum, sceneChecksumText(whole.document()));
    while (whole.undo()) ASSERT_TRUE(lazy.undo());
    EXPECT_FALSE(lazy.undo());
    EXPECT_EQ(lazy.saveEdits().checksum, sceneChecksumText(opened));
    EXPECT_EQ(sceneChecksumText(loadScene(path)), sceneChecksumText(opened));
    expectSameFeatures(dumpFeatures(path), dumpFeatures(*original_), "all undone");
}

TEST_F(LazySaveTest, ACurveDrawnOverAStreamedDemSumsTheHeadFromTheTreesLayoutAndDigest) {
    // A scene whose DEM is a LOD tree (io/dem_lod.h): a save that adds rows sums the checksum's
    // head again from the tree's layout and stored digest (no level of it read), and the file
    // loads, its checksum checked.
    const std::string tree = (*dir_ / "tree.gpkg").string();
    SceneDocument doc = loadScene(*original_);
    {
        createEmptyGpkg(tree);
        SqliteDb db(tree, SqliteDb::Mode::ReadWrite);
        writeDemLod(db, *doc.dem, 64, 0);
        db.close();
    }
    doc.demLod = std::make_shared<const DemLodFile>(tree);
    const std::string path = (*dir_ / "streamed.gpkg").string();
    saveScene(path, doc);
    ASSERT_TRUE(loadScene(path).demLod);
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const Vec2 a = doc.scene.extent.center(), b = a + Vec2(90.0, 30.0);
    Curve c;
    c.start = lazy.nextId(0, ElementKind::Node);
    lazy.execute(AddNodeCmd{0, a});
    c.end = lazy.nextId(0, ElementKind::Node);
    lazy.execute(AddNodeCmd{0, b});
    c.w = 5.0f;
    c.wf = 12.0f;
    c.vertices = {Vertex{a, true, false}, Vertex{b, true, false}};
    lazy.execute(AddCurveCmd{0, c});
    const SceneEditsSaved saved = lazy.saveEdits();
    EXPECT_TRUE(saved.headSummed);
    EXPECT_FALSE(saved.summedWhole);
    const SceneDocument file = loadScene(path);  // checks the checksum
    EXPECT_EQ(saved.checksum, sceneChecksumText(file));
    EXPECT_EQ(file.scene.layers[0].curves.size(), doc.scene.layers[0].curves.size() + 1);
    ASSERT_TRUE(lazy.undo() && lazy.undo() && lazy.undo());
    EXPECT_EQ(lazy.saveEdits().checksum, sceneChecksumText(doc));
    EXPECT_EQ(sceneChecksumText(loadScene(path)), sceneChecksumText(doc));
}

TEST_F(LazySaveTest, NothingToSaveWritesNothing) {
    const std::string path = copy("nothing.gpkg");
    const auto time = std::filesystem::last_write_time(path);
    EditSession lazy(path, lazyParams(), savingSessionParams());
    const SceneEditsSaved saved = lazy.saveEdits();
    EXPECT_EQ(saved.nodes + saved.curves + saved.areas, 0u);
    EXPECT_EQ(saved.checksum, lazy.storedChecksum());
    EXPECT_EQ(std::filesystem::last_write_time(path), time);
}

}  // namespace
}  // namespace lacet
