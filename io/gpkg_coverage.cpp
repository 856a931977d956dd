#include "io/gpkg_coverage.h"

#include <cstdio>

#include "io/sqlite_db.h"

namespace lacet {

std::string gpkgReal(double v) {
    char s[64];
    std::snprintf(s, sizeof s, "%.17g", v);
    return s;
}

void ensureGpkgTileTables(SqliteDb& db, bool gridded) {
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
        "extension_name));");
    if (!gridded) return;
    db.exec(
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

std::string gpkgTileTableSql(const std::string& schema, const std::string& name) {
    return "CREATE TABLE " + schema + ".\"" + name +
           "\" (id INTEGER PRIMARY KEY AUTOINCREMENT, zoom_level INTEGER NOT NULL, tile_column INTEGER NOT NULL, "
           "tile_row INTEGER NOT NULL, tile_data BLOB NOT NULL, UNIQUE (zoom_level, tile_column, tile_row))";
}

void addGpkgExtension(SqliteDb& db, const std::string& table, const std::string& column, const std::string& extension,
                      const std::string& definition, const std::string& scope) {
    ensureGpkgTileTables(db);
    auto s = db.prepare(
        "INSERT OR IGNORE INTO gpkg_extensions (table_name, column_name, extension_name, definition, scope) VALUES (?, ?, ?, "
        "?, ?)");
    s.bindText(1, table);
    if (column.empty()) s.bindNull(2);
    else s.bindText(2, column);
    s.bindText(3, extension);
    s.bindText(4, definition);
    s.bindText(5, scope);
    s.step();
}

void createGpkgTileTable(SqliteDb& db, const GpkgTileTable& t, const GpkgGriddedCoverage& coverage) {
    const bool gridded = t.dataType == GpkgTileTable::DataType::GriddedCoverage;
    ensureGpkgTileTables(db, gridded);
    db.exec(gpkgTileTableSql("main", t.name));
    {
        auto s = db.prepare(
            "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change, min_x, min_y, max_x, "
            "max_y, srs_id) VALUES (?, ?, ?, ?, strftime('%Y-%m-%dT%H:%M:%fZ','now'), ?, ?, ?, ?, ?)");
        s.bindText(1, t.name);
        s.bindText(2, gridded ? "2d-gridded-coverage" : "tiles");
        s.bindText(3, t.name);
        s.bindText(4, t.description);
        s.bind(5, t.contents.min.x);
        s.bind(6, t.contents.min.y);
        s.bind(7, t.contents.max.x);
        s.bind(8, t.contents.max.y);
        s.bind(9, std::int64_t(t.srsId));
        s.step();
    }
    {
        auto s = db.prepare("INSERT INTO gpkg_tile_matrix_set (table_name, srs_id, min_x, min_y, max_x, max_y) VALUES (?, ?, ?, ?, ?, ?)");
        s.bindText(1, t.name);
        s.bind(2, std::int64_t(t.srsId));
        s.bind(3, t.matrixSet.min.x);
        s.bind(4, t.matrixSet.min.y);
        s.bind(5, t.matrixSet.max.x);
        s.bind(6, t.matrixSet.max.y);
        s.step();
    }
    {
        auto s = db.prepare(
            "INSERT INTO gpkg_tile_matrix (table_name, zoom_level, matrix_width, matrix_height, tile_width, tile_height, "
            "pixel_x_size, pixel_y_size) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
        for (const GpkgTileMatrix& m : t.matrices) {
            s.bindText(1, t.name);
            s.bind(2, std::int64_t(m.zoomLevel));
            s.bind(3, m.matrixWidth);
            s.bind(4, m.matrixHeight);
            s.bind(5, std::int64_t(m.tileWidth));
            s.bind(6, std::int64_t(m.tileHeight));
            s.bind(7, m.pixelXSize);
            s.bind(8, m.pixelYSize);
            s.step();
            s.reset();
        }
    }
    if (!gridded) return;
    for (const char* a : {"gpkg_2d_gridded_coverage_ancillary", "gpkg_2d_gridded_tile_ancillary"})
        addGpkgExtension(db, a, "", "gpkg_2d_gridded_coverage", kGpkgGriddedCoverageDefinition);
    addGpkgExtension(db, t.name, "tile_data", "gpkg_2d_gridded_coverage", kGpkgGriddedCoverageDefinition);
    auto s = db.prepare(
        "INSERT INTO gpkg_2d_gridded_coverage_ancillary (tile_matrix_set_name, datatype, scale, offset, precision, data_null, "
        "grid_cell_encoding, uom) VALUES (?, 'float', 1.0, 0.0, ?, ?, ?, ?)");
    s.bindText(1, t.name);
    s.bind(2, coverage.precision);
    if (coverage.dataNull) s.bind(3, *coverage.dataNull);
    else s.bindNull(3);
    s.bindText(4, coverage.gridCellEncoding);
    s.bindText(5, coverage.uom);
    s.step();
}

void dropGpkgTileTable(SqliteDb& db, const std::string& name) {
    db.exec("DROP TABLE IF EXISTS \"" + name + "\"");
    const auto deleteRows = [&](const char* table, const char* column) {
        if (!db.hasTable(table)) return;
        auto s = db.prepare(std::string("DELETE FROM ") + table + " WHERE " + column + " = ?");
        s.bindText(1, name);
        s.step();
    };
    deleteRows("gpkg_tile_matrix", "table_name");
    deleteRows("gpkg_tile_matrix_set", "table_name");
    deleteRows("gpkg_contents", "table_name");
    deleteRows("gpkg_extensions", "table_name");
    deleteRows("gpkg_2d_gridded_coverage_ancillary", "tile_matrix_set_name");
    deleteRows("gpkg_2d_gridded_tile_ancillary", "tpudt_name");
}

}  // namespace lacet
