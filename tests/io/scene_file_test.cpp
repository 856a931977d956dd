// The scene file (io/scene_file.h): hand-made and synthetic scenes round-trip exactly (NaN
// payloads, -0.0, dead slots, roundabouts, attributes), saving again gives the same tables, and
// the file is a GeoPackage 1.2 that ogrinfo and gdalinfo open. Its failures:
// scene_file_failure_test.cpp.
#include "tests/io/scene_file_fixture.h"

namespace lacet {
namespace {

TEST_F(SceneFile, HandMadeSceneIsValid) {
    const auto problems = validate(handScene());
    for (const auto& p : problems) ADD_FAILURE() << p.where << ": " << p.reason;
}

TEST_F(SceneFile, RoundTripOfAHandMadeSceneIsExact) {
    const SceneDocument doc = handDocument(true);
    const std::string path = file("hand.gpkg");
    saveScene(path, doc);
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_FALSE(fs::exists(path + ".tmp-journal"));
    EXPECT_TRUE(identical(loadScene(path), doc));
}

TEST_F(SceneFile, RoundTripWithoutDemOrGeoreferenceIsExact) {
    SceneDocument doc = handDocument(false);
    doc.georeference = {};
    doc.georeference.lat0 = std::nan("3");  // meaningless while invalid, kept all the same
    const std::string path = file("nodem.gpkg");
    saveScene(path, doc);
    EXPECT_TRUE(identical(loadScene(path), doc));
}

TEST_F(SceneFile, RoundTripOfRoundaboutRadiiIsExact) {
    SceneDocument doc = handDocument(false);
    doc.scene.layers[0].nodes[1].roundabout = 12.5f;
    doc.scene.layers[0].nodes[2].roundabout = 0.1f;  // not a short decimal in binary
    const std::string path = file("roundabouts.gpkg");
    saveScene(path, doc);
    EXPECT_EQ(dumpQuery(path, "SELECT layer, id FROM lacet_nodes WHERE roundabout != 0 ORDER BY layer, id"),
              "1:0|1:1|\n1:0|1:2|\n");
    const SceneDocument back = loadScene(path);
    EXPECT_TRUE(identical(back, doc));
    EXPECT_EQ(back.scene.layers[0].nodes[2].roundabout, 0.1f);
    // A radius is a part of the checksum: changed behind the program's back, the file is refused.
    execSql(path, "UPDATE lacet_nodes SET roundabout = 13.5 WHERE layer = 0 AND id = 1");
    expectSceneFileError([&] { loadScene(path); }, path, "do not match their checksum");
}

TEST_F(SceneFile, FilesWrittenBeforeRoundaboutsLoadWithoutThem) {
    // A file of the first format has no roundabout column: its nodes load with radius 0, and its
    // checksum (which covered no radius) still matches.
    const SceneDocument doc = handDocument(true);
    const std::string path = file("before.gpkg");
    saveScene(path, doc);
    execSql(path, "DROP INDEX lacet_nodes_roundabout");  // nor its index, made with the column
    execSql(path, "ALTER TABLE lacet_nodes DROP COLUMN roundabout");
    ASSERT_EQ(dumpQuery(path, "SELECT COUNT(*) FROM pragma_table_info('lacet_nodes') WHERE name = 'roundabout'"), "1:0|\n");
    const SceneDocument back = loadScene(path);
    EXPECT_TRUE(identical(back, doc));
    for (const Layer& l : back.scene.layers)
        for (const Node& n : l.nodes) EXPECT_EQ(n.roundabout, 0.0f);
}

TEST_F(SceneFile, RoundTripOfASyntheticSceneIsExact) {
    const SceneDocument& doc = syntheticDocument();
    const std::string path = file("synthetic.gpkg");
    const auto t0 = std::chrono::steady_clock::now();
    saveScene(path, doc);
    const auto t1 = std::chrono::steady_clock::now();
    const SceneDocument loaded = loadScene(path);
    const auto t2 = std::chrono::steady_clock::now();
    EXPECT_TRUE(identical(loaded, doc));
    const SceneCounts n = count(doc.scene);
    const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
    std::printf("[ figures ] scene file, synthetic seed 1, %zu curves, %zu areas, %zu nodes, %zu vertices, DEM %d x %d: "
                "%.1f KiB, save %.1f ms, load %.1f ms\n",
                n.curves, n.areas, n.nodes, n.vertices, doc.dem->width(), doc.dem->height(),
                double(fs::file_size(path)) / 1024.0, ms(t1 - t0), ms(t2 - t1));
}

TEST_F(SceneFile, DemTilesOfZerosAndNegativeZerosAreExact) {
    // 600 x 300 samples: 3 x 2 tiles of 256; the first column of tiles all -0.0, the second all +0.0
    // (GDAL would skip a tile of nodata only).
    const int w = 600, h = 300;
    std::vector<float> z(std::size_t(w * h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) z[std::size_t(j * w + i)] = i < 256 ? -0.0f : i < 512 ? 0.0f : float(i * j) * 0.25f;
    SceneDocument doc = handDocument(false);
    doc.dem = Dem({{0.0, 0.0}, {6000.0, 3000.0}}, w, h, std::move(z));
    const std::string path = file("zeros.gpkg");
    saveScene(path, doc);
    EXPECT_TRUE(identical(loadScene(path), doc));
    EXPECT_EQ(dumpQuery(path, "SELECT count(*) FROM dem"), "1:6|\n");
}

TEST_F(SceneFile, SaveLoadSaveGivesTheSameTables) {
    for (const SceneDocument* doc : {&syntheticDocument(), static_cast<const SceneDocument*>(nullptr)}) {
        const SceneDocument hand = handDocument(true);
        const SceneDocument& d = doc ? *doc : hand;
        const std::string first = file("first.gpkg"), second = file("second.gpkg");
        saveScene(first, d);
        saveScene(second, loadScene(first));
        const std::string a = dumpTables(first), b = dumpTables(second);
        EXPECT_GT(a.size(), 1000u);
        EXPECT_EQ(a.find("cannot"), std::string::npos) << a.substr(0, 2000);
        EXPECT_TRUE(a == b) << "tables differ after save, load, save";
    }
}

TEST_F(SceneFile, IsAGeoPackage12WithAttributeTablesAndAGriddedCoverage) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true));
    EXPECT_EQ(dumpQuery(path, "PRAGMA application_id"), "1:1196444487|\n");  // 0x47504B47 'GPKG'
    EXPECT_EQ(dumpQuery(path, "PRAGMA user_version"), "1:10200|\n");
    EXPECT_EQ(dumpQuery(path, "SELECT table_name, data_type FROM gpkg_contents ORDER BY table_name"),
              "3:dem|3:2d-gridded-coverage|\n3:lacet_areas|3:attributes|\n3:lacet_attributes|3:attributes|\n"
              "3:lacet_curves|3:attributes|\n3:lacet_feature_tables|3:attributes|\n3:lacet_layers|3:attributes|\n"
              "3:lacet_meta|3:attributes|\n3:lacet_nodes|3:attributes|\n3:lakes|3:features|\n3:lakes_lines|3:features|\n"
              "3:roads_t|3:features|\n");  // feature tables and their index: tests/io/scene_features_test.cpp
    EXPECT_EQ(dumpQuery(path, "SELECT datatype FROM gpkg_2d_gridded_coverage_ancillary"), "3:float|\n");
    // -0.0 and NaN, which a REAL column cannot keep, have their exact bytes beside.
    EXPECT_EQ(dumpQuery(path, "SELECT layer, id FROM lacet_nodes WHERE exact IS NOT NULL ORDER BY layer, id"),
              "1:0|1:0|\n1:0|1:4|\n");
    EXPECT_EQ(dumpQuery(path, "SELECT layer, id FROM lacet_curves WHERE exact IS NOT NULL ORDER BY layer, id"),
              "1:0|1:0|\n1:0|1:3|\n");
}

TEST_F(SceneFile, OgrinfoAndGdalinfoOpenTheFile) {
    if (!onPath("ogrinfo") || !onPath("gdalinfo")) GTEST_SKIP() << "ogrinfo or gdalinfo not on PATH";
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true));
    const auto [ogrStatus, ogrOut] = runCommand("ogrinfo -ro -so '" + path + "'");
    EXPECT_EQ(ogrStatus, 0) << ogrOut;
    for (const char* table : {"lacet_meta", "lacet_layers", "lacet_nodes", "lacet_curves", "lacet_areas"})
        EXPECT_NE(ogrOut.find(table), std::string::npos) << ogrOut;
    const auto [ogrCurvesStatus, ogrCurvesOut] = runCommand("ogrinfo -ro -so '" + path + "' lacet_curves");
    EXPECT_EQ(ogrCurvesStatus, 0) << ogrCurvesOut;
    EXPECT_NE(ogrCurvesOut.find("Feature Count: 9"), std::string::npos) << ogrCurvesOut;
    const auto [gdalStatus, gdalOut] = runCommand("gdalinfo '" + path + "'");
    EXPECT_EQ(gdalStatus, 0) << gdalOut;
    EXPECT_NE(gdalOut.find("Size is 7, 5"), std::string::npos) << gdalOut;
    EXPECT_NE(gdalOut.find("Float32"), std::string::npos) << gdalOut;
    EXPECT_NE(gdalOut.find("Transverse Mercator"), std::string::npos) << gdalOut;
    // Without a DEM the file is a vector-only GeoPackage: ogrinfo still opens it.
    const std::string noDem = file("nodem.gpkg");
    saveScene(noDem, handDocument(false));
    const auto [status, out] = runCommand("ogrinfo -ro -so '" + noDem + "'");
    EXPECT_EQ(status, 0) << out;
}

TEST_F(SceneFile, KeptAttributesRoundTripAndMustNameAnElement) {
    SceneDocument doc = handDocument(false);
    doc.attributes = {{0, ElementKind::Curve, 0, "name", "Carretera General 2"},
                      {0, ElementKind::Curve, 0, "bridge", "yes"},
                      {0, ElementKind::Node, 1, "name", "Coll d'Ordino \xc3\xa0"},
                      {0, ElementKind::Curve, 1, "layer", "-1"}};
    const std::string path = file("attributes.gpkg");
    saveScene(path, doc);
    const SceneDocument loaded = loadScene(path);
    EXPECT_TRUE(identical(loaded, doc));
    EXPECT_EQ(loaded.attributes, doc.attributes);
    // An attribute naming a slot that does not exist makes the file corrupt.
    {
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
        ASSERT_EQ(sqlite3_exec(db, "UPDATE lacet_attributes SET id = 999999 WHERE fid = 1", nullptr, nullptr, nullptr), SQLITE_OK);
        sqlite3_close(db);
    }
    expectSceneFileError([&] { loadScene(path); }, path, "lacet_attributes row (layer 0): id = 999999 is out of range");
}

}  // namespace
}  // namespace lacet
