// The editor's reader of a pyramid (pyramid/pyramid_reader.h): it refuses a pyramid of an earlier
// state of the scene, and records the checksum it was given in either of the document's forms.
#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {

// The editor does not show a pyramid of another state of the scene; after an update it does.
TEST(PyramidReader, RefusesAPyramidOfAnEarlierStateOfTheScene) {
    SceneDocument doc = smallScene();
    TempFile f("pyramid_stale.gpkg");
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    EXPECT_NO_THROW(PyramidReader(f.path, doc));
    std::mt19937_64 rng(5);
    applyRandomEdit(doc.scene, rng, 50.0);
    try {
        PyramidReader reader(f.path, doc);
        FAIL() << "a pyramid of the scene before an edit was accepted";
    } catch (const PyramidError& e) {
        EXPECT_NE(std::string(e.what()).find("another state of the scene"), std::string::npos) << e.what();
    }
    updatePyramid(doc, f.path, nullptr);
    EXPECT_NO_THROW(PyramidReader(f.path, doc));
}

// A pyramid records the document's checksum, or the one given (a scene file's stored text, of a
// format-1 file: io/scene_checksum.h); the editor takes either form of the document's.
TEST(PyramidReader, RecordsTheChecksumGivenAndTakesEitherFormOfTheDocuments) {
    const SceneDocument doc = smallScene();
    TempFile f("pyramid_checksum.gpkg");
    PyramidParams params = smallParams();
    params.sceneChecksum = sceneChecksumText(doc, 1);
    buildPyramid(doc, f.path, params, false, nullptr);
    const Box extent = doc.scene.extent;
    EXPECT_EQ(PyramidReader(f.path, extent, std::string()).sceneChecksum(), sceneChecksumText(doc, 1));
    EXPECT_NO_THROW(PyramidReader(f.path, doc));
    updatePyramid(doc, f.path, nullptr);
    EXPECT_EQ(PyramidReader(f.path, extent, std::string()).sceneChecksum(), sceneChecksumText(doc));
    updatePyramid(doc, f.path, nullptr, PyramidParams{}.demBudgetMiB, "0123456789abcdef");
    EXPECT_EQ(PyramidReader(f.path, extent, std::string()).sceneChecksum(), "0123456789abcdef");
    EXPECT_THROW(PyramidReader(f.path, doc), PyramidError);
}

// A file that is no pyramid, an incomplete pyramid and a pyramid of another extent are refused by
// name and reason.
TEST(PyramidReader, RefusesWhatIsNoCompletePyramidOfTheScene) {
    const SceneDocument doc = smallScene();
    TempFile scene("reader_scene.gpkg"), incomplete("reader_incomplete.gpkg"), pyramid("reader_pyramid.gpkg");
    saveScene(scene.path, doc);
    buildPyramid(doc, pyramid.path, smallParams(), false, nullptr);
    std::filesystem::copy_file(pyramid.path, incomplete.path, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(incomplete.path, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE lacet_pyramid SET value = '0' WHERE key = 'complete'");
    }
    const auto refused = [&](const std::string& path, const Box& extent, const std::string& reason) {
        SCOPED_TRACE(path + ": " + reason);
        try {
            PyramidReader r(path, extent, doc.georeference.crsWkt);
            ADD_FAILURE() << "accepted";
        } catch (const PyramidError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
        }
    };
    refused(scene.path, doc.scene.extent, "no");
    refused(incomplete.path, doc.scene.extent, "incomplete");
    refused(pyramid.path, {doc.scene.extent.min, doc.scene.extent.max + Vec2(1.0)}, "made for the extent");
    PyramidReader ok(pyramid.path, doc.scene.extent, doc.georeference.crsWkt);  // the control
}

}  // namespace
}  // namespace lacet
