// `lacet import` on bad input (issue 12), through the binary: each case builds its bad input in a
// scratch folder, puts a good scene (written by a successful import of tests/data/vectors/
// good.geojson over the fixture DEM) at --out, or the file that --out wrongly names, runs the
// import and checks that it fails clearly and destroys nothing:
//  - the exit code is non-zero, and neither a signal (a crash) nor the 120 s timeout (a hang);
//  - the message (stderr, then stdout) names the offending path or option and says the reason;
//  - every file the import must leave alone (the good scene at --out, an input given as --out, a
//    text file at --out) keeps its bytes, and no <out>.tmp is left behind.
// Two control cases must succeed (--allow-empty, --force), so that "everything fails" would not
// pass. With LACET_BAD_INPUT_TABLE=FILE, the outcomes are also written to FILE as a Markdown table.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include "io/scene_file.h"
#include "tests/app/cli_fixtures.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

const std::string kAndorraPbf = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra/andorra-2021-04-14.osm.pbf";
// The suite's folder holds dem.tif (the fixture DEM), good.geojson and good.gpkg; each case runs
// in a folder of its own beside them.
const std::string kDem = "../dem.tif";
const std::string kGoodVectors = "../good.geojson";
const std::string kScene = "scene.gpkg";
// A guard against a hang only: far above what any import here takes, even sanitized on a loaded machine.
constexpr int kTimeoutS = 600;

using test::kWithoutRootsOverride;
using test::quoted;
using test::readFile;

void writeFile(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

struct Outcome {
    int code = -1;  // the exit status; 128 + n for a signal n, 124 for the timeout
    std::string out, err;
};

// Runs `lacet import args...` in `cwd`, after `prefix` (a command that runs the rest) if any.
Outcome runImport(const fs::path& cwd, const std::vector<std::string>& args, const std::string& prefix = {}) {
    const fs::path out = cwd / "lacet.stdout", err = cwd / "lacet.stderr";
    std::vector<std::string> words = {"cd", quoted(cwd.string()), "&&", "exec", "timeout", std::to_string(kTimeoutS)};
    if (!prefix.empty()) words.push_back(prefix);
    words.insert(words.end(), {quoted(LACET_BINARY), "import"});
    for (const std::string& a : args) words.push_back(quoted(a));
    words.insert(words.end(), {">", quoted(out.string()), "2>", quoted(err.string())});
    std::string cmd;
    for (const std::string& w : words) cmd += (cmd.empty() ? "" : " ") + w;
    const int status = std::system(cmd.c_str());
    Outcome o;
    if (status != -1) o.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    o.out = readFile(out);
    o.err = readFile(err);
    fs::remove(out);
    fs::remove(err);
    return o;
}

bool isProgressLine(const std::string& line) { return line.starts_with('[') && line.find("] ") != std::string::npos; }

// What the command said: stderr then stdout, without the progress lines ("[reading x.osm] ...",
// which name every input and so would name the offending one whatever the message says).
std::string message(const Outcome& o) {
    std::string m;
    for (const std::string* text : {&o.err, &o.out}) {
        std::istringstream in(*text);
        for (std::string line; std::getline(in, line);)
            if (!isProgressLine(line)) m += line + "\n";
    }
    return m;
}

// What the user reads first: the message's first line; a line that announces a list (ends with
// ':') is followed by the list's first item.
std::string firstLine(const std::string& said) {
    std::istringstream in(said);
    std::string line, next;
    while (std::getline(in, line) && line.empty()) {
    }
    if (!line.empty() && line.back() == ':' && std::getline(in, next)) {
        const std::size_t start = next.find_first_not_of(' ');
        if (start != std::string::npos) line += " " + next.substr(start);
    }
    return line;
}

// What one case expects of the import.
struct Expect {
    std::vector<std::string> args;       // after `lacet import`, run in the case's folder
    std::string out;                     // the --out given (in args too), relative to the case's folder
    std::vector<std::string> names;      // each must appear in the message: the offending paths or options
    std::string reason;                  // must appear in the message
    std::vector<std::string> untouched;  // files (relative) that must keep their bytes
    std::vector<std::string> absent;     // paths (relative) that must not exist afterwards
    bool succeeds = false;               // a control case: exit 0 and a Lacet scene now at `out`
    std::string skip;                    // not empty: skipped, for this reason
    std::string prefix;                  // runImport's
};

struct Case {
    const char* name;
    std::function<Expect(const fs::path& dir)> make;  // writes the inputs in `dir`
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

// The suite's scratch folder and the good scene's bytes.
struct Suite {
    fs::path root;
    std::string goodScene;
    std::string error;  // why the setup failed
};
Suite& suite() {
    static Suite s;
    return s;
}

// A case whose --out holds the good scene, which must survive.
Expect keepsTheScene(const fs::path& dir, std::vector<std::string> args, std::vector<std::string> names, std::string reason) {
    fs::copy_file(suite().root / "good.gpkg", dir / kScene, fs::copy_options::overwrite_existing);
    args.insert(args.end(), {"--out", kScene});
    return {std::move(args), kScene, std::move(names), std::move(reason), {kScene}, {}, false, {}, {}};
}

// A case whose --out names something else (or nowhere): `untouched` must keep their bytes and
// `absent` must still not exist.
Expect leavesAlone(std::vector<std::string> args, std::string out, std::vector<std::string> names, std::string reason,
                   std::vector<std::string> untouched, std::vector<std::string> absent = {}) {
    return {std::move(args), std::move(out), std::move(names), std::move(reason), std::move(untouched), std::move(absent), false, {}, {}};
}

Expect skipped(std::string why) {
    Expect e;
    e.skip = std::move(why);
    return e;
}

// Two roads of good.geojson in EPSG:3857 metres (spherical Mercator), with no "crs" member.
std::string mercatorGeoJsonWithoutCrs() {
    const auto xy = [](double lon, double lat) {
        constexpr double r = 6378137.0, k = std::numbers::pi / 180.0;
        return "[" + std::to_string(r * lon * k) + ", " + std::to_string(r * std::log(std::tan(std::numbers::pi / 4.0 + lat * k / 2.0))) + "]";
    };
    return R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 1, "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [)" +
           xy(1.505, 42.520) + ", " + xy(1.515, 42.521) + ", " + xy(1.525, 42.521) + R"(]}},
 {"type": "Feature", "id": 2, "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [)" +
           xy(1.525, 42.521) + ", " + xy(1.535, 42.520) + "]}}\n]}\n";
}

const char* const kOsmXml = R"(<?xml version="1.0" encoding="UTF-8"?>
<osm version="0.6" generator="lacet-test">
 <node id="1" lat="42.520" lon="1.505"/>
 <node id="2" lat="42.521" lon="1.515"/>
 <node id="3" lat="42.522" lon="1.525"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><nd ref="3"/><tag k="highway" v="primary"/></way>
 <way id="11"><nd ref="2"/><nd ref="3"/><tag k="highway" v="secondary"/></way>
</osm>
)";

// Nine levels of entities, ten references each: 10^9 'a's once expanded.
const char* const kBillionLaughsOsm = R"(<?xml version="1.0"?>
<!DOCTYPE osm [
 <!ENTITY a "aaaaaaaaaa">
 <!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">
 <!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">
 <!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">
 <!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;">
 <!ENTITY f "&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;">
 <!ENTITY g "&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;">
 <!ENTITY h "&g;&g;&g;&g;&g;&g;&g;&g;&g;&g;">
 <!ENTITY i "&h;&h;&h;&h;&h;&h;&h;&h;&h;&h;">
]>
<osm version="0.6">
 <node id="1" lat="42.520" lon="1.505"/>
 <node id="2" lat="42.521" lon="1.515"/>
 <way id="10"><nd ref="1"/><nd ref="2"/><tag k="highway" v="primary"/><tag k="name" v="&i;"/></way>
</osm>
)";

// Every feature mapped and every one a zero-length way: nothing can be kept.
const char* const kZeroLengthWays = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 1, "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [[1.51, 42.51], [1.51, 42.51]]}},
 {"type": "Feature", "id": 2, "properties": {"highway": "residential"},
  "geometry": {"type": "LineString", "coordinates": [[1.52, 42.52], [1.52, 42.52], [1.52, 42.52]]}},
 {"type": "Feature", "id": 3, "properties": {"waterway": "river"},
  "geometry": {"type": "LineString", "coordinates": [[1.53, 42.53]]}}
]}
)";

// Two short roads 60 degrees of longitude apart (about 4900 km at 42.5 N).
const char* const kFarApart = R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "id": 1, "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [[1.50, 42.50], [1.51, 42.51]]}},
 {"type": "Feature", "id": 2, "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [[61.50, 42.50], [61.51, 42.51]]}}
]}
)";

std::string mapping(const std::string& layers, const std::string& rule) {
    return R"({"layers": [)" + layers + R"(], "rules": [{"geometry": "line", "match": {"highway": ["*"]}, "layer": "roads")" + rule + "}]}\n";
}
const std::string kRoadsLayerJson = R"({"name": "roads", "kind": "roads"})";

const std::vector<Case> kCases = {
    {"truncated_osm_pbf",
     [](const fs::path& d) {
         if (!fs::exists(kAndorraPbf)) return skipped("no Andorra data at " + kAndorraPbf);
         writeFile(d / "cut.osm.pbf", readFile(kAndorraPbf, 4096));
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "cut.osm.pbf"}, {"cut.osm.pbf"}, "truncated or malformed");
     }},
    {"truncated_osm_xml",
     [](const fs::path& d) {
         const std::string xml = kOsmXml;
         writeFile(d / "cut.osm", xml.substr(0, xml.size() / 2));
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "cut.osm"}, {"cut.osm"}, "truncated or malformed");
     }},
    {"billion_laughs_osm_xml",
     [](const fs::path& d) {
         writeFile(d / "laughs.osm", kBillionLaughsOsm);
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "laughs.osm"}, {"laughs.osm"}, "read error");
     }},
    {"shapefile_without_prj",
     [](const fs::path& d) {
         test::writeRoadShapefile(d / "roads.shp", false);
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "roads.shp"}, {"roads.shp"}, "no coordinate reference system");
     }},
    {"geojson_in_3857_without_crs",
     [](const fs::path& d) {
         writeFile(d / "mercator.geojson", mercatorGeoJsonWithoutCrs());
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "mercator.geojson"}, {"mercator.geojson"},
                              "outside longitude/latitude ranges");
     }},
    {"dem_misses_every_feature",
     [](const fs::path& d) {
         test::writeDemTile(d / "far.tif", 10.0, 45.0, 20, 20, 0.0025);  // lon 10-10.05, lat 45-45.05
         return keepsTheScene(d, {"--dem", "far.tif", "--vectors", kGoodVectors}, {"far.tif"}, "inside the DEM");
     }},
    {"vector_budget_smaller_than_the_densest_part",
     [](const fs::path& d) {
         // Out of core, every part holds at least a way: a budget of 100 bytes fits none.
         writeFile(d / "roads.osm", kOsmXml);
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "roads.osm", "--vector-budget", "0.0001"}, {kScene, "MiB"},
                              "give --vector-budget at least that");
     }},
    {"dem_cell_too_fine_for_the_disk",
     [](const fs::path& d) {
         // A road 400 km long over a DEM of 4 x 4 degrees: at 0.1 m cells the tree would be some
         // 4 million samples a side, 80 TiB: refused with the figures before a row is visited.
         test::writeDemTile(d / "wide.tif", 0.0, 42.0, 40, 40, 0.1);
         writeFile(d / "long.geojson", R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": 1, "properties":
  {"highway": "primary"}, "geometry": {"type": "LineString", "coordinates": [[0.2, 42.2], [3.8, 45.8]]}}]})");
         return keepsTheScene(d, {"--dem", "wide.tif", "--vectors", "long.geojson", "--dem-cell", "0.1", "--dem-storage", "lod"},
                              {"wide.tif", "GiB"}, "m or more would fit (--dem-cell)");
     }},
    {"out_is_the_vectors_input",
     [](const fs::path& d) {
         writeFile(d / "roads.osm", kOsmXml);
         return leavesAlone({"--dem", kDem, "--vectors", "roads.osm", "--out", "roads.osm"}, "roads.osm", {"roads.osm"}, "is an input",
                            {"roads.osm"});
     }},
    {"out_is_a_text_file",
     [](const fs::path& d) {
         writeFile(d / "notes.txt", "not a scene\n");
         return leavesAlone({"--dem", kDem, "--vectors", kGoodVectors, "--out", "notes.txt"}, "notes.txt", {"notes.txt"},
                            "not a Lacet scene", {"notes.txt"});
     }},
    {"a_file_of_the_user_where_the_save_writes_its_temporary",
     [](const fs::path& d) {
         // The save writes <out>.tmp and removes a stale one: a file of the user's there is not ours.
         Expect e = keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors}, {kScene + ".tmp"}, "not a Lacet scene");
         writeFile(d / (kScene + ".tmp"), "the user's notes\n");
         e.untouched.push_back(kScene + ".tmp");
         return e;
     }},
    {"out_inside_the_dem_directory",
     [](const fs::path& d) {
         // The scene's DEM would be read as a tile of the mosaic by the next import.
         fs::create_directory(d / "tiles");
         fs::copy_file(suite().root / "dem.tif", d / "tiles" / "dem.tif");
         return leavesAlone({"--dem", "tiles", "--vectors", kGoodVectors, "--out", "tiles/scene.gpkg"}, "tiles/scene.gpkg",
                            {"tiles/scene.gpkg", "tiles"}, "inside the DEM directory", {"tiles/dem.tif"}, {"tiles/scene.gpkg"});
     }},
    {"out_is_a_directory",
     [](const fs::path& d) {
         fs::create_directory(d / "folder");
         writeFile(d / "folder" / "keep.txt", "kept\n");
         return leavesAlone({"--dem", kDem, "--vectors", kGoodVectors, "--out", "folder"}, "folder", {"folder"}, "is a directory",
                            {"folder/keep.txt"});
     }},
    {"out_in_a_missing_directory",
     [](const fs::path&) {
         return leavesAlone({"--dem", kDem, "--vectors", kGoodVectors, "--out", "missing/scene.gpkg"}, "missing/scene.gpkg",
                            {"missing/scene.gpkg"}, "does not exist", {}, {"missing"});
     }},
    {"out_in_a_read_only_directory",
     [](const fs::path& d) {
         fs::create_directory(d / "locked");
         fs::copy_file(suite().root / "good.gpkg", d / "locked" / kScene);
         fs::permissions(d / "locked", fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec);
         Expect e = leavesAlone({"--dem", kDem, "--vectors", kGoodVectors, "--out", "locked/scene.gpkg"}, "locked/scene.gpkg",
                                {"locked/scene.gpkg"}, "cannot write", {"locked/scene.gpkg"});
         if (::access((d / "locked").c_str(), W_OK) == 0) {  // root: run the import without its override, if that can be done
             const std::string probe = std::string(kWithoutRootsOverride) + " sh -c 'test -w \"$0\" && exit 3 || exit 4' " +
                                       quoted((d / "locked").string()) + " > /dev/null 2>&1";
             const int status = std::system(probe.c_str());
             if (!(WIFEXITED(status) && WEXITSTATUS(status) == 4))
                 return skipped("the read-only directory is writable to this user (root ignores permissions) and setpriv cannot drop that");
             e.prefix = kWithoutRootsOverride;
         }
         return e;
     }},
    {"missing_vectors_file",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "nowhere.geojson"}, {"nowhere.geojson"}, "No such file or directory");
     }},
    {"missing_dem_file",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", "nowhere.tif", "--vectors", kGoodVectors}, {"nowhere.tif"}, "No such file or directory");
     }},
    {"same_vectors_file_twice",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, kGoodVectors}, {kGoodVectors}, "given twice");
     }},
    {"same_vectors_file_as_x_and_dot_x",
     [](const fs::path& d) {
         fs::copy_file(suite().root / "good.geojson", d / "roads.geojson");
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "./roads.geojson", "roads.geojson"}, {"roads.geojson"}, "given twice");
     }},
    {"same_vectors_file_through_a_symlink",
     [](const fs::path& d) {
         fs::copy_file(suite().root / "good.geojson", d / "roads.geojson");
         fs::create_symlink("roads.geojson", d / "link.geojson");
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "link.geojson", "roads.geojson"}, {"link.geojson", "roads.geojson"},
                              "given twice");
     }},
    {"same_dem_file_twice",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "./" + kDem, "--vectors", kGoodVectors}, {kDem}, "given twice");
     }},
    {"tolerance_1e9",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--tolerance", "1e9"}, {"--tolerance"}, "must be in [0, 100]");
     }},
    {"tolerance_minus_1",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--tolerance", "-1"}, {"--tolerance"}, "must be in [0, 100]");
     }},
    {"tolerance_not_a_number",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--tolerance", "half"}, {"--tolerance"}, "Could not convert");
     }},
    {"dem_cell_1e12",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--dem-cell", "1e12"}, {"--dem-cell"}, "must be in [0.1, 10000]");
     }},
    {"mapping_with_an_unknown_key",
     [](const fs::path& d) {
         writeFile(d / "mapping.json", mapping(kRoadsLayerJson, R"(, "widht": 7)"));
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--mapping", "mapping.json"}, {"mapping.json", "widht"},
                              "unknown key");
     }},
    {"mapping_with_class_3_7",
     [](const fs::path& d) {
         writeFile(d / "mapping.json", mapping(kRoadsLayerJson, R"(, "class": 3.7)"));
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--mapping", "mapping.json"}, {"mapping.json", "class"},
                              "must be an integer");
     }},
    {"mapping_with_duplicate_layer_names",
     [](const fs::path& d) {
         writeFile(d / "mapping.json", mapping(kRoadsLayerJson + R"(, {"name": "roads", "kind": "rivers"})", ""));
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--mapping", "mapping.json"}, {"mapping.json", "roads"},
                              "duplicate layer name");
     }},
    {"mapping_not_json",
     [](const fs::path& d) {
         writeFile(d / "mapping.json", "layers:\n  - name: roads\n    kind: roads\n");
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--mapping", "mapping.json"}, {"mapping.json"}, "not valid JSON");
     }},
    {"missing_mapping_file",
     [](const fs::path& d) {
         return keepsTheScene(d, {"--dem", kDem, "--vectors", kGoodVectors, "--mapping", "nowhere.json"}, {"nowhere.json"},
                              "No such file or directory");
     }},
    {"empty_geojson",
     [](const fs::path& d) {
         const std::string empty = test::vectorData("empty.geojson");
         return keepsTheScene(d, {"--dem", kDem, "--vectors", empty}, {empty}, "no features");
     }},
    {"geojson_of_zero_length_ways_only",
     [](const fs::path& d) {
         writeFile(d / "zero_length.geojson", kZeroLengthWays);
         return keepsTheScene(d, {"--dem", kDem, "--vectors", "zero_length.geojson"}, {"zero_length.geojson"}, "zero-length");
     }},
    {"neither_dem_nor_vectors",
     [](const fs::path& d) { return keepsTheScene(d, {}, {"--dem", "--vectors"}, "nothing to import"); }},
    {"dem_that_is_a_text_file",
     [](const fs::path& d) {
         writeFile(d / "heights.tif", "not a raster\n");
         return keepsTheScene(d, {"--dem", "heights.tif", "--vectors", kGoodVectors}, {"heights.tif"}, "cannot open as a raster");
     }},
    {"dem_tiles_in_two_crs",
     [](const fs::path& d) {
         test::writeDemTile(d / "wgs84.tif", 1.50, 42.50, 20, 20, 0.0025);
         test::writeDemTile(d / "etrs89.tif", 1.55, 42.50, 20, 20, 0.0025, 0.0, "EPSG:4258");
         return keepsTheScene(d, {"--dem", "wgs84.tif", "etrs89.tif", "--vectors", kGoodVectors}, {"wgs84.tif", "etrs89.tif"},
                              "different CRS");
     }},
    {"extent_too_large_for_one_frame",
     [](const fs::path& d) {
         writeFile(d / "far_apart.geojson", kFarApart);
         return keepsTheScene(d, {"--vectors", "far_apart.geojson"}, {"far_apart.geojson"}, "distort");
     }},
    {"dem_directory_without_rasters",
     [](const fs::path& d) {
         fs::create_directory(d / "tiles");
         writeFile(d / "tiles" / "README.txt", "no raster here\n");
         return keepsTheScene(d, {"--dem", "tiles", "--vectors", kGoodVectors}, {"tiles"}, "no raster file");
     }},
    // Controls: what the user explicitly accepts succeeds.
    {"control_allow_empty_on_zero_length_ways",
     [](const fs::path& d) {
         writeFile(d / "zero_length.geojson", kZeroLengthWays);
         Expect e = keepsTheScene(d, {"--dem", kDem, "--vectors", "zero_length.geojson", "--allow-empty"}, {}, "");
         e.untouched.clear();
         e.succeeds = true;
         return e;
     }},
    {"control_force_over_a_text_file",
     [](const fs::path& d) {
         writeFile(d / "notes.txt", "not a scene\n");
         Expect e = leavesAlone({"--dem", kDem, "--vectors", kGoodVectors, "--out", "notes.txt", "--force"}, "notes.txt", {}, "", {});
         e.succeeds = true;
         return e;
     }},
};

// One row of the Markdown table.
struct Row {
    std::string name, command, code, message, survived;
};
std::vector<Row>& rows() {
    static std::vector<Row> r;
    return r;
}

std::string markdownCell(std::string s) {
    std::string out;
    for (const char c : s) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
    return out;
}

// The command as the table shows it: the source folder as $SRC, cut after 110 characters.
std::string shortCommand(const std::vector<std::string>& args) {
    std::string s = "lacet import";
    for (std::string a : args) {
        const std::string src = LACET_SOURCE_DIR;
        if (a.rfind(src, 0) == 0) a = "$SRC" + a.substr(src.size());
        s += ' ';
        s += a.empty() ? std::string("''") : a;
    }
    return s.size() > 110 ? s.substr(0, 107) + "..." : s;
}

class ImportCliBadInput : public testing::TestWithParam<Case> {
public:
    static void SetUpTestSuite() {
        Suite& s = suite();
        s.root = test::scratchDir("import_cli");
        test::writeFixtureDem(s.root, false);  // dem.tif
        fs::copy_file(test::vectorData("good.geojson"), s.root / "good.geojson", fs::copy_options::overwrite_existing);
        const Outcome good = runImport(s.root, {"--dem", "dem.tif", "--vectors", "good.geojson", "--out", "good.gpkg"});
        if (good.code != 0 || !isLacetScene((s.root / "good.gpkg").string()))
            s.error = "the good import failed (" + std::to_string(good.code) + "):\n" + good.err + good.out;
        s.goodScene = readFile(s.root / "good.gpkg");
    }

    static void TearDownTestSuite() {
        if (const char* table = std::getenv("LACET_BAD_INPUT_TABLE")) {
            std::ofstream out(table);
            out << "| case | command | exit | message (first line) | existing scene survived |\n|---|---|---|---|---|\n";
            for (const Row& r : rows())
                out << "| " << r.name << " | `" << markdownCell(r.command) << "` | " << r.code << " | " << markdownCell(r.message) << " | "
                    << r.survived << " |\n";
        }
        // A read-only folder must be writable again for its contents to be removed.
        std::error_code ec;
        for (const auto& e : fs::recursive_directory_iterator(suite().root, ec))
            if (e.is_directory() && !e.is_symlink()) fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(suite().root, ec);
    }
};

TEST_P(ImportCliBadInput, FailsNamingTheInputAndReasonAndDestroysNothing) {
    const Suite& s = suite();
    ASSERT_TRUE(s.error.empty()) << s.error;
    const Case& c = GetParam();
    const fs::path dir = s.root / c.name;
    fs::create_directories(dir);
    const Expect e = c.make(dir);
    if (!e.skip.empty()) {
        rows().push_back({c.name, "-", "skipped", e.skip, "-"});
        GTEST_SKIP() << e.skip;
    }
    std::vector<std::string> before;
    for (const std::string& f : e.untouched) before.push_back(readFile(dir / f));
    const std::string outBefore = readFile(dir / e.out);

    const Outcome o = runImport(dir, e.args, e.prefix);
    const std::string said = message(o);
    const std::string shown = (e.prefix.empty() ? std::string() : std::string("setpriv (no dac_override) ")) + shortCommand(e.args);
    const std::string where = shown + " -> exit " + std::to_string(o.code) + ":\n" + o.err + o.out;

    std::string damage;  // what the import destroyed or left behind
    for (std::size_t i = 0; i < e.untouched.size(); ++i)
        if (!fs::is_regular_file(dir / e.untouched[i]) || readFile(dir / e.untouched[i]) != before[i]) damage += e.untouched[i] + " changed; ";
    std::vector<std::string> absent = e.absent;
    for (const char* suffix : {".tmp", ".tmp-journal", ".tmp-wal"})
        if (std::find(e.untouched.begin(), e.untouched.end(), e.out + suffix) == e.untouched.end()) absent.push_back(e.out + suffix);
    for (const std::string& p : absent)
        if (fs::exists(fs::symlink_status(dir / p))) damage += p + " left behind; ";

    Row row{c.name, shown, std::to_string(o.code), firstLine(said), damage.empty() ? "yes" : "NO: " + damage};
    if (o.code == 124) row.code += " (timeout)";
    else if (o.code >= 128) row.code += " (signal " + std::to_string(o.code - 128) + ")";

    if (e.succeeds) {
        const bool replaced = isLacetScene((dir / e.out).string()) && readFile(dir / e.out) != outBefore;
        row.survived = replaced ? "replaced (as asked)" : "NO: not replaced by a scene";
        rows().push_back(row);
        EXPECT_EQ(o.code, 0) << where;
        EXPECT_TRUE(replaced) << e.out << " does not hold a new Lacet scene\n" << where;
        EXPECT_EQ(damage, "") << where;
        return;
    }
    rows().push_back(row);
    EXPECT_NE(o.code, 0) << "accepted\n" << where;
    EXPECT_TRUE(o.code != 124 && o.code < 128) << "crashed or hung\n" << where;
    for (const std::string& n : e.names) EXPECT_NE(said.find(n), std::string::npos) << "the message does not name " << n << "\n" << where;
    EXPECT_NE(said.find(e.reason), std::string::npos) << "the message does not say \"" << e.reason << "\"\n" << where;
    EXPECT_EQ(damage, "") << where;
    if (e.out == kScene) {
        EXPECT_TRUE(readFile(dir / kScene) == s.goodScene) << "the good scene at --out is not byte for byte the same";
    }
}

INSTANTIATE_TEST_SUITE_P(ImportCli, ImportCliBadInput, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<Case>& c) { return std::string(c.param.name); });

}  // namespace
}  // namespace lacet
