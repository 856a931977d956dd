#pragma once
// A tiled table of a GeoPackage, as the standard states it (OGC 12-128r15 for tiles, 17-066r1 for
// 2D gridded coverages): the tile table itself, its gpkg_contents row, its tile matrix set and one
// tile matrix per zoom level, and for a gridded coverage the extension rows and the coverage's
// ancillary row. The one place Lacet writes these: the DEM LOD tree (io/dem_lod.h), the pyramid
// (pyramid/pyramid_store.h), and the stores that follow.
//
// Every call works on `db`'s main database inside the caller's transaction, if any; a SQLite failure
// throws SqliteError. Numbers go into SQL as "%.17g" (exact when read back).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/types.h"

namespace lacet {

class SqliteDb;

// One zoom level's tile matrix.
struct GpkgTileMatrix {
    int zoomLevel = 0;
    std::int64_t matrixWidth = 1, matrixHeight = 1;  // tiles across and down
    int tileWidth = 256, tileHeight = 256;           // pixels (samples) of a tile
    double pixelXSize = 1.0, pixelYSize = 1.0;       // CRS units per pixel
};

// A tile table to create.
struct GpkgTileTable {
    enum class DataType { Tiles, GriddedCoverage };
    std::string name;
    DataType dataType = DataType::Tiles;
    std::string description;          // gpkg_contents.description
    Box contents;                     // gpkg_contents bounds (the data's)
    Box matrixSet;                    // gpkg_tile_matrix_set bounds (the tiles')
    int srsId = -1;                   // a gpkg_spatial_ref_sys row
    std::vector<GpkgTileMatrix> matrices;
};

// The coverage's ancillary row of a GriddedCoverage table (datatype 'float', scale 1, offset 0).
struct GpkgGriddedCoverage {
    double precision = 0.0;
    std::optional<double> dataNull;            // the value of a sample without data
    std::string gridCellEncoding = "grid-value-is-center";  // or "grid-value-is-corner"
    std::string uom = "m";
};

// "%.17g" of v.
std::string gpkgReal(double v);

// Creates those of the tile tables' metadata tables (gpkg_tile_matrix_set, gpkg_tile_matrix,
// gpkg_extensions) that `db` lacks; with `gridded`, also the two ancillary tables of 17-066r1.
void ensureGpkgTileTables(SqliteDb& db, bool gridded = false);

// CREATE TABLE of a tile table named `name` in `schema` ("main", or an ATTACH name).
std::string gpkgTileTableSql(const std::string& schema, const std::string& name);

// Creates table `t` with its gpkg_contents row, tile matrix set and matrices; for a gridded coverage
// also its extension rows and `coverage`'s ancillary row.
void createGpkgTileTable(SqliteDb& db, const GpkgTileTable& t, const GpkgGriddedCoverage& coverage = {});

// Registers extension `extension` of `table` (`column`, or none when empty) in gpkg_extensions,
// created when missing; a row already there is kept.
void addGpkgExtension(SqliteDb& db, const std::string& table, const std::string& column, const std::string& extension,
                      const std::string& definition, const std::string& scope = "read-write");

// Drops tile table `name` (if there) and its rows in every metadata table the file has.
void dropGpkgTileTable(SqliteDb& db, const std::string& name);

// The definition of the gridded coverage extension (17-066r1).
inline constexpr const char* kGpkgGriddedCoverageDefinition = "http://docs.opengeospatial.org/is/17-066r1/17-066r1.html";

}  // namespace lacet
