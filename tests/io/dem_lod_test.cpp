#include "io/dem_lod.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "io/gpkg_dem.h"
#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "io/tile_codec.h"
#include "synth/synthetic_scene.h"
#include "tests/io/test_crs.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class DemLod : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("lacet_dem_lod_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!std::getenv("LACET_KEEP")) fs::remove_all(dir_);
    }
    std::string file(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

// Heights with no pattern a wrong index could reproduce: a smooth part and a hashed one (cm steps,
// negative ones too).
Dem randomishDem(int w, int h, double cell = 2.0, Vec2 min = {1000.0, -500.0}) {
    std::vector<float> z(std::size_t(w) * std::size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            std::uint64_t k = std::uint64_t(j) * 1000003u + std::uint64_t(i) * 7919u + 17u;
            k ^= k >> 13;
            k *= 0x9E3779B97F4A7C15ULL;
            k ^= k >> 29;
            z[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                float(300.0 + 80.0 * std::sin(0.05 * i) * std::cos(0.07 * j) + double(k % 2001) * 0.01 - 10.0);
        }
    return Dem({min, {min.x + cell * w, min.y + cell * h}}, w, h, std::move(z));
}

// A smooth terrain, as a DEM is (for the tile sizes).
Dem smoothDem(int w, int h) {
    std::vector<float> z(std::size_t(w) * std::size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            z[std::size_t(j) * std::size_t(w) + std::size_t(i)] =
                float(1200.0 + 300.0 * std::sin(0.011 * i) * std::cos(0.013 * j) + 40.0 * std::sin(0.09 * (i + j)));
    return Dem({{0.0, 0.0}, {25.0 * w, 25.0 * h}}, w, h, std::move(z));
}

// A GeoPackage at `path` holding `dem` as a tree; the CRS row 100000 holds kWkt.
DemLodLayout writeTree(const std::string& path, const Dem& dem, int blockSide, int srsId = -1) {
    createEmptyGpkg(path);
    SqliteDb db(path, SqliteDb::Mode::ReadWrite);
    if (srsId > 0) {
        auto s = db.prepare(
            "INSERT INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, definition) "
            "VALUES ('test', ?, 'NONE', ?, ?)");
        s.bind(1, std::int64_t(srsId));
        s.bind(2, std::int64_t(srsId));
        s.bindText(3, kWkt);
        s.step();
    }
    DemLodLayout layout;
    writeDemLod(db, dem, blockSide, srsId, &layout);
    db.close();
    return layout;
}

// The Dem's sample at column i, row t from the top.
float fromTop(const Dem& dem, int i, int t) { return dem.heights()[std::size_t(dem.height() - 1 - t) * std::size_t(dem.width()) + std::size_t(i)]; }

bool isNull(float v) { return std::bit_cast<std::uint32_t>(v) == std::bit_cast<std::uint32_t>(kDemNull); }

// Asserts that `f` throws E whose message holds every one of `parts`.
template <class E, class F>
void expectError(F&& f, const std::vector<std::string>& parts) {
    try {
        f();
        ADD_FAILURE() << "no exception (expected '" << parts.front() << "')";
    } catch (const E& e) {
        const std::string what = e.what();
        for (const auto& p : parts) EXPECT_NE(what.find(p), std::string::npos) << "expected '" << p << "' in: " << what;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "another exception: " << e.what();
    }
}

// ---- layout ----

TEST_F(DemLod, LayoutLevelsStepsAndBlocks) {
    const DemLodLayout l = DemLodLayout::make(300, 177, 2.0, {10.0, 20.0}, 16);
    EXPECT_EQ(l.levels, 6);  // 16 * 2^5 = 512 >= 300 > 256
    EXPECT_EQ(l.step(0), 32);
    EXPECT_EQ(l.step(5), 1);
    EXPECT_EQ(l.levelCell(0), 64.0);
    const int widths[] = {10, 19, 38, 75, 150, 300}, heights[] = {6, 12, 23, 45, 89, 177};
    const int cols[] = {1, 2, 3, 5, 10, 19}, rows[] = {1, 1, 2, 3, 6, 12};
    for (int k = 0; k < 6; ++k) {
        EXPECT_EQ(l.levelWidth(k), widths[k]) << k;
        EXPECT_EQ(l.levelHeight(k), heights[k]) << k;
        EXPECT_EQ(l.blockColumns(k), cols[k]) << k;
        EXPECT_EQ(l.blockRows(k), rows[k]) << k;
        EXPECT_EQ(l.blocksPerSide(k), 1 << k);
    }
    EXPECT_EQ(l.tileCount(), 1 + 2 + 6 + 15 + 60 + 228);
    EXPECT_TRUE(l.hasBlock(5, 18, 11));
    EXPECT_FALSE(l.hasBlock(5, 19, 11));
    EXPECT_FALSE(l.hasBlock(5, 18, 12));
    EXPECT_FALSE(l.hasBlock(1, 1, 1));
    // levelFor: the coarsest level whose spacing is at most the one asked.
    EXPECT_EQ(l.levelFor(1000.0), 0);
    EXPECT_EQ(l.levelFor(64.0), 0);
    EXPECT_EQ(l.levelFor(63.9), 1);
    EXPECT_EQ(l.levelFor(10.0), 3);
    EXPECT_EQ(l.levelFor(2.0), 5);
    EXPECT_EQ(l.levelFor(0.5), 5);
    EXPECT_THROW(l.levelFor(std::nan("")), std::invalid_argument);
    EXPECT_EQ(levelAtMost(l, 4096), 5);
    EXPECT_EQ(levelAtMost(l, 299), 4);
    EXPECT_EQ(levelAtMost(l, 150), 4);
    EXPECT_EQ(levelAtMost(l, 10), 0);
    EXPECT_EQ(levelAtMost(l, 3), 0);
    EXPECT_THROW(levelAtMost(l, 0), std::invalid_argument);
    const Box e = l.extent();
    EXPECT_EQ(e.min.x, 9.0);
    EXPECT_EQ(e.max.x, 10.0 + 299.5 * 2.0);
    EXPECT_EQ(e.max.y, 21.0);
    EXPECT_EQ(e.min.y, 20.0 - 176.5 * 2.0);
    // A grid that fits one block has one level; one sample more needs two.
    EXPECT_EQ(DemLodLayout::make(16, 16, 1.0, {0.0, 0.0}, 16).levels, 1);
    EXPECT_EQ(DemLodLayout::make(17, 3, 1.0, {0.0, 0.0}, 16).levels, 2);
    EXPECT_THROW(DemLodLayout::make(1, 10, 1.0, {0.0, 0.0}, 16), std::invalid_argument);
    EXPECT_THROW(DemLodLayout::make(10, 10, 0.0, {0.0, 0.0}, 16), std::invalid_argument);
    EXPECT_THROW(DemLodLayout::make(10, 10, INFINITY, {0.0, 0.0}, 16), std::invalid_argument);
    EXPECT_THROW(DemLodLayout::make(10, 10, 1.0, {0.0, 0.0}, 15), std::invalid_argument);
    EXPECT_THROW(DemLodLayout::make(10, 10, 1.0, {0.0, 0.0}, 2), std::invalid_argument);
}

TEST_F(DemLod, InheritFromParentTakesTheQuarterOfTheParent) {
    const int bs = 4;
    std::vector<float> parent(16), block(16, -1.0f);
    for (int k = 0; k < 16; ++k) parent[std::size_t(k)] = float(k);
    inheritFromParent(block, parent, 3, 2, bs);  // odd column: right half; even row: top half
    // Parent samples (2 + m/2, 0 + q/2) at even (m, q).
    EXPECT_EQ(block[0], parent[2]);
    EXPECT_EQ(block[2], parent[3]);
    EXPECT_EQ(block[8], parent[6]);
    EXPECT_EQ(block[10], parent[7]);
    EXPECT_EQ(block[1], -1.0f);
    EXPECT_EQ(block[4], -1.0f);
    std::vector<float> small(15);
    EXPECT_THROW(inheritFromParent(block, small, 0, 0, bs), std::invalid_argument);
}

// ---- write and read back ----

TEST_F(DemLod, EveryLevelReadBackIsEveryStepthSample) {
    const Dem dem = randomishDem(300, 177);
    for (int bs : {16, 64}) {
        SCOPED_TRACE("block side " + std::to_string(bs));
        const std::string path = file("tree" + std::to_string(bs) + ".gpkg");
        const DemLodLayout layout = writeTree(path, dem, bs);
        const DemLodFile tree(path);
        ASSERT_EQ(tree.layout(), layout);
        EXPECT_EQ(layout.levels, bs == 16 ? 6 : 4);
        EXPECT_EQ(tree.path(), path);
        for (int l = 0; l < layout.levels; ++l) {
            const Dem level = readDemLevel(tree, l);
            const int step = layout.step(l);
            ASSERT_EQ(level.width(), layout.levelWidth(l));
            ASSERT_EQ(level.height(), layout.levelHeight(l));
            int wrong = 0;
            for (int r = 0; r < level.height(); ++r)
                for (int k = 0; k < level.width(); ++k)
                    wrong += fromTop(level, k, r) != fromTop(dem, k * step, r * step);
            EXPECT_EQ(wrong, 0) << "level " << l;
            // Cells centred on the samples: the top-left sample is the Dem's.
            const Vec2 p = level.samplePosition(0, level.height() - 1), q = dem.samplePosition(0, dem.height() - 1);
            EXPECT_NEAR(p.x, q.x, 1e-9);
            EXPECT_NEAR(p.y, q.y, 1e-9);
            EXPECT_NEAR(level.cellSize().x, 2.0 * step, 1e-12);
        }
        // The finest level is the Dem, exactly, over the same extent.
        const Dem finest = readDemLevel(tree, layout.levels - 1);
        EXPECT_EQ(finest.heights(), dem.heights());
        EXPECT_NEAR(finest.extent().min.x, dem.extent().min.x, 1e-9);
        EXPECT_NEAR(finest.extent().min.y, dem.extent().min.y, 1e-9);
        EXPECT_NEAR(finest.extent().max.x, dem.extent().max.x, 1e-9);
        EXPECT_NEAR(finest.extent().max.y, dem.extent().max.y, 1e-9);
        EXPECT_THROW(readDemLevel(tree, layout.levels), std::out_of_range);
        EXPECT_THROW(tree.readStored(1, 2, 0), std::out_of_range);
        // A block beyond the grid has no tile and reads as nulls.
        const auto beyond = tree.readStored(layout.levels - 1, layout.blockColumns(layout.levels - 1), 0);
        EXPECT_TRUE(std::all_of(beyond.begin(), beyond.end(), isNull));
    }
}

TEST_F(DemLod, TilesAreThoseOfTheBlocksOnTheGridAndHoldEverySampleOnce) {
    const Dem dem = randomishDem(300, 177);
    for (int bs : {16, 64}) {
        SCOPED_TRACE("block side " + std::to_string(bs));
        const std::string path = file("tree" + std::to_string(bs) + ".gpkg");
        const DemLodLayout layout = writeTree(path, dem, bs);
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM dem_lod"), bs == 16 ? 312 : 24);
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM dem_lod"), layout.tileCount());
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_2d_gridded_tile_ancillary WHERE tpudt_name = 'dem_lod'"),
                  layout.tileCount());
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM dem_lod t LEFT JOIN gpkg_2d_gridded_tile_ancillary a ON a.tpudt_id = "
                                  "t.id WHERE a.id IS NULL"),
                  0);
        // Every stored (non-null) sample over all tiles: each sample of the grid once, and every
        // stored value is the sample of its place.
        std::int64_t stored = 0, misplaced = 0;
        auto s = db.prepare("SELECT zoom_level, tile_column, tile_row, tile_data FROM dem_lod");
        while (s.step()) {
            const int l = int(s.integer(0)), c = int(s.integer(1)), r = int(s.integer(2));
            ASSERT_TRUE(layout.hasBlock(l, c, r)) << l << " " << c << " " << r;
            const DecodedFloats tile = decodeFloatTiff(s.blob(3));
            ASSERT_EQ(tile.width, bs);
            const int step = layout.step(l);
            for (int q = 0; q < bs; ++q)
                for (int m = 0; m < bs; ++m) {
                    const float v = tile.values[std::size_t(q * bs + m)];
                    if (isNull(v)) continue;
                    ++stored;
                    const int i = (c * bs + m) * step, t = (r * bs + q) * step;
                    misplaced += i >= dem.width() || t >= dem.height() || v != fromTop(dem, i, t);
                }
        }
        EXPECT_EQ(stored, std::int64_t(300) * 177);
        EXPECT_EQ(misplaced, 0);
        EXPECT_EQ(db.queryText("SELECT grid_cell_encoding FROM gpkg_2d_gridded_coverage_ancillary WHERE tile_matrix_set_name = "
                               "'dem_lod'"),
                  "grid-value-is-corner");
        EXPECT_EQ(db.queryText("SELECT data_type FROM gpkg_contents WHERE table_name = 'dem_lod'"), "2d-gridded-coverage");
    }
}

TEST_F(DemLod, TheDigestCoversEverySampleAndTheLayout) {
    const Dem a = randomishDem(40, 33);
    std::vector<float> z = a.heights();
    z[std::size_t(17 * 40 + 5)] += 0.25f;
    const Dem b(a.extent(), 40, 33, z);
    const Dem shifted({{a.extent().min.x + 1.0, a.extent().min.y}, {a.extent().max.x + 1.0, a.extent().max.y}}, 40, 33,
                      a.heights());
    writeTree(file("a.gpkg"), a, 16);
    writeTree(file("a2.gpkg"), a, 16);
    writeTree(file("a32.gpkg"), a, 32);
    writeTree(file("b.gpkg"), b, 16);
    writeTree(file("s.gpkg"), shifted, 16);
    const std::string d = DemLodFile(file("a.gpkg")).digest();
    EXPECT_EQ(d.size(), 16u);
    EXPECT_EQ(DemLodFile(file("a2.gpkg")).digest(), d);
    EXPECT_NE(DemLodFile(file("a32.gpkg")).digest(), d);
    EXPECT_NE(DemLodFile(file("b.gpkg")).digest(), d);
    EXPECT_NE(DemLodFile(file("s.gpkg")).digest(), d);
}

TEST_F(DemLod, WriterMisuseIsRefused) {
    const std::string path = file("w.gpkg");
    createEmptyGpkg(path);
    SqliteDb db(path, SqliteDb::Mode::ReadWrite);
    const DemLodLayout layout = DemLodLayout::make(20, 10, 1.0, {0.0, 0.0}, 8);
    db.exec("BEGIN");
    EXPECT_THROW(DemLodWriter(db, layout, 4242), std::invalid_argument);  // no such CRS row
    DemLodLayout wrong = layout;
    wrong.levels = 7;
    EXPECT_THROW(DemLodWriter(db, wrong, -1), std::invalid_argument);
    {
        DemLodWriter w(db, layout, -1);
        std::vector<float> row(20, 5.0f);
        EXPECT_THROW(w.addRow(std::vector<float>(19, 1.0f)), std::invalid_argument);
        row[7] = NAN;
        expectError<std::invalid_argument>([&] { w.addRow(row); }, {"DemLodWriter::addRow()", "sample (7, 0)"});
        row[7] = kDemNull;
        EXPECT_THROW(w.addRow(row), std::invalid_argument);
        row[7] = 1.0f;
        w.addRow(row);
        expectError<std::invalid_argument>([&] { w.finish(); }, {"1 of 10 rows"});
        for (int t = 1; t < 10; ++t) w.addRow(row);
        EXPECT_THROW(w.addRow(row), std::invalid_argument);
        w.finish();
        EXPECT_THROW(w.finish(), std::invalid_argument);
        EXPECT_EQ(w.tilesWritten(), std::uint64_t(layout.tileCount()));
        EXPECT_GT(w.bytesWritten(), 0u);
    }
    EXPECT_THROW(DemLodWriter(db, layout, -1), std::invalid_argument);  // the table exists
    db.exec("COMMIT");
    db.close();
    EXPECT_EQ(readDemLevel(DemLodFile(path), 1).heights()[3], 5.0f);
    // Cells that are not square.
    createEmptyGpkg(file("r.gpkg"));
    SqliteDb r(file("r.gpkg"), SqliteDb::Mode::ReadWrite);
    EXPECT_THROW(writeDemLod(r, Dem({{0.0, 0.0}, {10.0, 20.0}}, 10, 10, std::vector<float>(100, 1.0f)), 8, -1),
                 std::invalid_argument);
}

TEST_F(DemLod, AnUnfinishedTreeIsRefused) {
    const std::string path = file("u.gpkg");
    createEmptyGpkg(path);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("BEGIN");
        DemLodWriter w(db, DemLodLayout::make(20, 10, 1.0, {0.0, 0.0}, 8), -1);
        w.addRow(std::vector<float>(20, 1.0f));
        db.exec("COMMIT");
    }
    expectError<DemLodError>([&] { DemLodFile f(path); }, {path, "lacet_dem_lod", "did not finish"});
    expectError<DemLodError>([&] { DemLodFile f(file("none.gpkg")); }, {file("none.gpkg")});
}

// ---- damage ----

TEST_F(DemLod, ACorruptTileNamesTheFileAndTheBlock) {
    const std::string path = file("c.gpkg");
    const DemLodLayout layout = writeTree(path, randomishDem(300, 177), 16);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE dem_lod SET tile_data = x'49492a00deadbeefdeadbeef0102030405' WHERE zoom_level = 3 AND "
                "tile_column = 4 AND tile_row = 1");
        // A tile that decodes, with a height where the parent holds the sample.
        const std::vector<float> ones(16 * 16, 1.0f);
        auto s = db.prepare("UPDATE dem_lod SET tile_data = ? WHERE zoom_level = 2 AND tile_column = 1 AND tile_row = 0");
        const auto bytes = encodeFloatTiff(ones, 16, 16);
        s.bindBlob(1, bytes);
        s.step();
        db.exec("DELETE FROM dem_lod WHERE zoom_level = 5 AND tile_column = 3 AND tile_row = 2");
    }
    const DemLodFile tree(path);
    expectError<DemLodError>([&] { tree.readStored(3, 4, 1); },
                             {path, "block (level 3, column 4, row 1)", "does not decode"});
    expectError<DemLodError>([&] { tree.readStored(2, 1, 0); },
                             {path, "block (level 2, column 1, row 0)", "the null is expected"});
    expectError<DemLodError>([&] { tree.readStored(5, 3, 2); }, {path, "block (level 5, column 3, row 2)", "missing"});
    expectError<DemLodError>([&] { readDemLevel(tree, 3); }, {path, "block (level"});
    EXPECT_NO_THROW(tree.readStored(3, 4, 0));
    EXPECT_NO_THROW(readDemLevel(tree, 1));
    (void)layout;
}

// ---- GIS tools ----

TEST_F(DemLod, GdalOpensTheTreeAsAFloat32Coverage) {
    const Dem dem = randomishDem(300, 177);
    const std::string path = file("g.gpkg");
    const DemLodLayout layout = writeTree(path, dem, 16, 100000);
    GDALAllRegister();
    const char* drivers[] = {"GPKG", nullptr};
    for (int zoom : {0, layout.levels - 1}) {
        SCOPED_TRACE("zoom level " + std::to_string(zoom));
        const std::string zoomOption = "ZOOM_LEVEL=" + std::to_string(zoom);
        const char* options[] = {"TABLE=dem_lod", zoomOption.c_str(), nullptr};
        std::unique_ptr<GDALDataset> ds(
            GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, options, nullptr));
        ASSERT_TRUE(ds);
        ASSERT_EQ(ds->GetRasterCount(), 1);
        GDALRasterBand* band = ds->GetRasterBand(1);
        EXPECT_EQ(band->GetRasterDataType(), GDT_Float32);
        int hasNoData = 0;
        EXPECT_EQ(band->GetNoDataValue(&hasNoData), double(kDemNull));
        EXPECT_TRUE(hasNoData);
        const int levelW = layout.levelWidth(zoom), levelH = layout.levelHeight(zoom), step = layout.step(zoom);
        // GDAL sizes every level from the contents' extent (the finest grid) and rounds: a coarse
        // level's last column or row, whose sample lies in the padding's half of a pixel, can be
        // left out of its raster.
        if (zoom == layout.levels - 1) {
            EXPECT_EQ(ds->GetRasterXSize(), levelW);
            EXPECT_EQ(ds->GetRasterYSize(), levelH);
        }
        ASSERT_GE(ds->GetRasterXSize(), levelW - 1);
        ASSERT_GE(ds->GetRasterYSize(), levelH - 1);
        const int w = std::min(levelW, ds->GetRasterXSize()), h = std::min(levelH, ds->GetRasterYSize());
        double gt[6];
        ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
        // GDAL 3.6 reads grid-value-is-corner as AREA_OR_POINT=Point with the geotransform's origin on
        // the top-left sample, at every level.
        EXPECT_EQ(gt[0], layout.origin.x);
        EXPECT_EQ(gt[3], layout.origin.y);
        const char* areaOrPoint = ds->GetMetadataItem("AREA_OR_POINT");
        EXPECT_STREQ(areaOrPoint ? areaOrPoint : "", "Point");
        EXPECT_NEAR(gt[1], layout.levelCell(zoom), 1e-9);
        std::vector<float> values(std::size_t(w) * std::size_t(h));
        ASSERT_EQ(band->RasterIO(GF_Read, 0, 0, w, h, values.data(), w, h, GDT_Float32, 0, 0, nullptr), CE_None);
        std::int64_t wrong = 0, stored = 0;
        for (int r = 0; r < h; ++r)
            for (int k = 0; k < w; ++k) {
                const float v = values[std::size_t(r) * std::size_t(w) + std::size_t(k)];
                const bool inherited = zoom > 0 && k % 2 == 0 && r % 2 == 0;
                if (inherited) {
                    wrong += !isNull(v);
                } else {
                    ++stored;
                    wrong += v != fromTop(dem, k * step, r * step);
                }
            }
        EXPECT_EQ(wrong, 0);
        EXPECT_GT(stored, 0);
        const OGRSpatialReference* srs = ds->GetSpatialRef();
        ASSERT_TRUE(srs);
        EXPECT_TRUE(srs->IsProjected());
    }
}

// ---- tile sizes ----

TEST_F(DemLod, TileEncodingSizes) {
    const Dem dem = smoothDem(1000, 700);
    const std::string path = file("sizes.gpkg");
    const DemLodLayout layout = writeTree(path, dem, 256);
    const DemLodFile tree(path);
    std::uint64_t plain = 0, deflate = 0, predicted = 0;
    for (int l = 0; l < layout.levels; ++l)
        for (int r = 0; r < layout.blockRows(l); ++r)
            for (int c = 0; c < layout.blockColumns(l); ++c) {
                const std::vector<float> stored = tree.readStored(l, c, r);
                const auto a = encodeFloatTiff(stored, 256, 256);
                const auto b = encodeFloatTiffDeflate(stored, 256, 256, 6, false);
                const auto p = encodeFloatTiffDeflate(stored, 256, 256, 6, true);
                EXPECT_EQ(decodeFloatTiff(b).values, decodeFloatTiff(a).values);
                const auto back = decodeFloatTiff(p).values;
                EXPECT_TRUE(std::equal(back.begin(), back.end(), stored.begin(),
                                       [](float x, float y) { return std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); }));
                plain += a.size();
                deflate += b.size();
                predicted += p.size();
            }
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    const auto written = std::uint64_t(db.queryInteger("SELECT sum(length(tile_data)) FROM dem_lod"));
    std::cout << "DEM LOD tiles of a 1000 x 700 smooth DEM, " << layout.tileCount() << " tiles of 256^2: uncompressed "
              << plain << " bytes, deflate " << deflate << ", deflate + float predictor " << predicted << ", stored "
              << written << " (" << (1000 * 700 * 4) << " bytes of floats)\n";
    EXPECT_EQ(written, predicted);
    EXPECT_LT(deflate, plain);
}

// ---- the scene file ----

// A georeferenced document whose streamed DEM is a tree at `treePath` written under `srsId` (100000:
// a row of the scene's own WKT; -1: undefined Cartesian, as writeDemLodFile writes an import's).
SceneDocument lodDocument(const std::string& treePath, int srsId = 100000) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({1, 300});
    doc.georeference.valid = true;
    doc.georeference.lon0 = 1.5;
    doc.georeference.lat0 = 42.5;
    doc.georeference.crsWkt = kWkt;
    const Box& e = doc.scene.extent;
    const double cell = (e.max.x - e.min.x) / 300.0;
    writeTree(treePath, randomishDem(300, 177, cell, e.min), 16, srsId);
    auto lod = std::make_shared<const DemLodFile>(treePath);
    doc.dem = readDemLevel(*lod, levelAtMost(lod->layout(), kInMemoryDemSide));
    doc.demLod = std::move(lod);
    return doc;
}

TEST_F(DemLod, SceneFileWithAStreamedDemSavesLoadsAndSavesOverItself) {
    const SceneDocument doc = lodDocument(file("tree.gpkg"));
    const std::string path = file("scene.gpkg");
    saveScene(path, doc);
    const SceneDocument back = loadScene(path);
    ASSERT_TRUE(back.demLod);
    EXPECT_EQ(back.demLod->path(), path);
    EXPECT_EQ(back.demLod->layout(), doc.demLod->layout());
    EXPECT_EQ(back.demLod->digest(), doc.demLod->digest());
    ASSERT_TRUE(back.dem);
    EXPECT_EQ(back.dem->heights(), doc.dem->heights());
    EXPECT_EQ(back.dem->heights(), readDemLevel(*back.demLod, levelAtMost(back.demLod->layout(), kInMemoryDemSide)).heights());
    EXPECT_EQ(sceneChecksumText(back), sceneChecksumText(doc));
    {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        EXPECT_FALSE(db.hasTable(kDemRasterTable));
        EXPECT_EQ(db.queryText("SELECT value FROM lacet_meta WHERE key = 'dem'"), "dem_lod");
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM dem_lod"), doc.demLod->layout().tileCount());
        // The CRS row of the tree's definition is the scene's.
        EXPECT_EQ(db.queryText("SELECT s.definition FROM gpkg_tile_matrix_set t JOIN gpkg_spatial_ref_sys s USING (srs_id) "
                               "WHERE t.table_name = 'dem_lod'"),
                  kWkt);
    }
    // The checksum covers the tree, not the derived doc.dem: without the tree it differs.
    SceneDocument plain = doc;
    plain.demLod.reset();
    EXPECT_NE(sceneChecksumText(plain), sceneChecksumText(doc));
    // Saving over the file the tree is read from (the loaded document reads `path`).
    saveScene(path, back);
    const SceneDocument again = loadScene(path);
    EXPECT_EQ(again.dem->heights(), doc.dem->heights());
    EXPECT_EQ(again.demLod->digest(), doc.demLod->digest());
    EXPECT_EQ(readDemLevel(*again.demLod, again.demLod->layout().levels - 1).heights(),
              readDemLevel(*doc.demLod, doc.demLod->layout().levels - 1).heights());
    // The first loaded document still reads its tree (the file it opened was replaced).
    EXPECT_EQ(readDemLevel(*back.demLod, 2).heights(), readDemLevel(*doc.demLod, 2).heights());
    // And a save of a document without it is the scene file it always was.
    saveScene(file("plain.gpkg"), plain);
    EXPECT_FALSE(loadScene(file("plain.gpkg")).demLod);
}

TEST_F(DemLod, SceneFileWithAMissingOrCorruptTileIsRefused) {
    const SceneDocument doc = lodDocument(file("tree.gpkg"));
    const std::string missing = file("missing.gpkg"), corrupt = file("corrupt.gpkg");
    saveScene(missing, doc);
    saveScene(corrupt, doc);
    {
        SqliteDb db(missing, SqliteDb::Mode::ReadWrite);
        db.exec("DELETE FROM dem_lod WHERE zoom_level = 4 AND tile_column = 2 AND tile_row = 3");
    }
    expectError<SceneFileError>([&] { loadScene(missing); }, {missing, "of level 4"});
    {
        SqliteDb db(corrupt, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE dem_lod SET tile_data = x'00112233445566778899' WHERE zoom_level = 4 AND tile_column = 2 AND "
                "tile_row = 3");
    }
    expectError<SceneFileError>([&] { loadScene(corrupt); }, {corrupt, "block (level 4, column 2, row 3)"});
    // A tree moved out of place: its layout no longer matches the scene's DEM grid.
    {
        SqliteDb db(missing, SqliteDb::Mode::ReadWrite);
        db.exec("UPDATE lacet_meta SET value = '299' WHERE key = 'dem_width'");
    }
    expectError<SceneFileError>([&] { loadScene(missing); }, {missing, "300 x 177"});
}

// A tree written in scene metres (srs_id -1, as an import's and `lacet synth --dem-side`'s are) gets
// the scene's CRS row when saved, the one the feature tables have: GIS tools see its coordinates in
// the scene's Transverse Mercator, not as degrees of an undefined geographic CRS.
TEST_F(DemLod, SavedTreeHasTheScenesCrsRowAsTheFeatureTablesDo) {
    for (const bool georeferenced : {true, false}) {
        SCOPED_TRACE(georeferenced ? "georeferenced" : "no georeference");
        const std::string tree = file(georeferenced ? "tree_geo.gpkg" : "tree_plain.gpkg");
        SceneDocument doc = lodDocument(tree, -1);
        if (!georeferenced) doc.georeference = {};
        const std::string path = file(georeferenced ? "geo.gpkg" : "plain.gpkg");
        saveScene(path, doc);
        std::int64_t treeSrs = 0;
        {
            SqliteDb db(path, SqliteDb::Mode::ReadOnly);
            treeSrs = db.queryInteger("SELECT srs_id FROM gpkg_tile_matrix_set WHERE table_name = 'dem_lod'");
            EXPECT_EQ(db.queryInteger("SELECT srs_id FROM gpkg_contents WHERE table_name = 'dem_lod'"), treeSrs);
            ASSERT_GT(db.queryInteger("SELECT count(*) FROM gpkg_geometry_columns"), 0);
            EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_geometry_columns WHERE srs_id <> " + std::to_string(treeSrs)), 0)
                << "every feature table has the tree's CRS row";
            EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_contents WHERE srs_id IS NOT NULL AND srs_id <> " +
                                      std::to_string(treeSrs)),
                      0);
            if (georeferenced) {
                EXPECT_GT(treeSrs, 0);
                EXPECT_EQ(db.queryText("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = " + std::to_string(treeSrs)), kWkt);
            } else {
                EXPECT_EQ(treeSrs, -1) << "undefined Cartesian, not 0 (undefined geographic)";
            }
        }
        const SceneDocument back = loadScene(path);
        EXPECT_EQ(back.demLod->digest(), doc.demLod->digest());
        if (!georeferenced) continue;
        // Saved again from the saved file: the same row.
        const std::string again = file("again.gpkg");
        saveScene(again, back);
        {
            SqliteDb db(again, SqliteDb::Mode::ReadOnly);
            const std::int64_t srs = db.queryInteger("SELECT srs_id FROM gpkg_tile_matrix_set WHERE table_name = 'dem_lod'");
            EXPECT_EQ(db.queryText("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = " + std::to_string(srs)), kWkt);
            EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_geometry_columns WHERE srs_id <> " + std::to_string(srs)), 0);
        }
        // GDAL reads the coverage in the projected CRS.
        GDALAllRegister();
        const char* drivers[] = {"GPKG", nullptr};
        const char* options[] = {"TABLE=dem_lod", nullptr};
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, options, nullptr));
        ASSERT_TRUE(ds);
        const OGRSpatialReference* srs = ds->GetSpatialRef();
        ASSERT_TRUE(srs);
        EXPECT_TRUE(srs->IsProjected());
        EXPECT_FALSE(srs->IsGeographic());
    }
}

// The tree is copied from its file read-only: a file that is gone is refused by name and not made
// again (an empty SQLite file where it was).
TEST_F(DemLod, SavingATreeWhoseFileIsGoneFailsAndCreatesNothing) {
    const std::string tree = file("gone.gpkg");
    const SceneDocument doc = lodDocument(tree, -1);
    fs::remove(tree);
    const std::string path = file("scene.gpkg");
    expectError<SceneFileError>([&] { saveScene(path, doc); }, {path, tree, "no such file"});
    EXPECT_FALSE(fs::exists(tree));
    EXPECT_FALSE(fs::exists(path));
    {
        createEmptyGpkg(file("target.gpkg"));
        SqliteDb db(file("target.gpkg"), SqliteDb::Mode::ReadWrite);
        expectError<DemLodError>([&] { copyDemLod(db, tree, -1); }, {tree, "no such file"});
        EXPECT_FALSE(fs::exists(tree));
        expectError<DemLodError>([&] { copyDemLod(db, dir_.string(), -1); }, {dir_.string(), "not a regular file"});
        // A target without the row asked for.
        writeTree(file("t2.gpkg"), randomishDem(40, 30), 16);
        expectError<DemLodError>([&] { copyDemLod(db, file("t2.gpkg"), 4242); }, {"srs_id 4242"});
        EXPECT_FALSE(db.hasTable(kDemLodTable));
        // A path that needs escaping in a URI is still the file it names.
        const std::string odd = file("a?b#c%20 d.gpkg");
        fs::copy_file(file("t2.gpkg"), odd);
        copyDemLod(db, odd, -1);
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM dem_lod"), DemLodFile(odd).layout().tileCount());
    }
}

}  // namespace
}  // namespace lacet
