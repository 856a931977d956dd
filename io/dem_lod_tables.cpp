// The GeoPackage side of the DEM LOD tree (io/dem_lod.h) that the writer, the reader and the copy
// share: the coverage's tables, the exact text of doubles in kDemLodMetaTable, the messages.
#include <charconv>
#include <cmath>
#include <cstdio>

#include "io/dem_lod_internal.h"
#include "io/sqlite_db.h"

namespace lacet::dem_lod_detail {

// C hex float ("0x1.f4p+9", "-0x0p+0"), exact and locale-independent; finite values only.
std::string hexText(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, std::fabs(v), std::chars_format::hex);
    return std::string(std::signbit(v) ? "-0x" : "0x") + std::string(buf, r.ptr);
}

bool parseHex(std::string_view s, double& v) {
    const bool negative = s.starts_with("-");
    if (negative) s.remove_prefix(1);
    if (!s.starts_with("0x") || s.size() < 3) return false;
    const auto r = std::from_chars(s.data() + 2, s.data() + s.size(), v, std::chars_format::hex);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return false;
    if (negative) v = -v;
    return true;
}

// "%.17g": exact when read back, what GIS tools expect in the gpkg_* tables' SQL.
std::string sqlReal(double v) {
    char s[64];
    std::snprintf(s, sizeof s, "%.17g", v);
    return s;
}

std::string blockName(int level, int col, int row) {
    return "block (level " + std::to_string(level) + ", column " + std::to_string(col) + ", row " + std::to_string(row) + ")";
}

// ---- the GeoPackage tables the coverage needs (the DDL of OGC 12-128r15 and 17-066r1) ----

// Creates those of the tables a 2D gridded coverage needs that `db`'s main database lacks.
void ensureCoverageTables(SqliteDb& db) {
    db.exec(
        "CREATE TABLE IF NOT EXISTS gpkg_tile_matrix_set (table_name TEXT NOT NULL PRIMARY KEY, srs_id INTEGER NOT NULL, "
        "min_x DOUBLE NOT NULL, min_y DOUBLE NOT NULL, max_x DOUBLE NOT NULL, max_y DOUBLE NOT NULL, CONSTRAINT "
        "fk_gtms_table_name FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name), CONSTRAINT fk_gtms_srs FOREIGN "
        "KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id));"
        "CREATE TABLE IF NOT EXISTS gpkg_tile_matrix (table_name TEXT NOT NULL, zoom_level INTEGER NOT NULL, matrix_width "
        "INTEGER NOT NULL, matrix_height INTEGER NOT NULL, tile_width INTEGER NOT NULL, tile_height INTEGER NOT NULL, "
        "pixel_x_size DOUBLE NOT NULL, pixel_y_size DOUBLE NOT NULL, CONSTRAINT pk_ttm PRIMARY KEY (table_name, "
        "zoom_level), CONSTRAINT fk_tmm_table_name FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name));"
        "CREATE TABLE IF NOT EXISTS gpkg_extensions (table_name TEXT, column_name TEXT, extension_name TEXT NOT NULL, "
        "definition TEXT NOT NULL, scope TEXT NOT NULL, CONSTRAINT ge_tce UNIQUE (table_name, column_name, "
        "extension_name));"
        "CREATE TABLE IF NOT EXISTS gpkg_2d_gridded_coverage_ancillary (id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
        "tile_matrix_set_name TEXT NOT NULL UNIQUE, datatype TEXT NOT NULL DEFAULT 'integer', scale REAL NOT NULL DEFAULT "
        "1.0, offset REAL NOT NULL DEFAULT 0.0, precision REAL DEFAULT 1.0, data_null REAL, grid_cell_encoding TEXT "
        "DEFAULT 'grid-value-is-center', uom TEXT, field_name TEXT DEFAULT 'Height', quantity_definition TEXT DEFAULT "
        "'Height', CONSTRAINT fk_g2dgtct_name FOREIGN KEY(tile_matrix_set_name) REFERENCES gpkg_tile_matrix_set ( "
        "table_name ) CHECK (datatype in ('integer','float')));"
        "CREATE TABLE IF NOT EXISTS gpkg_2d_gridded_tile_ancillary (id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
        "tpudt_name TEXT NOT NULL, tpudt_id INTEGER NOT NULL, scale REAL NOT NULL DEFAULT 1.0, offset REAL NOT NULL "
        "DEFAULT 0.0, min REAL DEFAULT NULL, max REAL DEFAULT NULL, mean REAL DEFAULT NULL, std_dev REAL DEFAULT NULL, "
        "CONSTRAINT fk_g2dgtat_name FOREIGN KEY (tpudt_name) REFERENCES gpkg_contents(table_name), UNIQUE (tpudt_name, "
        "tpudt_id));");
}

std::string createTileTableSql(const std::string& schema) {
    return "CREATE TABLE " + schema + ".\"" + kDemLodTable +
           "\" (id INTEGER PRIMARY KEY AUTOINCREMENT, zoom_level INTEGER NOT NULL, tile_column INTEGER NOT NULL, "
           "tile_row INTEGER NOT NULL, tile_data BLOB NOT NULL, UNIQUE (zoom_level, tile_column, tile_row))";
}

std::string createMetaTableSql(const std::string& schema) {
    return "CREATE TABLE " + schema + "." + kDemLodMetaTable + " (key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL)";
}

bool hasTableIn(SqliteDb& db, const std::string& schema, const std::string& table) {
    auto s = db.prepare("SELECT 1 FROM " + schema + ".sqlite_master WHERE type = 'table' AND name = ?");
    s.bindText(1, table);
    return s.step();
}

void refuse(const std::string& path, const std::string& reason) {
    throw DemLodError(path + ": DEM LOD tree '" + kDemLodTable + "': " + reason);
}

}  // namespace lacet::dem_lod_detail
