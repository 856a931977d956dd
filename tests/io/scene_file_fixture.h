#pragma once
// What the scene file tests share (tests/io/scene_file_test.cpp: round trips and the format;
// scene_file_failure_test.cpp: failed writes, damaged files, killed saves): a fresh directory per
// test, a hand-made scene and DEM, a synthetic one, and SQL and file helpers.
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
#include "tests/io/scene_identical.h"
#include "tests/io/test_crs.h"

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

inline float nanWithPayload(std::uint32_t payload) { return std::bit_cast<float>(0x7fc00000u | payload); }

// Two layers; curves with line, quadratic and cubic pieces; a closed curve; an area with a hole and
// an axial curve; a deleted curve and a deleted node keeping their slots (with values only a dead
// slot may hold: NaN coordinates and widths); -0.0 where a valid scene may have it.
inline Scene handScene() {
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

inline Dem handDem() {
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

inline SceneDocument handDocument(bool withDem) {
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
inline Dem demOver(const Box& extent, int w, int h) {
    std::vector<float> z(std::size_t(w) * std::size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            z[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                float(100.0 + 30.0 * std::sin(0.3 * i) * std::cos(0.17 * j) + 0.5 * j);
    return Dem(extent, w, h, std::move(z));
}

inline const SceneDocument& syntheticDocument() {
    static const SceneDocument doc = [] {
        SceneDocument d;
        d.scene = makeSyntheticScene({1, 3000});
        d.dem = demOver(d.scene.extent, 150, 120);
        return d;
    }();
    return doc;
}

// ---- comparisons ----

// ---- file helpers ----

inline std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
}

// Runs SQL on a file (for the tests that damage one, and to read tables back).
inline void execSql(const std::string& path, const std::string& sql) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* message = nullptr;
    const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
    EXPECT_EQ(rc, SQLITE_OK) << (message ? message : "");
    sqlite3_free(message);
    sqlite3_close(db);
}

// The rows of `query`, each value with its type, as text.
inline std::string dumpQuery(const std::string& path, const std::string& query) {
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

inline std::string dumpTables(const std::string& path) {
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

inline bool onPath(const char* tool) { return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0; }

// Output and exit status of a shell command.
inline std::pair<int, std::string> runCommand(const std::string& command) {
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

}  // namespace
}  // namespace lacet
