// The GeoPackage tile tables of io/gpkg_coverage.h: what GDAL reads of them, and that a dropped
// table leaves no row behind in the metadata tables.
#include "io/gpkg_coverage.h"

#include <filesystem>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "tests/io/gis_fixtures.h"
#include "io/gpkg_dem.h"
#include "io/sqlite_db.h"

namespace lacet {
namespace {

GpkgTileTable table(const std::string& name, GpkgTileTable::DataType type, int levels, int tilePixels) {
    GpkgTileTable t{.name = name, .dataType = type, .description = name + " test", .contents = {{100.0, 200.0}, {900.0, 1000.0}},
                    .matrixSet = {{100.0, 200.0}, {900.0, 1000.0}}, .srsId = -1, .matrices = {}};
    for (int l = 0; l < levels; ++l)
        t.matrices.push_back({.zoomLevel = l, .matrixWidth = 1 << l, .matrixHeight = 1 << l, .tileWidth = tilePixels,
                              .tileHeight = tilePixels, .pixelXSize = 800.0 / double((1 << l) * tilePixels),
                              .pixelYSize = 800.0 / double((1 << l) * tilePixels)});
    return t;
}

std::int64_t rowsNamed(SqliteDb& db, const std::string& table, const std::string& column, const std::string& name) {
    return db.queryInteger("SELECT count(*) FROM " + table + " WHERE " + column + " = '" + name + "'");
}

TEST(GpkgCoverage, GdalReadsBothKindsAtTheirSizeAndDropLeavesNoRow) {
    const auto dir = test::scratchDir("gpkg_coverage");
    const std::string path = (dir / "t.gpkg").string();
    createEmptyGpkg(path);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        createGpkgTileTable(db, table("colour", GpkgTileTable::DataType::Tiles, 3, 256));
        createGpkgTileTable(db, table("heights", GpkgTileTable::DataType::GriddedCoverage, 2, 64),
                            {.precision = 0.0, .dataNull = -9999.0, .gridCellEncoding = "grid-value-is-corner", .uom = "m"});
        addGpkgExtension(db, "colour", "tile_data", "gpkg_webp", "http://www.geopackage.org/spec120/#extension_tiles_webp");
        addGpkgExtension(db, "colour", "tile_data", "gpkg_webp", "http://www.geopackage.org/spec120/#extension_tiles_webp");
        EXPECT_EQ(rowsNamed(db, "gpkg_extensions", "table_name", "colour"), 1);  // a second registration is kept once
        EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_2d_gridded_coverage_ancillary WHERE tile_matrix_set_name = "
                                  "'heights' AND data_null = -9999.0 AND grid_cell_encoding = 'grid-value-is-corner'"),
                  1);
    }
    GDALAllRegister();
    for (const auto& [name, side] : {std::pair<std::string, int>{"colour", 1024}, {"heights", 128}}) {
        GDALDataset* ds = GDALDataset::Open(("GPKG:" + path + ":" + name).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
        ASSERT_NE(ds, nullptr) << name;
        EXPECT_EQ(ds->GetRasterXSize(), side) << name;
        EXPECT_EQ(ds->GetRasterYSize(), side) << name;
        double gt[6];
        ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
        EXPECT_DOUBLE_EQ(gt[0], 100.0);
        EXPECT_DOUBLE_EQ(gt[3], 1000.0);
        EXPECT_DOUBLE_EQ(gt[1], 800.0 / side);
        GDALClose(ds);
    }
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        for (const std::string name : {"colour", "heights"}) {
            dropGpkgTileTable(db, name);
            EXPECT_FALSE(db.hasTable(name));
            for (const char* meta : {"gpkg_contents", "gpkg_tile_matrix_set", "gpkg_tile_matrix", "gpkg_extensions"})
                EXPECT_EQ(rowsNamed(db, meta, "table_name", name), 0) << meta;
            EXPECT_EQ(rowsNamed(db, "gpkg_2d_gridded_coverage_ancillary", "tile_matrix_set_name", name), 0);
        }
        dropGpkgTileTable(db, "never_made");  // nothing to drop is no error
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
