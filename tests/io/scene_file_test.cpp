#include "io/scene_file.h"

#include <sqlite3.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "io/gpkg_dem.h"
#include "model/validate.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// ---- fixtures ----

// A fresh directory per test, removed afterwards.
class SceneFile : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("lacet_scene_file_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir_, ec);
    }
    std::string file(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

const char* const kWkt =
    "PROJCS[\"Lacet TM\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
    "PARAMETER[\"latitude_of_origin\",42.5],PARAMETER[\"central_meridian\",1.5],PARAMETER[\"scale_factor\",1],"
    "PARAMETER[\"false_easting\",0],PARAMETER[\"false_northing\",0],UNIT[\"metre\",1]]";

float nanWithPayload(std::uint32_t payload) { return std::bit_cast<float>(0x7fc00000u | payload); }

// Two layers; curves with line, quadratic and cubic pieces; a closed curve; an area with a hole and
// an axial curve; a deleted curve and a deleted node keeping their slots (with values only a dead
// slot may hold: NaN coordinates and widths); -0.0 where a valid scene may have it.
Scene handScene() {
    Scene s;
    s.extent = {{0.0, 0.0}, {1000.0, 1000.0}};
    s.layers.resize(2);

    Layer& roads = s.layers[0];
    roads.name = "roads \xc3\xa9t\xc3\xa9";  // UTF-8
    roads.kind = LayerKind::Roads;
    const ElementId a = roads.addNode({-0.0, 100.0}), b = roads.addNode({400.25, 100.0 / 3.0}),
                    c = roads.addNode({700.0, 650.0}), d = roads.addNode({999.999999, 1e-300});
    Curve line;
    line.vertices = {{{-0.0, 100.0}}, {{400.25, 100.0 / 3.0}}};
    line.start = a;
    line.end = b;
    line.w = -0.0f;
    line.wf = 0.1f;
    line.cls = 2;
    line.flags = kBridge;
    roads.addCurve(line);
    Curve quad;
    quad.vertices = {{{400.25, 100.0 / 3.0}}, {{550.0, 500.0}, false}, {{700.0, 650.0}}};
    quad.start = b;
    quad.end = c;
    quad.w = 6.5f;
    quad.wf = 14.0f / 3.0f + 10.0f;
    quad.cls = 65535;
    quad.flags = kBridge | kTunnel;
    roads.addCurve(quad);
    Curve mixed;  // a cubic piece then a quadratic piece then a line, one vertex marked closing
    mixed.vertices = {{{700.0, 650.0}},         {{750.0, 700.0}, false}, {{800.0, 600.0}, false},
                      {{850.0, 640.0}, true, true}, {{900.0, 500.0}, false}, {{950.0, 300.0}},
                      {{999.999999, 1e-300}}};
    mixed.start = c;
    mixed.end = d;
    mixed.w = 3.0f;
    mixed.wf = 7.0f;
    roads.addCurve(mixed);
    Curve dead;  // deleted: keeps its slot and whatever it held
    dead.vertices = {{{1.0, 2.0}}, {{std::nan("7"), -0.0}, false}, {{3.0, 4.0}}};
    dead.start = a;
    dead.end = d;
    dead.w = nanWithPayload(0x1234);
    dead.wf = -std::numeric_limits<float>::infinity();
    const ElementId deadId = roads.addCurve(dead);
    roads.curves[deadId].alive = false;
    std::erase(roads.nodes[a].curves, deadId);
    std::erase(roads.nodes[d].curves, deadId);
    const ElementId deadNode = roads.addNode({std::nan("42"), -0.0});
    roads.nodes[deadNode].alive = false;
    roads.nodes[deadNode].curves = {7, 0x80000003u};
    Curve after;  // a curve after the dead slot, so ids past it matter
    after.vertices = {{{700.0, 650.0}}, {{400.25, 100.0 / 3.0}}};
    after.start = c;
    after.end = b;
    after.w = 1.0f;
    after.wf = 1.0f;
    roads.addCurve(after);

    Layer& lakes = s.layers[1];
    lakes.name = "lakes";
    lakes.kind = LayerKind::Lakes;
    const ElementId p = lakes.addNode({100.0, 100.0}), q = lakes.addNode({500.0, 100.0}),
                    h = lakes.addNode({300.0, 200.0}), x0 = lakes.addNode({150.0, 120.0}),
                    x1 = lakes.addNode({450.0, 140.0});
    Curve south;
    south.vertices = {{{100.0, 100.0}}, {{300.0, 0.0}, false}, {{500.0, 100.0}}};
    south.start = p;
    south.end = q;
    south.wf = 2.0f;
    const ElementId cs = lakes.addCurve(south);
    Curve north;
    north.vertices = {{{500.0, 100.0}}, {{450.0, 400.0}, false}, {{150.0, 400.0}, false}, {{100.0, 100.0}}};
    north.start = q;
    north.end = p;
    north.wf = 2.0f;
    const ElementId cn = lakes.addCurve(north);
    Curve island;  // closed: starts and ends at h
    island.vertices = {{{300.0, 200.0}}, {{350.0, 250.0}, false}, {{250.0, 250.0}, false}, {{300.0, 200.0}}};
    island.start = h;
    island.end = h;
    island.wf = 1.0f;
    const ElementId ci = lakes.addCurve(island);
    Curve axis;
    axis.vertices = {{{150.0, 120.0}}, {{450.0, 140.0}}};
    axis.start = x0;
    axis.end = x1;
    const ElementId ca = lakes.addCurve(axis);
    Area lake;
    lake.loops = {{{cs, false}, {cn, false}}, {{ci, true}}};
    lake.wf = 5.5f;
    lake.cls = 9;
    lake.axial = ca;
    lakes.addArea(lake);
    Area gone;  // deleted area: its curves no longer list it
    gone.loops = {{{cs, true}}};
    gone.wf = -0.0f;
    gone.alive = false;
    lakes.areas.push_back(gone);
    return s;
}

Dem handDem() {
    const int w = 7, h = 5;
    std::vector<float> z(std::size_t(w * h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) z[std::size_t(j * w + i)] = float(j * 100 + i) + 0.1f * float(i) - 50.0f;
    z[0] = -0.0f;
    z[1] = std::numeric_limits<float>::denorm_min();
    z[2] = std::numeric_limits<float>::max();
    z[3] = -std::numeric_limits<float>::max();
    z[4] = 1e-30f;
    return Dem({{-10.5, 20.25}, {1010.5, 1000.0 / 3.0}}, w, h, std::move(z));
}

SceneDocument handDocument(bool withDem) {
    SceneDocument doc;
    doc.scene = handScene();
    doc.georeference.valid = true;
    doc.georeference.lon0 = 1.5;
    doc.georeference.lat0 = 42.5;
    doc.georeference.originShift = {12345.678901234567, -0.0};
    doc.georeference.crsWkt = kWkt;
    if (withDem) doc.dem = handDem();
    return doc;
}

// A DEM over the scene's extent, smooth, with a height pattern that differs along x and y.
Dem demOver(const Box& extent, int w, int h) {
    std::vector<float> z(std::size_t(w) * std::size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            z[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                float(100.0 + 30.0 * std::sin(0.3 * i) * std::cos(0.17 * j) + 0.5 * j);
    return Dem(extent, w, h, std::move(z));
}

const SceneDocument& syntheticDocument() {
    static const SceneDocument doc = [] {
        SceneDocument d;
        d.scene = makeSyntheticScene({1, 3000});
        d.dem = demOver(d.scene.extent, 150, 120);
        return d;
    }();
    return doc;
}

// ---- comparisons ----

bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool sameBits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
bool sameBits(Vec2 a, Vec2 b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y); }
bool sameBits(const Box& a, const Box& b) { return sameBits(a.min, b.min) && sameBits(a.max, b.max); }

// Every field, doubles and floats by bit pattern; names the first difference.
::testing::AssertionResult identical(const SceneDocument& x, const SceneDocument& y) {
    auto differ = [](const std::string& what) { return ::testing::AssertionFailure() << what << " differs"; };
    const Scene& a = x.scene;
    const Scene& b = y.scene;
    if (!sameBits(a.extent, b.extent)) return differ("extent");
    if (a.layers.size() != b.layers.size()) return differ("layer count");
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer& p = a.layers[l];
        const Layer& q = b.layers[l];
        const std::string at = "layer " + std::to_string(l) + " ";
        if (p.name != q.name || p.kind != q.kind) return differ(at + "name or kind");
        if (p.nodes.size() != q.nodes.size() || p.curves.size() != q.curves.size() || p.areas.size() != q.areas.size())
            return differ(at + "element count");
        for (std::size_t i = 0; i < p.nodes.size(); ++i)
            if (!sameBits(p.nodes[i].p, q.nodes[i].p) || p.nodes[i].curves != q.nodes[i].curves ||
                p.nodes[i].alive != q.nodes[i].alive || !sameBits(p.nodes[i].roundabout, q.nodes[i].roundabout))
                return differ(at + "node " + std::to_string(i));
        for (std::size_t i = 0; i < p.curves.size(); ++i) {
            const Curve& c = p.curves[i];
            const Curve& d = q.curves[i];
            bool same = c.start == d.start && c.end == d.end && sameBits(c.w, d.w) && sameBits(c.wf, d.wf) &&
                        c.cls == d.cls && c.flags == d.flags && c.areas == d.areas && c.alive == d.alive &&
                        c.vertices.size() == d.vertices.size();
            for (std::size_t k = 0; same && k < c.vertices.size(); ++k)
                same = sameBits(c.vertices[k].p, d.vertices[k].p) && c.vertices[k].onCurve == d.vertices[k].onCurve &&
                       c.vertices[k].closing == d.vertices[k].closing;
            if (!same) return differ(at + "curve " + std::to_string(i));
        }
        for (std::size_t i = 0; i < p.areas.size(); ++i) {
            const Area& c = p.areas[i];
            const Area& d = q.areas[i];
            if (c.loops != d.loops || !sameBits(c.wf, d.wf) || c.cls != d.cls || c.axial != d.axial || c.alive != d.alive)
                return differ(at + "area " + std::to_string(i));
        }
    }
    const Georeference& g = x.georeference;
    const Georeference& h = y.georeference;
    if (g.valid != h.valid || !sameBits(g.lon0, h.lon0) || !sameBits(g.lat0, h.lat0) ||
        !sameBits(g.originShift, h.originShift) || g.crsWkt != h.crsWkt)
        return differ("georeference");
    if (x.dem.has_value() != y.dem.has_value()) return differ("DEM presence");
    if (x.dem) {
        if (!sameBits(x.dem->extent(), y.dem->extent()) || x.dem->width() != y.dem->width() ||
            x.dem->height() != y.dem->height())
            return differ("DEM grid");
        for (std::size_t k = 0; k < x.dem->heights().size(); ++k)
            if (!sameBits(x.dem->heights()[k], y.dem->heights()[k])) return differ("DEM height " + std::to_string(k));
    }
    return ::testing::AssertionSuccess();
}

// ---- file helpers ----

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

// Runs SQL on a file (for the tests that damage one, and to read tables back).
void execSql(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* message = nullptr;
    const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
    EXPECT_EQ(rc, SQLITE_OK) << (message ? message : "");
    sqlite3_free(message);
    sqlite3_close(db);
}

// The rows of `query`, each value with its type, as text.
std::string dumpQuery(const std::string& path, const std::string& query) {
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
    sqlite3_stmt* s = nullptr;
    std::ostringstream out;
    if (sqlite3_prepare_v2(db, query.c_str(), -1, &s, nullptr) != SQLITE_OK) {
        out << "cannot prepare " << query << ": " << sqlite3_errmsg(db);
    } else {
        while (sqlite3_step(s) == SQLITE_ROW) {
            for (int c = 0; c < sqlite3_column_count(s); ++c) {
                const int t = sqlite3_column_type(s, c);
                out << t << ':';
                if (t == SQLITE_FLOAT) {
                    out << std::bit_cast<std::uint64_t>(sqlite3_column_double(s, c));
                } else if (t == SQLITE_INTEGER) {
                    out << sqlite3_column_int64(s, c);
                } else if (t == SQLITE_TEXT || t == SQLITE_BLOB) {
                    const auto* p = static_cast<const char*>(sqlite3_column_blob(s, c));
                    out << std::string(p ? p : "", std::size_t(sqlite3_column_bytes(s, c)));
                }
                out << '|';
            }
            out << '\n';
        }
    }
    sqlite3_finalize(s);
    sqlite3_close(db);
    return out.str();
}

std::string dumpTables(const std::string& path) {
    std::string out;
    for (const char* table : {"lacet_meta", "lacet_layers", "lacet_nodes", "lacet_curves", "lacet_areas", "lacet_attributes", "dem",
                              "gpkg_tile_matrix_set", "gpkg_tile_matrix", "gpkg_2d_gridded_coverage_ancillary",
                              "gpkg_2d_gridded_tile_ancillary", "gpkg_spatial_ref_sys"})
        out += std::string("== ") + table + "\n" + dumpQuery(path, std::string("SELECT * FROM ") + table + " ORDER BY 1");
    out += "== contents\n" + dumpQuery(path, "SELECT table_name, data_type, identifier, description, min_x, min_y, "
                                             "max_x, max_y, srs_id FROM gpkg_contents ORDER BY 1");
    return out;
}

// Asserts that `f` throws SceneFileError whose message names `path` and contains `reason`.
template <class F>
void expectSceneFileError(F&& f, const std::string& path, const std::string& reason) {
    try {
        f();
        ADD_FAILURE() << "no SceneFileError for " << path << " (expected '" << reason << "')";
    } catch (const SceneFileError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        EXPECT_NE(what.find(reason), std::string::npos) << "expected '" << reason << "' in: " << what;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "another exception for " << path << ": " << e.what();
    }
}

bool onPath(const char* tool) { return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0; }

// Output and exit status of a shell command.
std::pair<int, std::string> runCommand(const std::string& command) {
    std::string output;
    FILE* p = ::popen((command + " 2>&1").c_str(), "r");
    if (!p) return {-1, ""};
    char buf[4096];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
    const int status = ::pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// ---- tests ----

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

TEST_F(SceneFile, ATemporaryPathThatCannotBeWrittenLeavesThePreviousFile) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true));
    const std::string before = readBytes(path);
    fs::create_directories(path + ".tmp/occupied");  // the temporary file cannot be removed nor created
    expectSceneFileError([&] { saveScene(path, syntheticDocument()); }, path, "cannot remove the stale temporary file");
    EXPECT_EQ(readBytes(path), before);
    EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    EXPECT_TRUE(fs::is_directory(path + ".tmp/occupied"));  // not ours: left alone
}

// Writes fail past `limit` bytes per file while alive (RLIMIT_FSIZE, SIGXFSZ ignored), as on a full disk.
class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t limit) {
        previousHandler_ = std::signal(SIGXFSZ, SIG_IGN);
        ::getrlimit(RLIMIT_FSIZE, &previous_);
        rlimit r = previous_;
        r.rlim_cur = limit;
        ok_ = ::setrlimit(RLIMIT_FSIZE, &r) == 0;
    }
    ~FileSizeLimit() {
        ::setrlimit(RLIMIT_FSIZE, &previous_);
        std::signal(SIGXFSZ, previousHandler_);
    }
    bool ok() const { return ok_; }

private:
    rlimit previous_{};
    void (*previousHandler_)(int) = nullptr;
    bool ok_ = false;
};

TEST_F(SceneFile, AWriteFailingMidwayLeavesThePreviousFile) {
    const std::string path = file("scene.gpkg");
    const SceneDocument& big = syntheticDocument();
    saveScene(path, handDocument(true));
    const std::string before = readBytes(path);
    // Size of the file once GDAL has written the DEM, before the SQLite part: a limit a little
    // above it fails inside the SQLite transaction, one below it inside GDAL.
    const std::string probe = file("probe.gpkg");
    createGpkgWithDem(probe, *big.dem, "");
    const auto rasterOnly = fs::file_size(probe);
    for (const rlim_t limit : {rlim_t(rasterOnly / 2), rlim_t(rasterOnly + 64 * 1024)}) {
        SCOPED_TRACE("file size limit " + std::to_string(limit) + " bytes (DEM-only file " + std::to_string(rasterOnly) +
                     ")");
        {
            FileSizeLimit fsl(limit);
            ASSERT_TRUE(fsl.ok());
            expectSceneFileError([&] { saveScene(path, big); }, path, "cannot save");
        }
        EXPECT_EQ(readBytes(path), before);
        EXPECT_FALSE(fs::exists(path + ".tmp"));
        EXPECT_FALSE(fs::exists(path + ".tmp-journal"));
        EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    }
    saveScene(path, big);  // and a save with room to write succeeds
    EXPECT_TRUE(identical(loadScene(path), big));
}

TEST_F(SceneFile, AFailedRenameRemovesTheTemporaryFile) {
    const std::string path = file("scene.gpkg");
    fs::create_directories(path + "/occupied");  // the final rename cannot replace a directory
    expectSceneFileError([&] { saveScene(path, handDocument(true)); }, path, "cannot rename");
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_TRUE(fs::is_directory(path + "/occupied"));
}

TEST_F(SceneFile, AnInvalidSceneIsNotSaved) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(false));
    const std::string before = readBytes(path);
    SceneDocument bad = handDocument(false);
    bad.scene.layers[0].curves[0].vertices[0].p.x = 5.0;  // no longer at its start node
    expectSceneFileError([&] { saveScene(path, bad); }, path, "invalid scene");
    EXPECT_EQ(readBytes(path), before);
}

TEST_F(SceneFile, AStaleTemporaryFileAndJournalAreReplaced) {
    const std::string path = file("scene.gpkg");
    writeBytes(path + ".tmp", "half a scene");
    writeBytes(path + ".tmp-journal", std::string(4096, '\x5a'));
    saveScene(path, handDocument(true));
    EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_FALSE(fs::exists(path + ".tmp-journal"));
}

TEST_F(SceneFile, MissingEmptyAndForeignFilesAreRefused) {
    const std::string missing = file("missing.gpkg");
    expectSceneFileError([&] { loadScene(missing); }, missing, "No such file");
    const std::string empty = file("empty.gpkg");
    writeBytes(empty, "");
    expectSceneFileError([&] { loadScene(empty); }, empty, "empty file");
    const std::string text = file("text.gpkg");
    writeBytes(text, std::string(10000, 'x'));
    expectSceneFileError([&] { loadScene(text); }, text, "not a GeoPackage");
    expectSceneFileError([&] { loadScene(dir_.string()); }, dir_.string(), "is a directory");
    const std::string sqlite = file("plain.sqlite");
    execSql(sqlite, "CREATE TABLE t (a); INSERT INTO t VALUES (1)");
    expectSceneFileError([&] { loadScene(sqlite); }, sqlite, "not a GeoPackage");
    const std::string gpkg = file("other.gpkg");
    createEmptyGpkg(gpkg);
    expectSceneFileError([&] { loadScene(gpkg); }, gpkg, "not a Lacet scene");
}

TEST_F(SceneFile, TruncatedFilesAreRefused) {
    const std::string path = file("scene.gpkg");
    saveScene(path, syntheticDocument());
    const std::string bytes = readBytes(path);
    ASSERT_GT(bytes.size(), 65536u);
    for (const std::size_t size : {std::size_t(1), std::size_t(50), std::size_t(100), std::size_t(1024),
                                   std::size_t(4096), std::size_t(4097), bytes.size() / 3, bytes.size() / 2,
                                   bytes.size() - 4096, bytes.size() - 1}) {
        const std::string cut = file("cut_" + std::to_string(size) + ".gpkg");
        writeBytes(cut, bytes.substr(0, size));
        try {
            loadScene(cut);
            ADD_FAILURE() << "a copy truncated to " << size << " bytes of " << bytes.size() << " loaded";
        } catch (const SceneFileError& e) {
            EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
        }
    }
}

TEST_F(SceneFile, DamagedContentsAreRefused) {
    const std::string good = file("good.gpkg");
    saveScene(good, handDocument(true));
    auto damaged = [&](const std::string& name, const std::string& sql, const std::string& reason) {
        SCOPED_TRACE(name);
        const std::string path = file(name + ".gpkg");
        fs::copy_file(good, path);
        execSql(path, sql);
        expectSceneFileError([&] { loadScene(path); }, path, reason);
    };
    damaged("vertices_length", "UPDATE lacet_curves SET vertices = zeroblob(33) WHERE layer = 0 AND id = 1",
            "lacet_curves row (layer 0, id 1): vertices blob of 33 bytes, not a multiple of 17");
    damaged("vertices_odd_length",
            "UPDATE lacet_curves SET vertices = CAST(zeroblob(34) || x'07' AS BLOB) WHERE layer = 0 AND id = 1",
            "not a multiple of 17");
    damaged("vertex_flag_bits",
            "UPDATE lacet_curves SET vertices = CAST(substr(vertices, 1, length(vertices) - 1) || x'09' AS BLOB) "
            "WHERE layer = 0 AND id = 1",
            "unknown flag bits");
    damaged("areas_blob", "UPDATE lacet_curves SET areas = x'010203' WHERE layer = 1 AND id = 0", "not a multiple of 4");
    damaged("loops_blob", "UPDATE lacet_areas SET loops = x'05000000' WHERE layer = 1 AND id = 0", "loops blob is truncated");
    damaged("loops_count", "UPDATE lacet_areas SET loops = x'ffffffff01000000' WHERE layer = 1 AND id = 0",
            "loops blob is truncated");
    damaged("node_text", "UPDATE lacet_nodes SET x = 'east' WHERE layer = 1 AND id = 1", "x is not a number");
    damaged("missing_id", "DELETE FROM lacet_curves WHERE layer = 0 AND id = 2", "ids are not 0, 1, 2");
    damaged("unknown_layer", "UPDATE lacet_nodes SET layer = 7 WHERE layer = 1 AND id = 4", "layer = 7 is out of range");
    damaged("roundabout_negative", "UPDATE lacet_nodes SET roundabout = -2 WHERE layer = 0 AND id = 1",
            "roundabout is not a finite radius >= 0");
    damaged("roundabout_text", "UPDATE lacet_nodes SET roundabout = 'big' WHERE layer = 0 AND id = 1",
            "roundabout is not a number");
    damaged("width_not_float", "UPDATE lacet_curves SET w = 0.1 WHERE layer = 0 AND id = 1", "w is not a 32-bit float");
    damaged("kind", "UPDATE lacet_layers SET kind = 'glaciers' WHERE id = 1", "unknown layer kind 'glaciers'");
    damaged("no_meta", "DROP TABLE lacet_meta", "not a Lacet scene");
    damaged("no_curves", "DROP TABLE lacet_curves", "no lacet_curves table");
    damaged("version", "UPDATE lacet_meta SET value = '3' WHERE key = 'format_version'", "format version 3");
    damaged("extent", "UPDATE lacet_meta SET value = '12.5' WHERE key = 'extent_max_x'", "is not a hex float");
    damaged("dem_size", "UPDATE lacet_meta SET value = '8' WHERE key = 'dem_width'", "the DEM raster is 7 x 5");
    damaged("dem_tiles", "DELETE FROM dem", "corrupt DEM: raster table 'dem' holds 0 of its 1 tiles");
    damaged("dem_tile_data", "UPDATE dem SET tile_data = zeroblob(100)", "cannot read the DEM raster");
    damaged("model", "UPDATE lacet_nodes SET x = x + 1 WHERE layer = 1 AND id = 0", "invalid scene");
    damaged("application_id", "PRAGMA application_id = 0", "not a GeoPackage");
    // Changes that leave a valid scene: only the checksum tells.
    damaged("class", "UPDATE lacet_curves SET cls = 3 WHERE layer = 0 AND id = 0", "do not match their checksum");
    damaged("dead_slot", "UPDATE lacet_curves SET cls = 1 WHERE layer = 0 AND id = 3", "do not match their checksum");
    damaged("first_vertex",
            "UPDATE lacet_curves SET vertices = CAST(x'0000000000c08240' || substr(vertices, 9) AS BLOB) "
            "WHERE layer = 1 AND id = 0",
            "invalid scene");
    damaged("control_point",
            "UPDATE lacet_curves SET vertices = "
            "CAST(substr(vertices, 1, 16) || x'0000000000c08240' || substr(vertices, 25) AS BLOB) "
            "WHERE layer = 1 AND id = 0",
            "do not match their checksum");
    damaged("georeference", "UPDATE lacet_meta SET value = '0x1p+0' WHERE key = 'georeference_lon0'",
            "do not match their checksum");
    damaged("no_checksum", "DELETE FROM lacet_meta WHERE key = 'checksum'", "lacet_meta has no 'checksum'");
}

TEST_F(SceneFile, OverwrittenBytesAreRefusedWithoutACrash) {
    // 512 bytes of garbage at 23 places: refused (by SQLite's quick_check, the checks of every value or
    // the checksum), or, where it fell on unused space, the scene saved.
    const std::string good = file("good.gpkg");
    saveScene(good, syntheticDocument());
    const std::string bytes = readBytes(good);
    int refused = 0, loaded = 0;
    for (std::size_t at = 4096; at + 4096 <= bytes.size(); at += bytes.size() / 23) {
        std::string copy = bytes;
        for (std::size_t k = 0; k < 512; ++k) copy[at + k] = char((k * 131 + at) & 0xff);
        const std::string path = file("garbage.gpkg");
        writeBytes(path, copy);
        try {
            // Garbage over unused space: what loads is then the scene saved, bit for bit (the checksum).
            EXPECT_TRUE(identical(loadScene(path), syntheticDocument())) << "garbage at byte " << at;
            ++loaded;
        } catch (const SceneFileError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            ++refused;
        }
    }
    std::printf("[ figures ] overwritten pages: %d refused, %d loaded\n", refused, loaded);
    EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// A child process saves over the file in a loop and is killed (SIGKILL) at varying moments: the
// file at the path always opens and holds one of the two scenes, whole.
TEST_F(SceneFile, KillingTheProcessDuringASaveLeavesAWholeScene) {
    const SceneDocument& big = syntheticDocument();
    const SceneDocument small = handDocument(true);
    const std::string path = file("killed.gpkg");
    saveScene(path, small);
    int sawOld = 0, sawNew = 0;
    for (int delayMs : {1, 5, 12, 25, 50, 100, 200}) {
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            for (;;) saveScene(path, big);  // killed from outside
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
        ::kill(child, SIGKILL);
        int status = 0;
        ::waitpid(child, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status));
        const SceneDocument loaded = loadScene(path);
        const bool isOld = identical(loaded, small), isNew = identical(loaded, big);
        EXPECT_TRUE(isOld || isNew) << "after a kill at " << delayMs << " ms";
        sawOld += isOld;
        sawNew += isNew;
    }
    std::printf("[ figures ] killed saves: %d left the old scene, %d the new one, 0 a broken file\n", sawOld, sawNew);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

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
