// The pyramid's file (pyramid/pyramid_store.h): tiles, elevation statistics and quad digests round
// trip with GeoPackage's row order; a transaction rolled back leaves nothing; and every failure is a
// PyramidError naming the file: not a GeoPackage, a lacet_pyramid table missing a key, of a later
// format or with impossible levels, a write to a file opened read-only.
#include <fstream>
#include <initializer_list>
#include <string>

#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {

PyramidInfo smallInfo() {
    PyramidInfo i;
    i.minLevel = 0;
    i.maxLevel = 3;
    i.vectorLevel = 2;
    i.tileSize = 16;
    i.elevationSize = 9;
    i.encoding = "png";
    i.extent = {{0.0, 0.0}, {1000.0, 1000.0}};
    i.inputs = 0x0123456789abcdefULL;
    i.sceneChecksum = "cafe";
    return i;
}

// `f()` throws a PyramidError whose message holds every one of `parts`.
template <class F>
void expectPyramidError(F&& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no PyramidError";
    } catch (const PyramidError& e) {
        for (const std::string& p : parts) EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << "\nlacks: " << p;
    }
}

TEST(PyramidStore, TilesDigestsAndInfoRoundTrip) {
    TempFile f("store_round_trip.gpkg");
    const PyramidInfo info = smallInfo();
    {
        PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
        EXPECT_FALSE(s.info());
        s.begin();
        s.create(info);
        const std::vector<std::uint8_t> a = {1, 2, 3}, b = {4, 5};
        EXPECT_TRUE(s.putTile(kAppearanceTable, {3, 1, 6}, a));
        EXPECT_FALSE(s.putTile(kAppearanceTable, {3, 1, 6}, a));  // the same bytes: not written again
        EXPECT_TRUE(s.putTile(kAppearanceTable, {3, 1, 6}, b));
        EXPECT_TRUE(s.putTile(kAppearanceTable, {0, 0, 0}, a));
        EXPECT_TRUE(s.putElevation({2, 3, 0}, a, -1.0, 2.0, 0.5, 0.25));
        s.putDigest({3, 1, 6}, 0xfedcba9876543210ULL);
        EXPECT_TRUE(s.removeTile(kAppearanceTable, {0, 0, 0}));
        EXPECT_FALSE(s.removeTile(kAppearanceTable, {0, 0, 0}));
        s.commit();
    }
    PyramidStore s(f.path, PyramidStore::Mode::ReadOnly);
    const std::optional<PyramidInfo> read = s.info();
    ASSERT_TRUE(read);
    EXPECT_EQ(read->maxLevel, 3);
    EXPECT_EQ(read->inputs, info.inputs);
    EXPECT_EQ(read->sceneChecksum, "cafe");
    EXPECT_FALSE(read->complete);
    EXPECT_EQ(s.tile(kAppearanceTable, {3, 1, 6}), (std::vector<std::uint8_t>{4, 5}));
    EXPECT_FALSE(s.tile(kAppearanceTable, {0, 0, 0}));
    EXPECT_EQ(s.tileCount(kAppearanceTable), 1u);
    EXPECT_EQ(s.tileBytes(kAppearanceTable), 2u);
    EXPECT_EQ(s.tileCount(kWaterTable), 0u);
    const auto all = s.allTiles(kAppearanceTable);
    ASSERT_EQ(all.size(), 1u);
    EXPECT_EQ(all[0].first, (PyramidKey{3, 1, 6}));
    // GeoPackage counts rows from the top: quad row 6 of 8 (y grows northwards) is tile_row 1.
    EXPECT_EQ(s.db().queryInteger(std::string("SELECT tile_row FROM ") + kAppearanceTable), 1);
    EXPECT_EQ(s.db().queryInteger("SELECT max FROM gpkg_2d_gridded_tile_ancillary"), 2);
    const QuadDigestMap d = s.digests();
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d.at({3, 1, 6}), 0xfedcba9876543210ULL);
}

TEST(PyramidStore, ARolledBackTransactionLeavesNothing) {
    TempFile f("store_rollback.gpkg");
    PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
    s.begin();
    s.create(smallInfo());
    s.commit();
    s.begin();
    s.putTile(kAppearanceTable, {1, 0, 0}, std::vector<std::uint8_t>{9});
    s.putDigest({1, 0, 0}, 5);
    s.rollback();
    s.rollback();  // quiet without a transaction
    EXPECT_EQ(s.tileCount(kAppearanceTable), 0u);
    EXPECT_TRUE(s.digests().empty());
}

TEST(PyramidStore, AFileThatIsNotAGeoPackageIsRefusedByName) {
    TempFile f("store_text.gpkg");
    { std::ofstream(f.path) << "my notes, not a pyramid\n"; }
    expectPyramidError([&] { PyramidStore s(f.path, PyramidStore::Mode::ReadOnly); }, {f.path});
    expectPyramidError([&] { PyramidStore s(f.path, PyramidStore::Mode::ReadWrite); }, {f.path});
    EXPECT_FALSE(isPyramidFile(f.path));
    EXPECT_FALSE(isPyramidFile(f.path + ".missing"));
    EXPECT_FALSE(isPyramidFile(std::filesystem::path(f.path).parent_path().string()));  // a directory
    expectPyramidError([&] { PyramidStore s(f.path + ".missing", PyramidStore::Mode::ReadOnly); }, {f.path + ".missing"});
}

TEST(PyramidStore, ABrokenInfoTableIsRefusedByNameAndReason) {
    TempFile f("store_info.gpkg");
    {
        PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
        s.begin();
        s.create(smallInfo());
        s.commit();
    }
    const auto withInfo = [&](const std::string& sql, std::initializer_list<std::string> parts) {
        SCOPED_TRACE(sql);
        PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
        s.begin();
        s.db().exec(sql);
        expectPyramidError([&] { s.info(); }, parts);
        s.rollback();
    };
    withInfo("DELETE FROM lacet_pyramid WHERE key = 'max_level'", {f.path, "max_level"});
    withInfo("UPDATE lacet_pyramid SET value = '99' WHERE key = 'format_version'", {f.path, "later"});
    withInfo("UPDATE lacet_pyramid SET value = '31' WHERE key = 'max_level'", {f.path, "impossible levels"});
    withInfo("UPDATE lacet_pyramid SET value = '-2' WHERE key = 'tile_size'", {f.path, "impossible"});
    withInfo("UPDATE lacet_pyramid SET value = 'many' WHERE key = 'min_level'", {f.path, "unreadable"});
    // And the table itself gone: no pyramid, not an error.
    PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
    s.db().exec("DROP TABLE lacet_pyramid");
    EXPECT_FALSE(s.info());
    EXPECT_FALSE(isPyramidFile(f.path));
}

// A tile row at a place no pyramid has (fuzz finding: a zoom level of 64 was shifted by, undefined
// behaviour) is refused naming the file and the place, by the store and by lacet info's check.
TEST(PyramidStore, ATileAtAnImpossiblePlaceIsRefusedByName) {
    TempFile built("store_impossible_built.gpkg"), f("store_impossible_tile.gpkg");
    buildPyramid(smallScene(), built.path, smallParams(), false, nullptr);
    for (const char* place : {"zoom_level = 64", "zoom_level = -1", "tile_column = 1000000", "tile_row = -5"}) {
        SCOPED_TRACE(place);
        std::filesystem::copy_file(built.path, f.path, std::filesystem::copy_options::overwrite_existing);
        {
            SqliteDb db(f.path, SqliteDb::Mode::ReadWrite);
            db.exec(std::string("UPDATE ") + kAppearanceTable + " SET " + place + " WHERE zoom_level = 1 AND tile_column = 0 AND tile_row = 0");
        }
        PyramidStore s(f.path, PyramidStore::Mode::ReadOnly);
        expectPyramidError([&] { s.allTiles(kAppearanceTable); }, {f.path, "impossible place"});
        expectPyramidError([&] { checkPyramid(f.path); }, {f.path, "impossible place"});
    }
}

TEST(PyramidStore, AWriteToAFileOpenedReadOnlyIsRefusedByName) {
    TempFile f("store_read_only.gpkg");
    {
        PyramidStore s(f.path, PyramidStore::Mode::ReadWrite);
        s.begin();
        s.create(smallInfo());
        s.commit();
    }
    PyramidStore s(f.path, PyramidStore::Mode::ReadOnly);
    expectPyramidError([&] { s.putTile(kAppearanceTable, {0, 0, 0}, std::vector<std::uint8_t>{1}); }, {f.path, "readonly"});
    expectPyramidError([&] { s.putDigest({0, 0, 0}, 1); }, {f.path});
    expectPyramidError([&] { s.begin(), s.create(smallInfo()); }, {f.path});
    s.rollback();
    EXPECT_EQ(s.tileCount(kAppearanceTable), 0u);
}

// A pyramid added to a GeoPackage that has custom CRSs of its own takes a new id and leaves
// theirs alone; built again, it reuses its own.
TEST(PyramidStore, TheScenesCrsTakesAFreeIdAndLeavesOthersAlone) {
    SceneDocument doc = smallScene();
    doc.georeference.valid = true;
    doc.georeference.crsWkt = "LOCAL_CS[\"Lacet test scene\",LOCAL_DATUM[\"none\",32767],UNIT[\"metre\",1]]";
    TempFile f("pyramid_srs.gpkg");
    {
        PyramidStore created(f.path, PyramidStore::Mode::ReadWrite);  // a new, empty GeoPackage
        created.db().exec("INSERT INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, "
                          "definition) VALUES ('a', 100000, 'NONE', 100000, 'LOCAL_CS[\"a\"]'), ('b', 100001, 'NONE', "
                          "100001, 'LOCAL_CS[\"b\"]')");
    }
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    buildPyramid(doc, f.path, smallParams(), false, nullptr);
    SqliteDb db(f.path, SqliteDb::Mode::ReadOnly);
    EXPECT_EQ(db.queryInteger(std::string("SELECT srs_id FROM gpkg_tile_matrix_set WHERE table_name = '") + kAppearanceTable + "'"),
              100002);
    EXPECT_EQ(db.queryText("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = 100000"), "LOCAL_CS[\"a\"]");
    EXPECT_EQ(db.queryText("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = 100001"), "LOCAL_CS[\"b\"]");
    EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_spatial_ref_sys WHERE srs_id >= 100000"), 3);
}

}  // namespace
}  // namespace lacet
