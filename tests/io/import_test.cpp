// GIS import: the mapping, the vector reader's per-feature report on a corpus of faults, the DEM
// import (voids, reprojection, outside), the scene frame, topology and splines, end to end.
#include <filesystem>
#include <fstream>
#include <limits>

#include <glm/common.hpp>
#include <gtest/gtest.h>
#include <ogrsf_frmts.h>

#include "io/dem_import.h"
#include "io/scene_import.h"
#include "model/validate.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

std::map<std::string, std::vector<std::int64_t>> byReason(const std::vector<FeatureProblem>& problems) {
    std::map<std::string, std::vector<std::int64_t>> out;
    for (const FeatureProblem& p : problems) out[p.reason].push_back(p.source.fid);
    return out;
}

TEST(FeatureMapping, DefaultMappingAndOtherTags) {
    const FeatureMapping m = defaultMapping();
    std::map<std::string, std::string> a;
    parseOtherTags(R"("bridge"=>"yes","name"=>"Pont \"vell\"","layer"=>"1")", a);
    EXPECT_EQ(a.at("bridge"), "yes");
    EXPECT_EQ(a.at("name"), "Pont \"vell\"");
    EXPECT_EQ(a.at("layer"), "1");
    a["highway"] = "primary";
    const auto rule = m.match(a, GeometryKind::Line);
    ASSERT_TRUE(rule);
    EXPECT_EQ(m.layers[m.rules[*rule].layer].kind, LayerKind::Roads);
    EXPECT_EQ(m.rules[*rule].cls, 0);
    EXPECT_FALSE(m.match({{"highway", "footway"}}, GeometryKind::Line));
    EXPECT_FALSE(m.match({{"highway", "primary"}}, GeometryKind::Area));
    EXPECT_TRUE(m.match({{"natural", "wood"}}, GeometryKind::Area));
}

TEST(FeatureMapping, BadMappingFilesNameTheFileAndTheReason) {
    try {
        loadMapping(test::vectorData("bad_mapping.json"));
        FAIL();
    } catch (const MappingError& e) {
        EXPECT_NE(std::string(e.what()).find("bad_mapping.json"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("layers[0].kind: unknown layer kind \"motorways\""), std::string::npos);
    }
    EXPECT_THROW(parseMapping("{", "inline"), MappingError);
    EXPECT_THROW(parseMapping(R"({"layers":[{"name":"r","kind":"roads"}],"rules":[{"geometry":"line","match":{"a":["b"]},"layer":"x"}]})", "inline"),
                 MappingError);
    EXPECT_THROW(parseMapping(R"({"layers":[{"name":"r","kind":"roads"}],"rules":[{"geometry":"area","match":{"a":["b"]},"layer":"r"}]})", "inline"),
                 MappingError);
    EXPECT_THROW(loadMapping("/nonexistent/mapping.json"), MappingError);
}

TEST(VectorImport, EachGeometryFaultGetsItsExactReportAndTheRestImports) {
    VectorData d;
    readVectors(test::vectorData("faults.geojson"), defaultMapping(), d);
    const auto r = byReason(d.problems);
    EXPECT_EQ(r.at("zero-length way (fewer than 2 distinct points)"), (std::vector<std::int64_t>{10}));
    EXPECT_EQ(r.at("duplicate consecutive points (removed)"), (std::vector<std::int64_t>{11}));
    EXPECT_EQ(r.at("self-intersecting or invalid polygon"), (std::vector<std::int64_t>{12}));
    EXPECT_EQ(r.at("unclosed ring"), (std::vector<std::int64_t>{13}));
    EXPECT_EQ(r.at("non-finite or out-of-range coordinate"), (std::vector<std::int64_t>{14}));
    EXPECT_EQ(r.at("no geometry"), (std::vector<std::int64_t>{16}));
    EXPECT_EQ(r.at("degenerate ring (fewer than 3 distinct points)"), (std::vector<std::int64_t>{17}));
    EXPECT_EQ(d.problems.size(), 7u);
    for (const FeatureProblem& p : d.problems) EXPECT_NE(p.source.str().find("faults.geojson"), std::string::npos);
    // Kept: 11 (repaired), 15 (outside any DEM: decided later), 18.
    EXPECT_EQ(d.lines.size(), 3u);
    EXPECT_EQ(d.areas.size(), 0u);
    EXPECT_EQ(d.featuresRead, 9u);
}

TEST(VectorImport, MissingTruncatedAndEmptyFiles) {
    VectorData d;
    try {
        readVectors(test::vectorData("missing.geojson"), defaultMapping(), d);
        FAIL();
    } catch (const VectorImportError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.geojson: cannot open as vector data"), std::string::npos) << e.what();
    }
    EXPECT_THROW(readVectors(test::vectorData("truncated.geojson"), defaultMapping(), d), VectorImportError);
    readVectors(test::vectorData("empty.geojson"), defaultMapping(), d);
    ASSERT_EQ(d.fileErrors.size(), 1u);  // a reason to fail the import
    EXPECT_NE(d.fileErrors[0].find("empty.geojson: no features"), std::string::npos) << d.fileErrors[0];
}

TEST(VectorImport, TruncatedOsmPbfNeverCrashes) {
    const std::string source = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra/andorra-2021-04-14.osm.pbf";
    if (!std::filesystem::exists(source)) GTEST_SKIP() << "no Andorra data";
    const auto dir = test::scratchDir("pbf");
    for (std::size_t bytes : {std::size_t(0), std::size_t(100), std::size_t(5000), std::size_t(300000)}) {
        const std::string cut = (dir / ("cut" + std::to_string(bytes) + ".osm.pbf")).string();
        {
            std::ifstream in(source, std::ios::binary);
            std::ofstream out(cut, std::ios::binary);
            std::vector<char> buf(bytes);
            in.read(buf.data(), std::streamsize(bytes));
            out.write(buf.data(), std::streamsize(bytes));
        }
        VectorData d;
        try {
            readVectors(cut, defaultMapping(), d);
            // Opened: a file-level error says the rest was not read (the import fails on it).
            ASSERT_FALSE(d.fileErrors.empty()) << bytes << " bytes";
            EXPECT_NE(d.fileErrors[0].find(cut), std::string::npos) << d.fileErrors[0];
        } catch (const VectorImportError& e) {
            EXPECT_NE(std::string(e.what()).find(cut), std::string::npos);
        }
    }
    std::filesystem::remove_all(dir);
}

TEST(DemImport, VoidsAreFilledAndCountedAndHeightsLandWhereTheyBelong) {
    const auto dir = test::scratchDir("dem");
    const std::string path = test::writeFixtureDem(dir);
    SceneFrame frame(1.525, 42.525);
    const Vec2 a = frame.forward({1.505, 42.505}), b = frame.forward({1.545, 42.545});
    frame.setOriginShift(-a);
    const Box extent{{0, 0}, {b.x - a.x, b.x - a.x}};
    DemImportReport r;
    const Dem dem = importDem(demSourceInfo({path}), frame, extent, 20.0, r);
    EXPECT_EQ(r.voids, 36u);
    EXPECT_EQ(r.sourceWidth, 100);
    EXPECT_LT(r.outsideFraction, 0.05);
    // Away from the voids and the valley's kink, the bilinear resampling of a plane is exact to
    // float precision; the geographic position of every scene cell comes back through the frame.
    double worst = 0.0;
    for (int j = 0; j < dem.height(); j += 7)
        for (int i = 0; i < dem.width(); i += 7) {
            const glm::dvec2 ll = frame.reverse(dem.samplePosition(i, j));
            const bool nearKink = std::abs(ll.x - 1.53) < 0.0065;  // the valley's kinks at 1.525, 1.53, 1.535
            const bool nearVoid = ll.x > 1.5185 && ll.x < 1.5245 && ll.y > 42.5155 && ll.y < 42.5215;
            if (nearKink || nearVoid || ll.y > 42.5495 || ll.x > 1.5495) continue;
            worst = std::max(worst, std::abs(double(dem.at(i, j)) - test::fixtureHeight(ll.x, ll.y)));
        }
    EXPECT_LT(worst, 0.05) << "metres";
    // The void block (lon 1.520-1.523, lat 42.517-42.520) is filled between its neighbours.
    const Vec2 inVoid = frame.forward({1.5215, 42.5185});
    EXPECT_NEAR(dem.sample(inVoid), test::fixtureHeight(1.5215, 42.5185), 15.0);
    std::filesystem::remove_all(dir);
}

TEST(DemImport, BadRastersGetClearErrors) {
    const auto dir = test::scratchDir("dembad");
    try {
        demSourceInfo({(dir / "missing.tif").string()});
        FAIL();
    } catch (const DemImportError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.tif: No such file or directory"), std::string::npos) << e.what();
    }
    const std::string garbage = (dir / "garbage.tif").string();
    std::ofstream(garbage) << "not a tiff at all";
    try {
        demSourceInfo({garbage});
        FAIL();
    } catch (const DemImportError& e) {
        EXPECT_NE(std::string(e.what()).find("garbage.tif: cannot open as a raster"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

TEST(DemImport, SrtmInsideAZipThroughVsizip) {
    const std::string zip = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra/N42E001.hgt.zip";
    if (!std::filesystem::exists(zip)) GTEST_SKIP() << "no Andorra data";
    const std::string path = "/vsizip/" + zip + "/N42E001.hgt";
    const DemSourceInfo info = demSourceInfo({path});
    EXPECT_EQ(info.width, 1201);
    SceneFrame frame(1.55, 42.55);
    frame.setOriginShift({5000.0, 5000.0});
    DemImportReport r;
    const Dem dem = importDem(info, frame, {{0, 0}, {10000, 10000}}, 90.0, r);
    EXPECT_GT(r.voids, 0u) << "SRTM voids on the peaks";
    EXPECT_EQ(r.outsideFraction, 0.0);
    EXPECT_GT(r.minHeight, 300.0);
    EXPECT_LT(r.maxHeight, 3200.0);
}

TEST(SceneFrame, ProjectionRoundTripsAndItsScaleErrorIsSmallNearTheCentre) {
    SceneFrame f(1.6, 42.55);
    f.setOriginShift({16000.0, 16000.0});
    for (const glm::dvec2 ll : {glm::dvec2(1.6, 42.55), glm::dvec2(1.42, 42.43), glm::dvec2(1.79, 42.66)}) {
        const glm::dvec2 back = f.reverse(f.forward(ll));
        EXPECT_NEAR(back.x, ll.x, 1e-10);
        EXPECT_NEAR(back.y, ll.y, 1e-10);
    }
    EXPECT_NEAR(f.forward({1.6, 42.55}).x, 16000.0, 1e-6);
    // 1 km north is 1 km of scene y on the central meridian (within the ellipsoid's meridian arc).
    EXPECT_NEAR(f.forward({1.6, 42.55 + 1.0 / 111.1}).y - 16000.0, 1000.0, 3.0);
    const double e = f.largestScaleError({{0, 0}, {32000, 32000}});
    EXPECT_GT(e, 0.0);
    EXPECT_LT(e, 1e-5);  // 16 km from the central meridian: (16/6371)^2 / 2 = 3.2e-6
    EXPECT_NE(f.georeference().crsWkt.find("Transverse_Mercator"), std::string::npos);
}

TEST(SceneImport, GeoJsonAndDemIntoAValidSceneWithJunctionsBridgesAndHoles) {
    const auto dir = test::scratchDir("import");
    ImportOptions o;
    o.dem = {test::writeFixtureDem(dir)};
    o.vectors = {test::vectorData("good.geojson"), test::vectorData("faults.geojson")};
    ImportReport r;
    const SceneDocument doc = importScene(o, r);
    EXPECT_TRUE(validate(doc.scene).empty());
    const Layer& roads = doc.scene.layers[0];
    const Layer& rivers = doc.scene.layers[1];
    const Layer& lakes = doc.scene.layers[2];
    // Roads: 1 and 2 meet end to end (same rule: merged), 3 leaves 1 at a shared interior point,
    // 4 (a bridge) leaves 2 at a shared interior point: 2 junctions of degree 3.
    std::size_t junctions = 0;
    for (const Node& n : roads.nodes) junctions += n.curves.size() >= 3;
    EXPECT_EQ(junctions, 2u);
    std::size_t bridges = 0;
    for (const Curve& c : roads.curves) bridges += (c.flags & kBridge) != 0;
    EXPECT_EQ(bridges, 1u);
    // Kept attributes: the road's name, the bridge's OSM layer and bridge tag, the river's name.
    std::map<std::string, std::string> kept;
    for (const ElementAttribute& a : doc.attributes) kept[std::to_string(a.layer) + "/" + a.key + "=" + a.value] = "";
    EXPECT_TRUE(kept.count("0/name=Main road"));
    EXPECT_TRUE(kept.count("0/layer=1"));
    EXPECT_TRUE(kept.count("0/bridge=yes"));
    EXPECT_TRUE(kept.count("1/name=Riu"));
    EXPECT_EQ(rivers.curves.size(), 1u);
    ASSERT_EQ(lakes.areas.size(), 1u);
    EXPECT_EQ(lakes.areas[0].loops.size(), 2u) << "the lake keeps its island";
    // Fault corpus: the feature outside the DEM is reported, the repaired one imported.
    const auto reasons = byReason(r.problems);
    EXPECT_EQ(reasons.at("outside the DEM"), (std::vector<std::int64_t>{15}));
    EXPECT_LE(r.network.maxFitError, o.fitTolerance + 1e-9);
    EXPECT_GT(r.network.inputPoints, 0u);
    // Junction positions are exact: every road node is the projection of an input point.
    SceneFrame frame(doc.georeference);
    const Vec2 shared = frame.forward({1.515, 42.521});
    bool found = false;
    for (const Node& n : roads.nodes) found = found || n.p == shared;
    EXPECT_TRUE(found);
    EXPECT_LT(r.largestScaleError, 1e-5);
    const nlohmann::json j = r.json();
    EXPECT_EQ(j["layers"][0]["junctions"], 2);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

TEST(VectorImport, ShapefilesAreReprojectedAndOnesWithoutACrsAreFileErrors) {
    const auto dir = test::scratchDir("shp");
    VectorData d;
    readVectors(test::writeRoadShapefile(dir / "roads.shp", true), defaultMapping(), d);
    ASSERT_EQ(d.lines.size(), 1u);
    EXPECT_NEAR(d.lines[0].lonLat[0].x, 1.51, 0.02);
    EXPECT_NEAR(d.lines[0].lonLat[0].y, 42.52, 0.02);
    VectorData e;
    readVectors(test::writeRoadShapefile(dir / "roads_nocrs.shp", false), defaultMapping(), e);
    EXPECT_TRUE(e.lines.empty());
    ASSERT_EQ(e.fileErrors.size(), 1u);  // a reason to fail the import
    EXPECT_NE(e.fileErrors[0].find("roads_nocrs.shp"), std::string::npos) << e.fileErrors[0];
    EXPECT_NE(e.fileErrors[0].find("no coordinate reference system"), std::string::npos) << e.fileErrors[0];
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Absurd knob values are refused with their valid range, before any file is opened (the DEM
// does not exist: a message about it would mean the knobs were checked too late).
TEST(SceneImport, BadOptionsAreRefusedWithTheirRangeBeforeAnythingIsRead) {
    ImportOptions o;
    o.dem = {"/nonexistent.tif"};
    o.vectors = {test::vectorData("good.geojson")};
    ImportReport r;
    auto refused = [&](const char* what) {
        try {
            importScene(o, r);
            ADD_FAILURE() << what << ": accepted";
        } catch (const ImportError& e) {
            EXPECT_NE(std::string(e.what()).find(" must be in ["), std::string::npos) << what << ": " << e.what();
        }
    };
    for (double t : {-1.0, std::nan("1"), std::numeric_limits<double>::infinity(), 1e9}) {
        o.fitTolerance = t;
        refused("tolerance");
    }
    o.fitTolerance = 0.5;
    for (double c : {-3.0, 1e12, 0.001}) {
        o.demCell = c;
        refused("dem cell");
    }
    o.demCell = 0.0;
    o.margin = std::nan("1");
    refused("margin");
    o.margin = 200.0;
    o.dem.clear();
    o.vectors.clear();
    EXPECT_THROW(importScene(o, r), ImportError);  // nothing to import
}

TEST(DemImport, AGridTooFineForTheExtentIsRefused) {
    const auto dir = test::scratchDir("demfine");
    SceneFrame frame(1.525, 42.525);
    DemImportReport r;
    try {
        importDem(demSourceInfo({test::writeFixtureDem(dir)}), frame, {{0, 0}, {10000, 10000}}, 0.001, r);
        FAIL();
    } catch (const DemImportError& e) {
        EXPECT_NE(std::string(e.what()).find("more than 16384 samples a side"), std::string::npos) << e.what();
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

std::size_t aliveCurves(const Layer& l) {
    return std::size_t(std::count_if(l.curves.begin(), l.curves.end(), [](const Curve& c) { return c.alive; }));
}

// Issue 12: a road route relation tagged highway=* repeated its member ways as a second copy of
// the road (extra junctions, markings broken where the copies overlap); the same data read from
// two files (overlapping extracts) doubled everything. One feature, one curve.
TEST(SceneImport, RouteRelationsAndOverlappingExtractsImportEachRoadOnce) {
    const auto dir = test::scratchDir("route");
    ImportOptions o;
    o.dem = {test::writeFixtureDem(dir)};
    o.vectors = {test::vectorData("route_relation.osm")};
    ImportReport r;
    const SceneDocument once = importScene(o, r);
    const Layer& roads = once.scene.layers[0];
    EXPECT_EQ(aliveCurves(roads), 1u);  // ways 101 and 102 merged; the relation's two parts dropped
    EXPECT_EQ(r.network.duplicateLines, 2u);
    for (const Node& n : roads.nodes) EXPECT_LE(n.curves.size(), 1u) << "no junction between a road and its own copy";

    // The same OSM data from a second file: every element is a duplicate by its OSM id.
    const auto copy = dir / "copy.osm";
    std::filesystem::copy_file(test::vectorData("route_relation.osm"), copy);
    o.vectors.push_back(copy.string());
    const SceneDocument twice = importScene(o, r);
    EXPECT_EQ(aliveCurves(twice.scene.layers[0]), 1u);
    EXPECT_EQ(aliveCurves(twice.scene.layers[1]), aliveCurves(once.scene.layers[1]));
    EXPECT_EQ(r.duplicateOsmIds, 5u);  // three ways and two relations
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Issue 12: a mosaic of DEM tiles is taken directly (here a directory of two SRTM-like tiles that
// share their border column), its seam is checked, and the scene is the same as from one raster.
TEST(SceneImport, ADemMosaicDirectoryImportsWithItsSeamChecked) {
    const auto dir = test::scratchDir("mosaic");
    std::filesystem::create_directories(dir / "tiles");
    // lon 1.50-1.525 and 1.525-1.55, lat 42.50-42.55, 0.0005 degree samples (the fixture's).
    test::writeDemTile(dir / "tiles" / "west.tif", 1.500, 42.50, 50, 100, 0.0005);
    test::writeDemTile(dir / "tiles" / "east.tif", 1.525, 42.50, 50, 100, 0.0005);
    test::writeDemTile(dir / "whole.tif", 1.500, 42.50, 100, 100, 0.0005);
    ImportOptions o;
    o.vectors = {test::vectorData("good.geojson")};
    o.dem = {(dir / "tiles").string()};
    ImportReport mosaic, whole;
    const SceneDocument a = importScene(o, mosaic);
    o.dem = {(dir / "whole.tif").string()};
    const SceneDocument b = importScene(o, whole);
    EXPECT_EQ(mosaic.dem.files.size(), 2u);
    EXPECT_EQ(mosaic.dem.seamsChecked, 1u);
    EXPECT_LT(mosaic.dem.largestSeamStep, 1e-3);
    ASSERT_EQ(a.dem->heights().size(), b.dem->heights().size());
    double worst = 0.0;
    for (std::size_t k = 0; k < a.dem->heights().size(); ++k)
        worst = std::max(worst, double(std::abs(a.dem->heights()[k] - b.dem->heights()[k])));
    EXPECT_LT(worst, 1e-3) << "metres: the mosaic is the raster";
    EXPECT_EQ(mosaic.json()["dem"]["seams_checked"], 1);
    std::filesystem::remove_all(dir);
}

// Vectors without a DEM import on flat ground, and a DEM without vectors as a DEM-only scene
// inside the DEM: both say so, and neither needs --allow-empty.
TEST(SceneImport, VectorsWithoutADemAndADemWithoutVectors) {
    const auto dir = test::scratchDir("partial");
    ImportOptions o;
    o.vectors = {test::vectorData("good.geojson")};
    o.flatHeight = 250.0;
    ImportReport r;
    const SceneDocument flat = importScene(o, r);
    EXPECT_TRUE(r.flatGround);
    ASSERT_TRUE(flat.dem.has_value());
    for (float z : flat.dem->heights()) EXPECT_EQ(z, 250.0f);
    EXPECT_EQ(flat.dem->extent(), flat.scene.extent);
    EXPECT_GT(flat.scene.layers[0].curves.size(), 0u);
    EXPECT_EQ(r.json()["dem"]["flat_ground_m"], 250.0);

    o = {};
    o.dem = {test::writeFixtureDem(dir)};
    const SceneDocument demOnly = importScene(o, r);
    EXPECT_FALSE(r.flatGround);
    for (const Layer& l : demOnly.scene.layers) EXPECT_TRUE(l.curves.empty() && l.areas.empty()) << l.name;
    EXPECT_EQ(r.dem.outsideFraction, 0.0);  // the largest square inside the DEM
    EXPECT_GT(demOnly.scene.extent.size().x, 3000.0);  // the fixture is about 4.1 x 5.6 km
    bool said = false;
    for (const std::string& w : r.warnings) said = said || w.find("DEM-only") != std::string::npos;
    EXPECT_TRUE(said);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// The "projected data that does not say so" file error fires when nothing of a layer was in
// lon/lat range, and only then: a multi-line feature with two parts in metres beside a valid
// line is two per-feature problems, not a reason to fail the file.
TEST(VectorImport, OutOfRangePartsBesideAValidFeatureAreProblemsNotAFileError) {
    const auto dir = test::scratchDir("range");
    const auto mixed = dir / "mixed.geojson";
    std::ofstream(mixed) << R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"highway": "primary"},
  "geometry": {"type": "MultiLineString", "coordinates": [[[168000, 5240000], [169000, 5241000]], [[170000, 5240000], [171000, 5241000]]]}},
 {"type": "Feature", "properties": {"highway": "primary"},
  "geometry": {"type": "LineString", "coordinates": [[1.51, 42.52], [1.52, 42.53]]}}]})";
    VectorData d;
    readVectors(mixed.string(), defaultMapping(), d);
    EXPECT_TRUE(d.fileErrors.empty()) << d.fileErrors.front();
    EXPECT_EQ(d.lines.size(), 1u);
    EXPECT_EQ(d.problems.size(), 2u);

    const auto metres = dir / "metres.geojson";
    std::ofstream(metres) << R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"highway": "primary"},
  "geometry": {"type": "MultiLineString", "coordinates": [[[168000, 5240000], [169000, 5241000]], [[170000, 5240000], [171000, 5241000]]]}}]})";
    VectorData e;
    readVectors(metres.string(), defaultMapping(), e);
    ASSERT_EQ(e.fileErrors.size(), 1u);
    EXPECT_NE(e.fileErrors[0].find("outside longitude/latitude ranges"), std::string::npos) << e.fileErrors[0];
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// River polygons (natural=water with water=river, waterway=riverbank, also as a closed way, which
// OGR's OSM reader makes a line) are areas of the rivers layer; each gets as its axial curve the
// river that runs through it, and one that no river crosses gets none (flat, as a lake) and is
// counted apart. Other natural=water polygons stay lakes.
TEST(SceneImport, RiverPolygonsAreRiverAreasWithTheRiverThroughThemAsAxialCurve) {
    const auto dir = test::scratchDir("river_areas");
    const auto vectors = dir / "river_areas.geojson";
    std::ofstream(vectors) << R"({"type": "FeatureCollection", "features": [
 {"type": "Feature", "properties": {"waterway": "river", "name": "Riu"},
  "geometry": {"type": "LineString", "coordinates": [[1.530, 42.545], [1.5302, 42.530], [1.5299, 42.515], [1.530, 42.505]]}},
 {"type": "Feature", "properties": {"waterway": "riverbank"},
  "geometry": {"type": "Polygon", "coordinates": [[[1.5294, 42.512], [1.5306, 42.512], [1.5306, 42.528], [1.5294, 42.528], [1.5294, 42.512]]]}},
 {"type": "Feature", "properties": {"natural": "water", "water": "river"},
  "geometry": {"type": "Polygon", "coordinates": [[[1.5294, 42.531], [1.5308, 42.531], [1.5308, 42.540], [1.5294, 42.540], [1.5294, 42.531]]]}},
 {"type": "Feature", "properties": {"waterway": "riverbank"},
  "geometry": {"type": "LineString", "coordinates": [[1.5293, 42.5065], [1.5307, 42.5065], [1.5307, 42.5105], [1.5293, 42.5105], [1.5293, 42.5065]]}},
 {"type": "Feature", "properties": {"natural": "water", "water": "river"},
  "geometry": {"type": "Polygon", "coordinates": [[[1.510, 42.510], [1.512, 42.510], [1.512, 42.520], [1.510, 42.520], [1.510, 42.510]]]}},
 {"type": "Feature", "properties": {"natural": "water"},
  "geometry": {"type": "Polygon", "coordinates": [[[1.540, 42.540], [1.545, 42.540], [1.545, 42.545], [1.540, 42.545], [1.540, 42.540]]]}}]})";
    ImportOptions o;
    o.dem = {test::writeFixtureDem(dir, false)};
    o.vectors = {vectors.string()};
    ImportReport r;
    const SceneDocument doc = importScene(o, r);
    EXPECT_TRUE(validate(doc.scene).empty());
    const Layer& rivers = doc.scene.layers[1];
    const Layer& lakes = doc.scene.layers[2];
    ASSERT_EQ(rivers.kind, LayerKind::Rivers);
    std::vector<ElementId> riverCurves;  // the rivers proper, not the areas' borders
    for (ElementId c = 0; c < rivers.curves.size(); ++c)
        if (rivers.curves[c].areas.empty()) riverCurves.push_back(c);
    ASSERT_EQ(riverCurves.size(), 1u) << "the areas' borders do not cut the river";
    EXPECT_EQ(rivers.curves[riverCurves[0]].w, 10.0f);
    ASSERT_EQ(rivers.areas.size(), 4u);
    std::size_t withAxial = 0;
    for (const Area& a : rivers.areas) {
        if (a.axial == kNoElement) continue;
        ++withAxial;
        EXPECT_EQ(a.axial, riverCurves[0]);
    }
    EXPECT_EQ(withAxial, 3u);
    // The polygon away from the river (the fourth feature read as an area) has none.
    SceneFrame frame(doc.georeference);
    const Vec2 away = frame.forward({1.511, 42.515});
    bool awayFlat = false;
    for (const Area& a : rivers.areas) {
        Box box{rivers.curves[a.loops[0][0].curve].vertices.front().p, rivers.curves[a.loops[0][0].curve].vertices.front().p};
        for (const Vertex& v : rivers.curves[a.loops[0][0].curve].vertices) box = {glm::min(box.min, v.p), glm::max(box.max, v.p)};
        if (box.contains(away)) awayFlat = a.axial == kNoElement;
    }
    EXPECT_TRUE(awayFlat);
    ASSERT_EQ(lakes.areas.size(), 1u) << "a plain natural=water polygon is still a lake";
    EXPECT_EQ(r.network.riverAreas, 4u);
    EXPECT_EQ(r.network.riverAreasWithAxial, 3u);
    const nlohmann::json j = r.json();
    EXPECT_EQ(j["river_areas"]["count"], 4);
    EXPECT_EQ(j["river_areas"]["with_axial_curve"], 3);
    EXPECT_EQ(j["river_areas"]["flat_without_axial_curve"], 1);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
