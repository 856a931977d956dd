// The copy of a DEM LOD tree (io/dem_lod.h) from its own GeoPackage into a scene file being saved:
// SQLite ATTACH, the tables and their gpkg_* rows, out of core.
#include <sqlite3.h>

#include <string>

#include "io/dem_lod.h"
#include "io/dem_lod_internal.h"
#include "io/sqlite_db.h"

namespace lacet {

using namespace dem_lod_detail;

namespace {

constexpr const char* kSourceSchema = "lacet_dem_lod_source";  // the ATTACH name of copyDemLod's source

}  // namespace

void copyDemLod(SqliteDb& db, const std::string& from) {
    const std::string src = kSourceSchema, table = kDemLodTable, meta = kDemLodMetaTable;
    {
        auto attach = db.prepare("ATTACH DATABASE ? AS " + src);
        attach.bindText(1, from);
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
            db.exec("BEGIN IMMEDIATE");
            inTransaction = true;
            ensureCoverageTables(db);
            // The CRS: the target's row of the same id and definition, else its row of the same
            // definition, else the source's row under its id (or a free one from 100000 up).
            std::int64_t srs = -1;
            {
                auto s = db.prepare("SELECT srs_id FROM " + src + ".gpkg_tile_matrix_set WHERE table_name = ?");
                s.bindText(1, table);
                if (!s.step()) refuse(from, "no gpkg_tile_matrix_set row");
                srs = s.integer(0);
            }
            auto def = db.prepare("SELECT srs_name, organization, organization_coordsys_id, definition, description FROM " + src +
                                  ".gpkg_spatial_ref_sys WHERE srs_id = ?");
            def.bind(1, srs);
            if (!def.step()) refuse(from, "no gpkg_spatial_ref_sys row of srs_id " + std::to_string(srs));
            const std::string definition = def.text(3);
            auto same = db.prepare("SELECT srs_id FROM main.gpkg_spatial_ref_sys WHERE definition = ? ORDER BY srs_id = ? DESC, srs_id LIMIT 1");
            same.bindText(1, definition);
            same.bind(2, srs);
            if (same.step()) {
                srs = same.integer(0);
            } else {
                auto taken = db.prepare("SELECT 1 FROM main.gpkg_spatial_ref_sys WHERE srs_id = ?");
                taken.bind(1, srs);
                if (taken.step())
                    srs = db.queryInteger("SELECT max(100000, coalesce(max(srs_id), 0) + 1) FROM main.gpkg_spatial_ref_sys");
                auto insert = db.prepare(
                    "INSERT INTO main.gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, definition, "
                    "description) VALUES (?, ?, ?, ?, ?, ?)");
                insert.bindText(1, def.text(0));
                insert.bind(2, srs);
                insert.bindText(3, def.text(1));
                insert.bind(4, def.integer(2));
                insert.bindText(5, definition);
                if (def.type(4) == SQLITE_NULL) insert.bindNull(6);
                else insert.bindText(6, def.text(4));
                insert.step();
            }
            def.reset();
            const std::string srsText = std::to_string(srs);
            db.exec(createTileTableSql("main"));
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
