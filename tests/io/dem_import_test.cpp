// DEM import of several rasters: SRTM-like tiles given as paths, as a directory and as a VRT
// against one raster covering them all; seams, a missing tile, a scene larger than the DEM, the
// window read, and the refusals (different CRS, a file given twice, a missing path, a degenerate
// grid, a scene the DEM does not cover).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <tuple>

#include <gdal_utils.h>
#include <gtest/gtest.h>

#include "io/dem_import.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

// SRTM-like tiles of 64 x 64 intervals, 1/1024 degree apart (binary fractions: the tiles' grids
// line up exactly in GDAL's mosaic).
constexpr double kStep = 1.0 / 1024.0;
constexpr int kTile = 64;
constexpr double kTileSpan = kTile * kStep;  // degrees

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const DemImportError& e) {
        return e.what();
    }
    return "(no DemImportError)";
}

// A frame centred on `centre` and the scene box between two lon/lat corners, starting at (0, 0).
struct FramedScene {
    SceneFrame frame;
    Box extent;
};
FramedScene sceneBetween(glm::dvec2 southWest, glm::dvec2 northEast) {
    FramedScene s{SceneFrame((southWest.x + northEast.x) / 2, (southWest.y + northEast.y) / 2), {}};
    const Vec2 a = s.frame.forward(southWest), b = s.frame.forward(northEast);
    s.frame.setOriginShift(-a);
    s.extent = {{0.0, 0.0}, b - a};
    return s;
}

void expectSameDem(const Dem& a, const Dem& b) {
    ASSERT_EQ(a.width(), b.width());
    ASSERT_EQ(a.height(), b.height());
    EXPECT_EQ(a.extent(), b.extent());
    double worst = 0.0;
    for (std::size_t k = 0; k < a.heights().size(); ++k) worst = std::max(worst, double(std::abs(a.heights()[k] - b.heights()[k])));
    EXPECT_LT(worst, 1e-3) << "metres";
}

TEST(DemImport, TwoSrtmTilesAsPathsDirectoryOrVrtEqualOneRasterCoveringBoth) {
    const auto dir = test::scratchDir("demmosaic");
    std::filesystem::create_directories(dir / "tiles");
    const std::string west = test::writeDemTile(dir / "tiles" / "a_west.tif", 1.5, 42.5, kTile, kTile, kStep);
    const std::string east = test::writeDemTile(dir / "tiles" / "b_east.tif", 1.5 + kTileSpan, 42.5, kTile, kTile, kStep);
    std::ofstream(dir / "tiles" / "notes.txt") << "not a raster";
    const std::string whole = test::writeDemTile(dir / "whole.tif", 1.5, 42.5, 2 * kTile, kTile, kStep);
    const std::string vrt = (dir / "hand.vrt").string();
    {
        const char* names[] = {west.c_str(), east.c_str()};
        GDALDatasetH ds = GDALBuildVRT(vrt.c_str(), 2, nullptr, names, nullptr, nullptr);
        ASSERT_TRUE(ds);
        GDALClose(ds);
    }
    const FramedScene s = sceneBetween({1.505, 42.505}, {1.62, 42.557});
    DemImportReport reference;
    const Dem one = importDem(demSourceInfo({whole}), s.frame, s.extent, 50.0, reference);
    EXPECT_EQ(reference.outsideFraction, 0.0);
    EXPECT_EQ(reference.seamsChecked, 0u);

    const DemSourceInfo byDir = demSourceInfo({(dir / "tiles").string()});
    EXPECT_EQ(byDir.files, (std::vector<std::string>{west, east})) << "sorted by name, the text file ignored";
    EXPECT_EQ(byDir.width, 2 * kTile + 1) << "the shared column once";
    EXPECT_EQ(byDir.height, kTile + 1);
    EXPECT_NEAR(byDir.lonLat.min.x, 1.5 - kStep / 2, 1e-12);
    EXPECT_NEAR(byDir.lonLat.max.x, 1.5 + 2 * kTileSpan + kStep / 2, 1e-12);
    EXPECT_NEAR(byDir.resolution.y, kStep * 111000.0, 300.0) << "metres per sample northwards";
    EXPECT_NEAR(byDir.resolution.x, byDir.resolution.y * std::cos(42.53 * 3.14159265358979 / 180.0), 100.0);
    EXPECT_TRUE(byDir.covers({1.5625, 42.53}));
    EXPECT_FALSE(byDir.covers({1.7, 42.53}));

    for (const std::vector<std::string>& inputs : {std::vector<std::string>{west, east}, {(dir / "tiles").string()}, {vrt}}) {
        SCOPED_TRACE(inputs.front());
        DemImportReport r;
        const Dem mosaic = importDem(demSourceInfo(inputs), s.frame, s.extent, 50.0, r);
        expectSameDem(mosaic, one);
        EXPECT_EQ(r.outsideFraction, 0.0);
        EXPECT_EQ(r.uncoveredFilled, 0u);
        EXPECT_EQ(r.voids, 0u);
        if (inputs.front() == vrt) continue;  // a hand-made VRT is one raster: its tiles are not seen
        EXPECT_EQ(r.files.size(), 2u);
        ASSERT_EQ(r.seams.size(), 1u);
        EXPECT_EQ(r.seamsChecked, 1u);
        EXPECT_GT(r.seams[0].points, std::size_t(0.052 / kStep)) << "the shared column, inside the window";
        EXPECT_LT(r.largestSeamStep, 1e-3) << "metres";
    }
    std::filesystem::remove_all(dir);
}

TEST(DemImport, AStepBetweenTilesIsReportedAtItsSeam) {
    const auto dir = test::scratchDir("demstep");
    const std::string west = test::writeDemTile(dir / "west.tif", 1.5, 42.5, kTile, kTile, kStep);
    const std::string east = test::writeDemTile(dir / "east.tif", 1.5 + kTileSpan, 42.5, kTile, kTile, kStep, 50.0);
    const FramedScene s = sceneBetween({1.505, 42.505}, {1.62, 42.557});
    DemImportReport r;
    importDem(demSourceInfo({west, east}), s.frame, s.extent, 50.0, r);
    ASSERT_EQ(r.seams.size(), 1u);
    EXPECT_EQ(r.seams[0].fileA, west);
    EXPECT_EQ(r.seams[0].fileB, east);
    EXPECT_NEAR(r.largestSeamStep, 50.0, 1e-3) << "metres";
    EXPECT_NEAR(r.largestSeamStepAt.x, 1.5 + kTileSpan, 1e-9) << "on the shared column";
    EXPECT_GT(r.largestSeamStepAt.y, 42.5);
    EXPECT_LT(r.largestSeamStepAt.y, 42.5 + kTileSpan);
    std::filesystem::remove_all(dir);
}

TEST(DemImport, TilesThatOnlyTouchAreComparedAtTheirCommonBorder) {
    // Pixel-is-area tiles side by side without a shared column: each is continued linearly to
    // the border from its two outermost columns, exact on the fixture's plane away from the valley.
    const auto dir = test::scratchDir("demtouch");
    const std::string west = test::writeDemTile(dir / "west.tif", 1.5, 42.5, kTile, kTile, kStep);
    const std::string east = test::writeDemTile(dir / "east.tif", 1.5 + kTileSpan + kStep, 42.5, kTile, kTile, kStep);
    const FramedScene s = sceneBetween({1.505, 42.505}, {1.62, 42.557});
    DemImportReport r;
    const DemSourceInfo info = demSourceInfo({west, east});
    EXPECT_TRUE(info.covers({1.5 + kTileSpan + kStep / 2, 42.53})) << "the common border";
    importDem(info, s.frame, s.extent, 50.0, r);
    EXPECT_EQ(r.seamsChecked, 1u);
    EXPECT_NEAR(r.largestSeamStepAt.x, 1.5 + kTileSpan + kStep / 2, 1e-9);
    EXPECT_LT(r.largestSeamStep, 1e-3) << "metres";
    std::filesystem::remove_all(dir);
}

TEST(DemImport, AMissingTileLeavesAHoleReportedAsUncovered) {
    const auto dir = test::scratchDir("demhole");
    std::vector<std::string> tiles;
    for (const auto& [name, i, j] : {std::tuple{"sw.tif", 0, 0}, std::tuple{"se.tif", 1, 0}, std::tuple{"nw.tif", 0, 1}})
        tiles.push_back(test::writeDemTile(dir / name, 1.5 + i * kTileSpan, 42.5 + j * kTileSpan, kTile, kTile, kStep));
    const DemSourceInfo info = demSourceInfo(tiles);
    const glm::dvec2 hole(1.5 + 1.5 * kTileSpan, 42.5 + 1.5 * kTileSpan);
    EXPECT_FALSE(info.covers(hole)) << "the north-east tile is missing";
    EXPECT_TRUE(info.covers(hole - kTileSpan));
    EXPECT_EQ(info.lonLat.max, glm::dvec2(1.5 + 2 * kTileSpan + kStep / 2, 42.5 + 2 * kTileSpan + kStep / 2));

    // Over the whole 2 x 2 square, the hole is inside the covered cells' box: filled from its
    // covered neighbours and counted, cell for cell.
    const FramedScene s = sceneBetween({1.505, 42.505}, {1.62, 42.62});
    DemImportReport r;
    const Dem dem = importDem(info, s.frame, s.extent, 50.0, r);
    EXPECT_EQ(r.outsideFraction, 0.0);
    std::size_t inHole = 0;
    for (int j = 0; j < dem.height(); ++j)
        for (int i = 0; i < dem.width(); ++i) {
            const glm::dvec2 ll = s.frame.reverse(dem.samplePosition(i, j));
            inHole += ll.x > 1.5 + kTileSpan + kStep / 2 && ll.y > 42.5 + kTileSpan + kStep / 2;
        }
    EXPECT_EQ(r.uncoveredFilled, inHole);
    EXPECT_NEAR(double(inHole) / double(dem.width() * dem.height()), 0.25, 0.04);
    EXPECT_EQ(r.voids, 0u) << "the hole is not a void of the data";
    EXPECT_EQ(r.seams.size(), 3u) << "two shared borders and one shared corner";
    EXPECT_LT(r.largestSeamStep, 1e-3);

    // Over the northern half, the covered cells end at the missing tile: the Dem stops there.
    const FramedScene north = sceneBetween({1.505, 42.57}, {1.62, 42.62});
    const Dem half = importDem(info, north.frame, north.extent, 50.0, r);
    EXPECT_EQ(r.uncoveredFilled, 0u);
    const double border = north.frame.forward({1.5 + kTileSpan + kStep / 2, 42.595}).x;
    EXPECT_NEAR(half.extent().max.x, border, 2 * 50.0);
    EXPECT_NEAR(r.outsideFraction, 1.0 - half.extent().size().x / north.extent.size().x, 1e-9);
    EXPECT_GT(r.outsideFraction, 0.4);
    std::filesystem::remove_all(dir);
}

TEST(DemImport, ASceneLargerThanTheDemGivesTheCoveredPartAndReportsTheRest) {
    const auto dir = test::scratchDir("demlarger");
    const std::string path = test::writeFixtureDem(dir, false);  // lon 1.50-1.55, lat 42.50-42.55
    SceneFrame frame(1.525, 42.525);
    const Vec2 sw = frame.forward({1.50, 42.50}), ne = frame.forward({1.55, 42.55});
    const double side = 2.0 * std::max(ne.x - sw.x, ne.y - sw.y);
    frame.setOriginShift(Vec2(side / 2));
    const Box extent{{0, 0}, {side, side}};
    constexpr double kCell = 50.0;
    DemImportReport r;
    const Dem dem = importDem(demSourceInfo({path}), frame, extent, kCell, r);
    // The DEM's footprint in the scene (its border densified: the projection curves it).
    Box footprint{{1e300, 1e300}, {-1e300, -1e300}};
    for (int k = 0; k <= 100; ++k)
        for (const glm::dvec2 ll : {glm::dvec2(1.50 + 0.0005 * k, 42.50), glm::dvec2(1.50 + 0.0005 * k, 42.55),
                                    glm::dvec2(1.50, 42.50 + 0.0005 * k), glm::dvec2(1.55, 42.50 + 0.0005 * k)}) {
            const Vec2 p = frame.forward(ll);
            footprint = {glm::min(footprint.min, p), glm::max(footprint.max, p)};
        }
    EXPECT_EQ(dem.extent(), r.demExtent);
    for (int axis = 0; axis < 2; ++axis) {
        EXPECT_NEAR(dem.extent().min[axis], footprint.min[axis], kCell);
        EXPECT_NEAR(dem.extent().max[axis], footprint.max[axis], kCell);
    }
    const double expected = 1.0 - footprint.size().x * footprint.size().y / (side * side);
    EXPECT_NEAR(r.outsideFraction, expected, 2.0 * kCell * (footprint.size().x + footprint.size().y) / (side * side));
    EXPECT_GT(r.outsideFraction, 0.7);
    // The Dem's cells are scene cells, and hold the data (no edge stretched into them).
    EXPECT_NEAR(dem.cellSize().x, extent.size().x / r.sceneWidth, 1e-9);
    EXPECT_NEAR(dem.cellSize().y, extent.size().y / r.sceneHeight, 1e-9);
    const Vec2 offset = (dem.extent().min - extent.min) / dem.cellSize();
    EXPECT_NEAR(offset.x, std::round(offset.x), 1e-9);
    EXPECT_NEAR(offset.y, std::round(offset.y), 1e-9);
    EXPECT_LT(r.uncoveredFilled, std::size_t(2 * (dem.width() + dem.height()))) << "slivers along the curved border only";
    for (const auto& [i, j] : {std::pair{1, 1}, std::pair{dem.width() - 2, dem.height() - 2}}) {
        const glm::dvec2 ll = frame.reverse(dem.samplePosition(i, j));
        if (std::abs(ll.x - 1.53) < 0.006) continue;  // the valley's kinks
        EXPECT_NEAR(dem.at(i, j), test::fixtureHeight(ll.x, ll.y), 0.05);
    }
    std::filesystem::remove_all(dir);
}

TEST(DemImport, OnlyTheWindowUnderTheSceneIsRead) {
    const auto dir = test::scratchDir("demwindow");
    constexpr double kFine = 1.0 / 4096.0;
    const std::string big = test::writeDemTile(dir / "big.tif", 1.25, 42.25, 2047, 2047, kFine);  // half a degree a side
    const DemSourceInfo info = demSourceInfo({big});
    ASSERT_EQ(info.width, 2048);
    const FramedScene s = sceneBetween({1.49, 42.49}, {1.51, 42.51});
    DemImportReport r;
    const Dem dem = importDem(info, s.frame, s.extent, 20.0, r);
    EXPECT_EQ(r.sourceWidth, 2048);
    // 0.02 degree is about 82 samples; the window adds the margin on each side.
    EXPECT_LE(r.windowWidth, int(0.02 / kFine) + 2 * kWindowMargin + 2);
    EXPECT_LE(r.windowHeight, int(0.02 / kFine) + 2 * kWindowMargin + 2);
    EXPECT_LT(double(r.windowWidth) * r.windowHeight, 0.01 * 2048.0 * 2048.0);
    const glm::dvec2 ll = s.frame.reverse(dem.samplePosition(3, 4));
    EXPECT_NEAR(dem.at(3, 4), test::fixtureHeight(ll.x, ll.y), 0.05) << "the window lands where it belongs";
    std::filesystem::remove_all(dir);
}

TEST(DemImport, RastersInDifferentCrsAreRefusedNamingBoth) {
    const auto dir = test::scratchDir("demcrs");
    const std::string west = test::writeDemTile(dir / "west.tif", 1.5, 42.5, kTile, kTile, kStep);
    const std::string east = test::writeDemTile(dir / "east.tif", 1.5 + kTileSpan, 42.5, kTile, kTile, kStep, 0.0, "EPSG:4258");
    const std::string e = errorOf([&] { demSourceInfo({west, east}); });
    EXPECT_NE(e.find(west + " (WGS 84)"), std::string::npos) << e;
    EXPECT_NE(e.find(east + " (ETRS89)"), std::string::npos) << e;
    EXPECT_NE(e.find("different CRS"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

TEST(DemImport, AFileGivenTwiceIsRefused) {
    const auto dir = test::scratchDir("demtwice");
    const std::string west = test::writeDemTile(dir / "west.tif", 1.5, 42.5, kTile, kTile, kStep);
    std::string e = errorOf([&] { demSourceInfo({west, west}); });
    EXPECT_NE(e.find(west + ": the same file is given twice"), std::string::npos) << e;
    e = errorOf([&] { demSourceInfo({dir.string(), (dir / "." / "west.tif").string()}); });
    EXPECT_NE(e.find("west.tif: the same file is given twice (also as " + west + ")"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

TEST(DemImport, MissingOrUnusableInputsNameTheFileAndTheReason) {
    const auto dir = test::scratchDir("demmissing");
    const std::string west = test::writeDemTile(dir / "west.tif", 1.5, 42.5, kTile, kTile, kStep);
    const std::string missing = (dir / "missing.tif").string();
    std::string e = errorOf([&] { demSourceInfo({west, missing}); });
    EXPECT_EQ(e, missing + ": No such file or directory");
    e = errorOf([&] { demSourceInfo({"/vsizip/" + (dir / "missing.zip").string() + "/N42E001.hgt"}); });
    EXPECT_NE(e.find("missing.zip/N42E001.hgt: No such file or directory"), std::string::npos) << e;
    std::filesystem::create_directories(dir / "empty");
    std::ofstream(dir / "empty" / "readme.txt") << "no raster here";
    e = errorOf([&] { demSourceInfo({(dir / "empty").string()}); });
    EXPECT_NE(e.find("empty: no raster file in this directory"), std::string::npos) << e;
    // A raster without a CRS.
    {
        GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
        GDALDataset* ds = gtiff->Create((dir / "nocrs.tif").string().c_str(), 4, 4, 1, GDT_Float32, nullptr);
        double gt[6] = {1.5, 0.001, 0.0, 42.5, 0.0, -0.001};
        ds->SetGeoTransform(gt);
        GDALClose(ds);
    }
    e = errorOf([&] { demSourceInfo({(dir / "nocrs.tif").string()}); });
    EXPECT_NE(e.find("nocrs.tif: no coordinate reference system"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

TEST(DemImport, DegenerateGridsAndScenesOutsideTheDemAreRefused) {
    const auto dir = test::scratchDir("demdegenerate");
    const DemSourceInfo info = demSourceInfo({test::writeFixtureDem(dir)});
    SceneFrame frame(1.525, 42.525);
    frame.setOriginShift({2000.0, 2000.0});
    DemImportReport r;
    std::string e = errorOf([&] { importDem(info, frame, {{0, 0}, {4000, 4000}}, 1e12, r); });
    EXPECT_NE(e.find("fewer than 2 samples a side"), std::string::npos) << e;
    EXPECT_NE(e.find("the DEM cell must be between 0.244141 and 2666.67 m"), std::string::npos) << e;
    e = errorOf([&] { importDem(info, frame, {{0, 0}, {4000, 4000}}, 0.0, r); });
    EXPECT_NE(e.find("the DEM cell must be between"), std::string::npos) << e;
    SceneFrame far(10.0, 50.0);
    far.setOriginShift({2000.0, 2000.0});
    e = errorOf([&] { importDem(info, far, {{0, 0}, {4000, 4000}}, 50.0, r); });
    EXPECT_NE(e.find("the DEM does not cover the scene"), std::string::npos) << e;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
