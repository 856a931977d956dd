// DEM import out of core (io/dem_import_lod.h): the same samples as the in-memory importDem (with
// voids, with a scene larger than the DEM), the documented change when a void is wider than the
// fill's margin, a two-tile SRTM mosaic cut from the shared Andorra tile (no seam, the same samples
// as the uncut tile), and the memory held (the strips, never the whole grid).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>
#include <vector>

#include <gdal_utils.h>
#include <gtest/gtest.h>

#include "io/dem_import.h"
#include "io/dem_import_lod.h"
#include "io/dem_lod.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

// The finest level of the tree at `path`.
Dem finestLevel(const std::string& path) {
    const DemLodFile file(path);
    return readDemLevel(file, file.layout().levels - 1);
}

// Largest |a - b| over the samples of two grids of the same size (metres).
double largestDifference(const Dem& a, const Dem& b) {
    EXPECT_EQ(a.width(), b.width());
    EXPECT_EQ(a.height(), b.height());
    if (a.width() != b.width() || a.height() != b.height()) return 1e300;
    double worst = 0.0;
    for (std::size_t k = 0; k < a.heights().size(); ++k) worst = std::max(worst, double(std::abs(a.heights()[k] - b.heights()[k])));
    return worst;
}

void expectSameExtent(const Box& a, const Box& b, double tolerance) {
    for (int axis = 0; axis < 2; ++axis) {
        EXPECT_NEAR(a.min[axis], b.min[axis], tolerance);
        EXPECT_NEAR(a.max[axis], b.max[axis], tolerance);
    }
}

// A square scene of `side` metres centred on (lon, lat).
struct Square {
    SceneFrame frame;
    Box extent;
};
Square squareAround(double lon, double lat, double side) {
    Square s{SceneFrame(lon, lat), {{0.0, 0.0}, {side, side}}};
    s.frame.setOriginShift(Vec2(side / 2));
    return s;
}

TEST(DemImportLod, SameSamplesAsImportDemWithVoids) {
    const auto dir = test::scratchDir("demlod_same");
    const std::string path = test::writeFixtureDem(dir, true);  // lon 1.50-1.55, lat 42.50-42.55, a 6 x 6 void
    const DemSourceInfo info = demSourceInfo({path});
    const Square s = squareAround(1.525, 42.525, 4000.0);
    DemImportReport grid;
    const Dem reference = importDem(info, s.frame, s.extent, 10.0, grid);
    ASSERT_EQ(grid.voids, 36u) << "the fixture's void block lies under the scene";

    DemLodImportParams p;
    p.stripRows = 16;  // many strips, one of them cutting the void
    p.blockSide = 64;
    DemImportReport lod;
    const std::string lodPath = (dir / "lod.gpkg").string();
    const DemLodOutput out = importDemLod(info, s.frame, s.extent, 10.0, lodPath, lod, p);
    EXPECT_EQ(lod.storage, "lod");
    EXPECT_EQ(lod.strips, (grid.height + 15) / 16);
    EXPECT_EQ(lod.voids, grid.voids);
    EXPECT_EQ(lod.voidsBeyondMargin, 0u);
    EXPECT_EQ(lod.width, grid.width);
    EXPECT_EQ(lod.height, grid.height);
    EXPECT_EQ(lod.windowWidth, grid.windowWidth);
    EXPECT_EQ(lod.windowHeight, grid.windowHeight);
    EXPECT_EQ(lod.minHeight, grid.minHeight);
    EXPECT_EQ(lod.maxHeight, grid.maxHeight);
    EXPECT_EQ(out.layout.width, reference.width());
    EXPECT_GT(out.layout.levels, 2);
    EXPECT_GT(out.tiles, 0u);
    expectSameExtent(out.layout.extent(), reference.extent(), 1e-6);

    const Dem back = finestLevel(lodPath);
    EXPECT_EQ(largestDifference(back, reference), 0.0) << "sample for sample, through the file";
    ASSERT_TRUE(out.coarse);
    EXPECT_EQ(out.coarseLevel, out.layout.levels - 1) << "a small DEM is kept whole in memory";
    EXPECT_EQ(largestDifference(*out.coarse, reference), 0.0);
    std::filesystem::remove_all(dir);
}

TEST(DemImportLod, ASceneLargerThanTheDemGivesImportDemsCoveredPartAndFill) {
    const auto dir = test::scratchDir("demlod_larger");
    const std::string path = test::writeFixtureDem(dir, true);
    const DemSourceInfo info = demSourceInfo({path});
    const Square s = squareAround(1.52, 42.53, 8000.0);  // the DEM's west and north edges inside the scene
    DemImportReport grid;
    const Dem reference = importDem(info, s.frame, s.extent, 25.0, grid);
    ASSERT_GT(grid.outsideFraction, 0.2);
    DemLodImportParams p;
    p.stripRows = 20;
    p.blockSide = 32;
    DemImportReport lod;
    const std::string lodPath = (dir / "lod.gpkg").string();
    importDemLod(info, s.frame, s.extent, 25.0, lodPath, lod, p);
    EXPECT_EQ(lod.width, grid.width);
    EXPECT_EQ(lod.height, grid.height);
    EXPECT_EQ(lod.outsideFraction, grid.outsideFraction);
    EXPECT_EQ(lod.uncoveredFilled, grid.uncoveredFilled);
    EXPECT_EQ(lod.uncoveredBeyondMargin, 0u);
    EXPECT_EQ(lod.demExtent, grid.demExtent);
    EXPECT_EQ(largestDifference(finestLevel(lodPath), reference), 0.0);
    std::filesystem::remove_all(dir);
}

// SRTM-like tiles of 64 x 64 intervals, 1/1024 degree apart, as in dem_import_test.cpp.
constexpr double kStep = 1.0 / 1024.0;
constexpr int kTile = 64;
constexpr double kTileSpan = kTile * kStep;  // degrees

TEST(DemImportLod, AMissingTileIsFilledAsImportDemFillsItWithinTheMargin) {
    const auto dir = test::scratchDir("demlod_hole");
    std::vector<std::string> tiles;
    for (const auto& [name, i, j] : {std::tuple{"sw.tif", 0, 0}, std::tuple{"se.tif", 1, 0}, std::tuple{"nw.tif", 0, 1}})
        tiles.push_back(test::writeDemTile(dir / name, 1.5 + i * kTileSpan, 42.5 + j * kTileSpan, kTile, kTile, kStep));
    const DemSourceInfo info = demSourceInfo(tiles);
    const Square s = squareAround(1.5 + kTileSpan, 42.5 + kTileSpan, 9000.0);  // the north-east quarter is the hole
    DemImportReport grid;
    const Dem reference = importDem(info, s.frame, s.extent, 50.0, grid);
    ASSERT_GT(grid.uncoveredFilled, 80u * 80u);
    DemLodImportParams p;
    p.stripRows = 20;
    p.blockSide = 32;
    p.uncoveredMargin = 1000;  // the whole grid: importDem's fill
    DemImportReport lod;
    importDemLod(info, s.frame, s.extent, 50.0, (dir / "wide.gpkg").string(), lod, p);
    EXPECT_EQ(lod.uncoveredFilled, grid.uncoveredFilled);
    EXPECT_EQ(lod.uncoveredBeyondMargin, 0u);
    EXPECT_EQ(lod.seams.size(), 3u);
    EXPECT_LT(lod.largestSeamStep, 1e-3);
    EXPECT_EQ(largestDifference(finestLevel((dir / "wide.gpkg").string()), reference), 0.0);

    p.uncoveredMargin = 8;  // the hole is 90 rows tall: filled from the strip and 8 rows around it
    importDemLod(info, s.frame, s.extent, 50.0, (dir / "narrow.gpkg").string(), lod, p);
    EXPECT_EQ(lod.uncoveredFilled, grid.uncoveredFilled);
    EXPECT_GT(lod.uncoveredBeyondMargin, 0u);
    const Dem narrow = finestLevel((dir / "narrow.gpkg").string());
    EXPECT_GT(largestDifference(narrow, reference), 0.0);
    const auto [lo, hi] = std::minmax_element(reference.heights().begin(), reference.heights().end());
    const auto [narrowLo, narrowHi] = std::minmax_element(narrow.heights().begin(), narrow.heights().end());
    EXPECT_GE(*narrowLo, *lo) << "a fill between the rim's heights";
    EXPECT_LE(*narrowHi, *hi);
    std::filesystem::remove_all(dir);
}

TEST(DemImportLod, AVoidWiderThanTheMarginIsFilledFromTheStripAndCounted) {
    const auto dir = test::scratchDir("demlod_margin");
    const std::string path = test::writeFixtureDem(dir, true);
    const DemSourceInfo info = demSourceInfo({path});
    const Square s = squareAround(1.525, 42.525, 4000.0);
    DemImportReport grid;
    const Dem reference = importDem(info, s.frame, s.extent, 10.0, grid);
    DemLodImportParams p;
    p.stripRows = 8;
    p.voidMargin = 0;  // the strips' windows end inside the void
    p.blockSide = 64;
    DemImportReport lod;
    const std::string lodPath = (dir / "lod.gpkg").string();
    importDemLod(info, s.frame, s.extent, 10.0, lodPath, lod, p);
    EXPECT_EQ(lod.voids, grid.voids);
    EXPECT_GT(lod.voidsBeyondMargin, 0u);
    const double d = largestDifference(finestLevel(lodPath), reference);
    EXPECT_GT(d, 0.0) << "the fill sees less of the void's rim";
    EXPECT_LT(d, 30.0) << "metres: still a fill between the rim's heights (the fixture rises 1 m per 1e-3 degree)";
    std::filesystem::remove_all(dir);
}

TEST(DemImportLod, MemoryIsTheStripsNotTheGrid) {
    const auto dir = test::scratchDir("demlod_memory");
    constexpr double kFine = 1.0 / 4096.0;  // about 20 x 27 m
    const std::string big = test::writeDemTile(dir / "big.tif", 1.45, 42.45, 1023, 1023, kFine);
    const DemSourceInfo info = demSourceInfo({big});
    const Square s = squareAround(1.575, 42.575, 16000.0);
    DemLodImportParams p;
    p.stripRows = 32;
    DemImportReport lod;
    const std::string lodPath = (dir / "lod.gpkg").string();
    const DemLodOutput out = importDemLod(info, s.frame, s.extent, 20.0, lodPath, lod, p);
    const double gridSamples = double(lod.width) * double(lod.height);
    ASSERT_EQ(lod.width, 800);
    EXPECT_EQ(lod.strips, 25);
    EXPECT_GT(lod.peakStripSamples, std::size_t(32 * lod.width)) << "at least a strip";
    EXPECT_LT(double(lod.peakStripSamples), gridSamples / 4.0) << "never the whole grid";
    EXPECT_LT(double(lod.peakStripSamples), double(lod.windowWidth) * (32.0 + 2 * (p.voidMargin + kWindowMargin) + 4) +
                                                32.0 * lod.width + 1.0);
    EXPECT_EQ(out.layout.levels, 3) << "800 samples in blocks of 256";
    std::filesystem::remove_all(dir);
}

TEST(DemImportLod, ParametersOutOfRangeAreRefused) {
    const auto dir = test::scratchDir("demlod_params");
    const std::string path = test::writeFixtureDem(dir, false);
    const DemSourceInfo info = demSourceInfo({path});
    const Square s = squareAround(1.525, 42.525, 4000.0);
    DemImportReport r;
    for (auto change : {+[](DemLodImportParams& p) { p.stripRows = 0; }, +[](DemLodImportParams& p) { p.voidMargin = -1; },
                        +[](DemLodImportParams& p) { p.blockSide = 7; }}) {
        DemLodImportParams p;
        change(p);
        EXPECT_THROW(importDemLod(info, s.frame, s.extent, 10.0, (dir / "x.gpkg").string(), r, p), std::invalid_argument);
        EXPECT_FALSE(std::filesystem::exists(dir / "x.gpkg"));
    }
    std::filesystem::remove_all(dir);
}

// The shared SRTM tile (1201 x 1201, 3 arc-seconds) cut into two GeoTIFFs sharing column 600, as
// adjacent SRTM tiles share their border column.
class AndorraMosaic : public testing::Test {
protected:
    void SetUp() override {
        const std::string zip = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra/N42E001.hgt.zip";
        if (!std::filesystem::exists(zip)) GTEST_SKIP() << "no Andorra data";
        whole_ = "/vsizip/" + zip + "/N42E001.hgt";
        dir_ = test::scratchDir("demlod_andorra");
        GDALAllRegister();
        GDALDatasetH src = GDALOpen(whole_.c_str(), GA_ReadOnly);
        ASSERT_TRUE(src);
        west_ = cut(src, "N42E001_west.tif", 0);
        east_ = cut(src, "N42E001_east.tif", 600);
        GDALClose(src);
    }
    void TearDown() override {
        if (!dir_.empty()) std::filesystem::remove_all(dir_);
    }
    std::string cut(GDALDatasetH src, const std::string& name, int x0) {
        const std::string out = (dir_ / name).string();
        const std::string x = std::to_string(x0);
        const char* args[] = {"-of", "GTiff", "-srcwin", x.c_str(), "0", "601", "1201", nullptr};
        GDALTranslateOptions* o = GDALTranslateOptionsNew(const_cast<char**>(args), nullptr);
        int usageError = 0;
        GDALDatasetH ds = GDALTranslate(out.c_str(), src, o, &usageError);
        GDALTranslateOptionsFree(o);
        EXPECT_TRUE(ds) << name;
        if (ds) GDALClose(ds);
        return out;
    }
    std::string whole_, west_, east_;
    std::filesystem::path dir_;
};

TEST_F(AndorraMosaic, TwoTilesAtTheSourceResolutionHaveNoSeamAndEqualTheUncutTile) {
    const DemSourceInfo mosaic = demSourceInfo({west_, east_});
    const DemSourceInfo one = demSourceInfo({whole_});
    ASSERT_EQ(mosaic.width, 1201) << "the shared column once";
    ASSERT_EQ(mosaic.height, 1201);
    // 30 km square across the cut at lon 1.5, at the source's resolution (about 68 x 93 m).
    const Square s = squareAround(1.5, 42.55, 30000.0);
    const double cell = std::min(mosaic.resolution.x, mosaic.resolution.y);
    EXPECT_NEAR(cell, 68.5, 1.0);
    DemLodImportParams p;
    p.stripRows = 64;
    p.blockSide = 128;
    DemImportReport cutReport, oneReport, gridReport;
    const std::string cutPath = (dir_ / "cut.gpkg").string(), onePath = (dir_ / "one.gpkg").string();
    importDemLod(mosaic, s.frame, s.extent, cell, cutPath, cutReport, p);
    importDemLod(one, s.frame, s.extent, cell, onePath, oneReport, p);
    const Dem memory = importDem(mosaic, s.frame, s.extent, cell, gridReport);

    EXPECT_EQ(cutReport.files.size(), 2u);
    EXPECT_EQ(cutReport.filesRead, 2u);
    EXPECT_EQ(cutReport.seams.size(), 1u);
    EXPECT_EQ(cutReport.seamsChecked, 1u);
    ASSERT_FALSE(cutReport.seams.empty());
    EXPECT_GT(cutReport.seams[0].points, 300u) << "the shared column inside the window";
    EXPECT_LT(cutReport.largestSeamStep, 1e-3) << "metres";
    EXPECT_GT(cutReport.voids, 0u) << "SRTM voids on the peaks";
    EXPECT_EQ(cutReport.voids, oneReport.voids);
    EXPECT_EQ(cutReport.voidsBeyondMargin, 0u);
    EXPECT_NEAR(cutReport.cellSize, cell, 0.1);
    EXPECT_GT(cutReport.strips, 5);

    const Dem cutDem = finestLevel(cutPath), oneDem = finestLevel(onePath);
    EXPECT_EQ(largestDifference(cutDem, oneDem), 0.0) << "the mosaic is the tile";
    EXPECT_EQ(largestDifference(cutDem, memory), 0.0) << "the lod import is the in-memory import";
    // Across the cut: the rows step no more there than beside it.
    const Vec2 seam = s.frame.forward({1.5, 42.55});
    const int i = int(std::floor((seam.x - cutDem.extent().min.x) / cutDem.cellSize().x - 0.5));
    ASSERT_GT(i, 2);
    ASSERT_LT(i, cutDem.width() - 3);
    double across = 0.0, beside = 0.0;
    for (int j = 0; j < cutDem.height(); ++j) {
        across = std::max(across, double(std::abs(cutDem.at(i + 1, j) - cutDem.at(i, j))));
        for (int k : {i - 2, i + 2}) beside = std::max(beside, double(std::abs(cutDem.at(k + 1, j) - cutDem.at(k, j))));
    }
    EXPECT_LT(across, 3.0 * beside + 1.0) << "metres: no step at the seam";
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST_F(AndorraMosaic, ImportSceneWithLodStorageKeepsTheTreeAndACoarseLevel) {
    ImportOptions o;
    o.dem = {west_, east_};
    o.demStorage = DemStorage::Lod;
    o.demLodPath = (dir_ / "scene.gpkg.dem.tmp").string();
    ImportReport r;
    SceneDocument doc = importScene(o, r);
    EXPECT_EQ(r.dem.storage, "lod");
    ASSERT_TRUE(doc.demLod);
    EXPECT_EQ(doc.demLod->path(), o.demLodPath);
    const DemLodLayout& l = doc.demLod->layout();
    EXPECT_EQ(l, r.demLodLayout);
    EXPECT_EQ(l.width, r.dem.width);
    EXPECT_GT(l.width, 1000) << "the source's resolution over the DEM's largest square";
    EXPECT_NEAR(l.cell, std::min(r.dem.sourceResolution.x, r.dem.sourceResolution.y), 1.0);
    EXPECT_EQ(r.dem.seamsChecked, 1u);
    EXPECT_LT(r.dem.largestSeamStep, 1e-3);
    EXPECT_GT(r.demLodTiles, 0u);
    ASSERT_TRUE(doc.dem);
    EXPECT_EQ(r.demLodCoarseLevel, levelAtMost(l, kInMemoryDemSide));
    EXPECT_EQ(largestDifference(*doc.dem, readDemLevel(*doc.demLod, r.demLodCoarseLevel)), 0.0);
    const nlohmann::json j = r.json();
    EXPECT_EQ(j["dem"]["storage"], "lod");
    EXPECT_EQ(j["dem"]["lod"]["levels"], l.levels);
    EXPECT_EQ(j["dem"]["lod"]["tiles"], r.demLodTiles);

    // auto: grid under kInMemoryDemSide samples a side, the same samples.
    o.demStorage = DemStorage::Auto;
    ImportReport g;
    const SceneDocument inMemory = importScene(o, g);
    EXPECT_EQ(g.dem.storage, "grid");
    EXPECT_FALSE(inMemory.demLod);
    EXPECT_EQ(largestDifference(*inMemory.dem, readDemLevel(*doc.demLod, l.levels - 1)), 0.0);
    EXPECT_EQ(demStorageFromString("lod"), DemStorage::Lod);
    EXPECT_THROW(demStorageFromString("tiles"), ImportError);

    // Without a file to write to, lod is refused; a failed import leaves no file behind.
    o.demStorage = DemStorage::Lod;
    o.demLodPath.clear();
    EXPECT_THROW(importScene(o, g), ImportError);
    o.demLodPath = (dir_ / "failed.dem.tmp").string();
    o.vectors = {test::vectorData("good.geojson")};
    o.minKept = 1000000;  // fails after the DEM is written
    EXPECT_THROW(importScene(o, g), ImportError);
    EXPECT_FALSE(std::filesystem::exists(o.demLodPath));

    // A file already at demLodPath is the user's: refused, left as it was (also when the import
    // would fail anyway).
    o.minKept = 1;
    o.vectors.clear();
    o.demLodPath = (dir_ / "mine.dem.tmp").string();
    writeText(o.demLodPath, "my notes");
    EXPECT_THROW(importScene(o, g), ImportError);
    EXPECT_EQ(readText(o.demLodPath), "my notes");
}

TEST(DemLodTempPath, UniqueNamesBesideTheOutputThatNoFileHas) {
    const auto dir = test::scratchDir("demlod_temp_path");
    const std::string out = (dir / "scene.gpkg").string();
    const std::string a = uniqueDemLodPath(out), b = uniqueDemLodPath(out);
    EXPECT_NE(a, b);
    for (const std::string& p : {a, b}) {
        EXPECT_EQ(p.rfind(out + ".dem.", 0), 0u) << p;
        EXPECT_TRUE(p.ends_with(".tmp")) << p;
        EXPECT_FALSE(std::filesystem::exists(p)) << "reserved, then left free for writeDemLodFile: " << p;
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    EXPECT_THROW(uniqueDemLodPath((dir / "no_such_dir" / "scene.gpkg").string()), std::runtime_error);
    // writeDemLodFile never replaces (nor, failing, removes) a file it did not make.
    writeText(a, "my notes");
    const DemLodLayout layout = DemLodLayout::make(8, 8, 1.0, {0.0, 0.0}, 4);
    EXPECT_THROW(writeDemLodFile(a, layout, [](int, std::span<float> row) { std::fill(row.begin(), row.end(), 1.0f); }),
                 std::invalid_argument);
    EXPECT_EQ(readText(a), "my notes");
    std::filesystem::remove_all(dir);
}

// A killed import leaves its tree's temporary file (SIGKILL runs no cleanup): the next name asked
// for beside the same output removes those of processes that no longer run, and keeps a running
// process's, another output's and any file named otherwise.
TEST(DemLodTempPath, TheTemporaryFilesOfKilledImportsAreRemoved) {
    const auto dir = test::scratchDir("demlod_stale_temp");
    const std::string out = (dir / "scene.gpkg").string();
    // A process id that no process has: a child that exited and was reaped.
    const pid_t gone = ::fork();
    ASSERT_GE(gone, 0);
    if (gone == 0) ::_exit(0);
    ::waitpid(gone, nullptr, 0);
    const std::string stale = out + ".dem." + std::to_string(gone) + ".0123456789abcdef.tmp";
    const std::string running = out + ".dem." + std::to_string(::getpid()) + ".0123456789abcdef.tmp";
    const std::string other = (dir / "other.gpkg").string() + ".dem." + std::to_string(gone) + ".0123456789abcdef.tmp";
    const std::string unlike = out + ".dem." + std::to_string(gone) + ".notes.tmp";
    // An import out of core's spill of features (io/vector_spill.h), removed by any import.
    const std::string spill = out + ".vectors." + std::to_string(gone) + ".0123456789abcdef.tmp";
    for (const std::string& p : {stale, stale + "-journal", running, other, unlike, spill}) writeText(p, "left");
    const std::string fresh = uniqueDemLodPath(out);
    EXPECT_FALSE(std::filesystem::exists(stale));
    EXPECT_FALSE(std::filesystem::exists(stale + "-journal"));
    EXPECT_FALSE(std::filesystem::exists(spill));
    for (const std::string& p : {running, other, unlike}) EXPECT_EQ(readText(p), "left") << p;
    EXPECT_NE(fresh, stale);
    std::filesystem::remove_all(dir);
}

// `lacet import` writes a lod DEM's tree under a name of its own and removes only that: a file named
// like the old fixed temporary name (<out>.dem.tmp) survives imports of both storages, and nothing
// else is left beside the output.
TEST_F(AndorraMosaic, ImportCliLeavesAUsersDemTmpFileAlone) {
    const std::filesystem::path work = dir_ / "cli";
    std::filesystem::create_directories(work);
    const std::string out = (work / "scene.gpkg").string(), mine = out + ".dem.tmp";
    writeText(mine, "my notes");
    for (const char* storage : {"lod", "grid"}) {
        SCOPED_TRACE(storage);
        const std::string cmd = std::string(LACET_BINARY) + " import --dem '" + west_ + "' '" + east_ + "' --dem-storage " + storage +
                                " --force --out '" + out + "' > '" + (dir_ / "cli.log").string() + "' 2>&1";
        ASSERT_EQ(std::system(cmd.c_str()), 0) << readText((dir_ / "cli.log").string());
        EXPECT_EQ(readText(mine), "my notes");
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(work)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        EXPECT_EQ(names, (std::vector<std::string>{"scene.gpkg", "scene.gpkg.dem.tmp"}));
    }
    EXPECT_TRUE(loadScene(out).dem);
}

}  // namespace
}  // namespace lacet
