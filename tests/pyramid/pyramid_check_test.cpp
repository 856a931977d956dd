// What lacet info says of a pyramid (pyramid/pyramid_check.h): every tile decoded, a corrupt one
// and a missing one reported by table, quad and reason.
#include <fstream>
#include <string>

#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {

TEST(PyramidCheck, ReportsACorruptTileAndAMissingOne) {
    const SceneDocument doc = smallScene();
    TempFile f("pyramid_corrupt.gpkg");
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    {
        SqliteDb db(f.path, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("UPDATE ") + kAppearanceTable + " SET tile_data = x'89504E470D0A1A0A0000' WHERE zoom_level = 2 AND "
                "tile_column = 1 AND tile_row = 0");
        db.exec(std::string("DELETE FROM ") + kElevationTable + " WHERE zoom_level = 3 AND tile_column = 0 AND tile_row = 7");
    }
    const PyramidCheck c = checkPyramid(f.path);
    ASSERT_EQ(c.problems.size(), 2u);
    EXPECT_EQ(c.problems[0].table, kAppearanceTable);
    EXPECT_EQ(c.problems[0].quad, (PyramidKey{2, 1, 3}));
    EXPECT_NE(c.problems[0].reason.find("does not decode"), std::string::npos) << c.problems[0].reason;
    EXPECT_EQ(c.problems[1].table, kElevationTable);
    EXPECT_EQ(c.problems[1].quad, (PyramidKey{3, 0, 0}));
    EXPECT_EQ(c.problems[1].reason, "missing");
}

// A file that holds no pyramid (a scene, a text, nothing) is refused by name, never a crash.
TEST(PyramidCheck, AFileWithoutAPyramidIsRefusedByName) {
    TempFile scene("check_scene.gpkg"), text("check_text.gpkg");
    saveScene(scene.path, smallScene());
    { std::ofstream(text.path) << "not a pyramid\n"; }
    for (const std::string& path : {scene.path, text.path, text.path + ".missing"}) {
        SCOPED_TRACE(path);
        try {
            checkPyramid(path);
            ADD_FAILURE() << "accepted";
        } catch (const PyramidError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        }
    }
}

// A tile of the wrong size is reported as such, not drawn as garbage.
TEST(PyramidCheck, ReportsATileOfTheWrongSize) {
    TempFile f("pyramid_wrong_size.gpkg");
    buildPyramid(smallScene(), f.path, smallParams(), false, nullptr);
    {
        SqliteDb db(f.path, SqliteDb::Mode::ReadWrite);
        // Level 1's tile (0, 0) given level 0's bytes moved down: the right format, the right size;
        // then a tile of the appearance replaced by one of the elevation (another size and bands).
        db.exec(std::string("UPDATE ") + kAppearanceTable + " SET tile_data = (SELECT tile_data FROM " + kElevationTable +
                " WHERE zoom_level = 0) WHERE zoom_level = 1 AND tile_column = 0 AND tile_row = 0");
    }
    const PyramidCheck c = checkPyramid(f.path);
    ASSERT_EQ(c.problems.size(), 1u);
    EXPECT_EQ(c.problems[0].table, kAppearanceTable);
    EXPECT_EQ(c.problems[0].quad, (PyramidKey{1, 0, 1}));
}

}  // namespace
}  // namespace lacet
