// The copy of a DEM LOD tree (io/dem_lod.h) from its own GeoPackage into a scene file being saved:
// SQLite ATTACH, the tables and their gpkg_* rows, out of core.
#include <sqlite3.h>

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <string>
#include <system_error>

#include "io/dem_lod.h"
#include "io/dem_lod_internal.h"
#include "io/gpkg_coverage.h"
#include "io/sqlite_db.h"

namespace lacet {

using namespace dem_lod_detail;

namespace {

constexpr const char* kSourceSchema = "lacet_dem_lod_source";  // the ATTACH name of copyDemLod's source

// An SQLite URI that opens `path` read-only (never creating it): "file:" ("file://" before an
// absolute path: an empty authority) and the path with every byte but the unreserved ones and '/'
// percent-encoded.
std::string readOnlyUri(const std::string& path) {
    static const char* const kHex = "0123456789ABCDEF";
    std::string uri = path.starts_with('/') ? "file://" : "file:";
    for (const char ch : path) {
        const auto c = static_cast<unsigned char>(ch);
        if (std::isalnum(c) || c == '/' || c == '-' || c == '.' || c == '_' || c == '~') {
            uri += ch;
        } else {
            uri += '%';
            uri += kHex[c >> 4];
            uri += kHex[c & 15];
        }
    }
    return uri + "?mode=ro";
}

}  // namespace

void copyDemLod(SqliteDb& db, const std::string& from, std::int64_t srsId) {
    const std::string src = kSourceSchema, table = kDemLodTable, meta = kDemLodMetaTable;
    {
        // A missing source is refused before the ATTACH, which would create an empty file there;
        // the ATTACH itself is read-only where SQLite takes URIs, so that a source removed in
        // between is not created either.
        std::error_code ec;
        const auto status = std::filesystem::status(from, ec);
        if (!std::filesystem::exists(status)) refuse(from, "no such file (the tree to copy)");
        if (!std::filesystem::is_regular_file(status)) refuse(from, "not a regular file (the tree to copy)");
        auto attach = db.prepare("ATTACH DATABASE ? AS " + src);
        attach.bindText(1, sqlite3_compileoption_used("USE_URI") ? readOnlyUri(from) : from);
        try {
            attach.step();
        } catch (const SqliteError& e) {
            refuse(from, std::string("cannot attach: ") + e.what());
        }
    }
    bool inTransaction = false;
    try {
        {  // every statement finalized before the DETACH
            if (!hasTableIn(db, src, table) || !hasTableIn(db, src, meta))
                refuse(from, std::string("no complete tree to copy (tables ") + kDemLodTable + " and " + kDemLodMetaTable + ")");
            if (db.hasTable(table) || db.hasTable(meta))
                throw DemLodError(std::string("copyDemLod(): the target already has a table '") + kDemLodTable + "' or '" +
                                  kDemLodMetaTable + "'");
            {
                auto s = db.prepare("SELECT 1 FROM main.gpkg_spatial_ref_sys WHERE srs_id = ?");
                s.bind(1, srsId);
                if (!s.step())
                    throw DemLodError("copyDemLod(): the target has no gpkg_spatial_ref_sys row of srs_id " + std::to_string(srsId));
            }
            {
                auto s = db.prepare("SELECT 1 FROM " + src + ".gpkg_tile_matrix_set WHERE table_name = ?");
                s.bindText(1, table);
                if (!s.step()) refuse(from, "no gpkg_tile_matrix_set row");
            }
            db.exec("BEGIN IMMEDIATE");
            inTransaction = true;
            ensureGpkgTileTables(db, true);
            const std::string srsText = std::to_string(srsId);
            db.exec(gpkgTileTableSql("main", kDemLodTable));
            db.exec("INSERT INTO main.\"" + table + "\" (id, zoom_level, tile_column, tile_row, tile_data) SELECT id, zoom_level, "
                    "tile_column, tile_row, tile_data FROM " + src + ".\"" + table + "\"");
            db.exec("INSERT INTO main.gpkg_contents (table_name, data_type, identifier, description, last_change, min_x, min_y, "
                    "max_x, max_y, srs_id) SELECT table_name, data_type, identifier, description, last_change, min_x, min_y, max_x, "
                    "max_y, CASE WHEN table_name = '" + table + "' THEN " + srsText + " ELSE srs_id END FROM " + src +
                    ".gpkg_contents WHERE table_name IN ('" + table + "', '" + meta + "')");
            db.exec("INSERT INTO main.gpkg_tile_matrix_set (table_name, srs_id, min_x, min_y, max_x, max_y) SELECT table_name, " +
                    srsText + ", min_x, min_y, max_x, max_y FROM " + src + ".gpkg_tile_matrix_set WHERE table_name = '" + table + "'");
            db.exec("INSERT INTO main.gpkg_tile_matrix (table_name, zoom_level, matrix_width, matrix_height, tile_width, "
                    "tile_height, pixel_x_size, pixel_y_size) SELECT table_name, zoom_level, matrix_width, matrix_height, "
                    "tile_width, tile_height, pixel_x_size, pixel_y_size FROM " + src + ".gpkg_tile_matrix WHERE table_name = '" +
                    table + "'");
            db.exec("INSERT INTO main.gpkg_2d_gridded_coverage_ancillary (tile_matrix_set_name, datatype, scale, offset, "
                    "precision, data_null, grid_cell_encoding, uom, field_name, quantity_definition) SELECT tile_matrix_set_name, "
                    "datatype, scale, offset, precision, data_null, grid_cell_encoding, uom, field_name, quantity_definition "
                    "FROM " + src + ".gpkg_2d_gridded_coverage_ancillary WHERE tile_matrix_set_name = '" + table + "'");
            if (hasTableIn(db, src, "gpkg_2d_gridded_tile_ancillary"))
                db.exec("INSERT INTO main.gpkg_2d_gridded_tile_ancillary (tpudt_name, tpudt_id, scale, offset, min, max, mean, "
                        "std_dev) SELECT tpudt_name, tpudt_id, scale, offset, min, max, mean, std_dev FROM " + src +
                        ".gpkg_2d_gridded_tile_ancillary WHERE tpudt_name = '" + table + "'");
            if (hasTableIn(db, src, "gpkg_extensions"))
                db.exec("INSERT OR IGNORE INTO main.gpkg_extensions (table_name, column_name, extension_name, definition, scope) "
                        "SELECT table_name, column_name, extension_name, definition, scope FROM " + src +
                        ".gpkg_extensions WHERE table_name IN ('" + table +
                        "', 'gpkg_2d_gridded_coverage_ancillary', 'gpkg_2d_gridded_tile_ancillary')");
            db.exec(createMetaTableSql("main"));
            db.exec("INSERT INTO main." + meta + " (key, value) SELECT key, value FROM " + src + "." + meta);
            db.exec("COMMIT");
            inTransaction = false;
        }
        db.exec("DETACH DATABASE " + src);
    } catch (...) {
        try {
            if (inTransaction) db.exec("ROLLBACK");
            db.exec("DETACH DATABASE " + src);
        } catch (const std::exception&) {
        }
        throw;
    }
}

}  // namespace lacet
