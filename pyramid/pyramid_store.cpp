#include "pyramid/pyramid_store.h"

#include <sqlite3.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "io/gpkg_coverage.h"
#include "io/gpkg_dem.h"

namespace lacet {
namespace {

constexpr const char* kInfoTable = "lacet_pyramid";
constexpr const char* kQuadsTable = "lacet_pyramid_quads";
constexpr int kBusyTimeoutMs = 30000;  // ms a statement waits for another connection's lock

const std::string& ensureGpkg(const std::string& path, PyramidStore::Mode mode) {
    if (mode == PyramidStore::Mode::ReadWrite && !std::filesystem::exists(path)) createEmptyGpkg(path);
    return path;
}

SqliteDb::Mode sqliteMode(PyramidStore::Mode mode) {
    return mode == PyramidStore::Mode::ReadOnly ? SqliteDb::Mode::ReadOnly : SqliteDb::Mode::ReadWrite;
}

}  // namespace

PyramidStore::PyramidStore(const std::string& path, Mode mode) try : path_(path), db_(ensureGpkg(path, mode), sqliteMode(mode)) {
    // The editor reads a pyramid while an update writes it: each waits for the other's lock.
    db_.busyTimeout(kBusyTimeoutMs);
    if (!db_.hasTable("gpkg_contents")) throw PyramidError(path + ": not a GeoPackage (no gpkg_contents table)");
    if (mode == Mode::ReadWrite) db_.exec("PRAGMA cache_size = -65536");  // 64 MiB before spilling to the journal
} catch (const PyramidError&) {
    throw;
} catch (const std::exception& e) {
    throw PyramidError(path + ": cannot open as a GeoPackage: " + e.what());
}

bool isPyramidFile(const std::string& path) {
    try {
        if (!std::filesystem::is_regular_file(path)) return false;
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        return db.hasTable(kInfoTable);
    } catch (const std::exception&) {
        return false;
    }
}

std::optional<PyramidInfo> PyramidStore::info() {
    try {
        if (!db_.hasTable(kInfoTable)) return std::nullopt;
        std::map<std::string, std::string> kv;
        auto st = db_.prepare(std::string("SELECT key, value FROM ") + kInfoTable);
        while (st.step()) kv[st.text(0)] = st.text(1);
        const auto get = [&](const char* k) {
            auto it = kv.find(k);
            if (it == kv.end()) throw PyramidError(std::string("lacet_pyramid has no '") + k + "'");
            return it->second;
        };
        PyramidInfo i;
        i.formatVersion = std::stoi(get("format_version"));
        if (i.formatVersion > kPyramidFormatVersion)
            throw PyramidError("pyramid format " + std::to_string(i.formatVersion) + " is later than this program's (" +
                               std::to_string(kPyramidFormatVersion) + ")");
        i.minLevel = std::stoi(get("min_level"));
        i.maxLevel = std::stoi(get("max_level"));
        i.vectorLevel = std::stoi(get("vector_level"));
        i.appearance = get("appearance") == "1";
        i.elevation = get("elevation") == "1";
        i.tileSize = std::stoi(get("tile_size"));
        i.elevationSize = std::stoi(get("elevation_size"));
        i.encoding = get("encoding");
        i.extent = {{std::stod(get("min_x")), std::stod(get("min_y"))}, {std::stod(get("max_x")), std::stod(get("max_y"))}};
        i.crsWkt = get("crs_wkt");
        i.inputs = std::stoull(get("inputs"), nullptr, 16);
        i.complete = get("complete") == "1";
        if (auto it = kv.find("scene_checksum"); it != kv.end()) i.sceneChecksum = it->second;
        if (i.minLevel < 0 || i.maxLevel < i.minLevel || i.maxLevel > kMaxPyramidLevel || i.tileSize <= 0 || i.elevationSize <= 0)
            throw PyramidError("lacet_pyramid holds impossible levels or tile sizes");
        return i;
    } catch (const PyramidError& e) {
        throw PyramidError(path_ + ": " + e.what());
    } catch (const std::exception& e) {
        throw PyramidError(path_ + ": unreadable lacet_pyramid table: " + e.what());
    }
}

void PyramidStore::begin() {
    return named([&] {
        db_.exec("BEGIN IMMEDIATE");
        inTransaction_ = true;
    });
}
void PyramidStore::commit() {
    return named([&] {
        db_.exec("COMMIT");
        inTransaction_ = false;
    });
}
void PyramidStore::rollback() {
    if (!inTransaction_) return;
    inTransaction_ = false;
    try {
        db_.exec("ROLLBACK");
    } catch (const std::exception&) {
    }
}

SqliteStatement& PyramidStore::statement(const std::string& sql) {
    auto& st = statements_[sql];
    if (!st) st = db_.prepareKept(sql);
    else st->reset();
    return *st;
}

void PyramidStore::dropPyramid() {
    statements_.clear();  // no statement may hold a table being dropped
    for (const char* t : {kAppearanceTable, kWaterTable, kElevationTable}) dropGpkgTileTable(db_, t);
    for (const char* t : {kInfoTable, kQuadsTable}) {
        db_.exec(std::string("DROP TABLE IF EXISTS ") + t);
        db_.exec(std::string("DELETE FROM gpkg_contents WHERE table_name = '") + t + "'");
    }
}

void PyramidStore::create(const PyramidInfo& info) {
    return named([&] {
        dropPyramid();
        int srs = -1;  // undefined Cartesian
        if (!info.crsWkt.empty()) {
            // The row of this CRS if the file has one; otherwise a new id from 100000 up (GDAL's
            // custom range), never another row's.
            auto same = db_.prepare("SELECT srs_id FROM gpkg_spatial_ref_sys WHERE definition = ? ORDER BY srs_id LIMIT 1");
            same.bindText(1, info.crsWkt);
            if (same.step()) {
                srs = int(same.integer(0));
            } else {
                srs = int(db_.queryInteger("SELECT max(100000, coalesce(max(srs_id), 0) + 1) FROM gpkg_spatial_ref_sys"));
                auto st = db_.prepare(
                    "INSERT INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, definition, "
                    "description) VALUES ('Lacet scene', ?, 'NONE', ?, ?, 'the CRS of the Lacet scene the pyramid was built for')");
                st.bind(1, std::int64_t(srs));
                st.bind(2, std::int64_t(srs));
                st.bindText(3, info.crsWkt);
                st.step();
            }
        }
        const Box& e = info.extent;
        const auto tileTable = [&](const char* name, GpkgTileTable::DataType dataType, const std::string& description, int tilePixels) {
            GpkgTileTable t{.name = name, .dataType = dataType, .description = description, .contents = e, .matrixSet = e, .srsId = srs, .matrices = {}};
            for (int l = info.minLevel; l <= info.maxLevel; ++l) {
                const std::int64_t n = std::int64_t(1) << l;
                t.matrices.push_back({.zoomLevel = l,
                                      .matrixWidth = n,
                                      .matrixHeight = n,
                                      .tileWidth = tilePixels,
                                      .tileHeight = tilePixels,
                                      .pixelXSize = (e.max.x - e.min.x) / double(n) / double(tilePixels),
                                      .pixelYSize = (e.max.y - e.min.y) / double(n) / double(tilePixels)});
            }
            createGpkgTileTable(db_, t, {.precision = 0.0, .dataNull = std::nullopt, .gridCellEncoding = "grid-value-is-center", .uom = "m"});
        };
        if (info.appearance) {
            tileTable(kAppearanceTable, GpkgTileTable::DataType::Tiles, "Lacet appearance pyramid: colour (RGB)", info.tileSize);
            tileTable(kWaterTable, GpkgTileTable::DataType::Tiles,
                      "Lacet appearance pyramid: water mask (0 land, 255 water; missing tiles: no water)", info.tileSize);
            if (info.encoding.rfind("webp", 0) == 0)
                addGpkgExtension(db_, kAppearanceTable, "tile_data", "gpkg_webp", "http://www.geopackage.org/spec120/#extension_tiles_webp");
        }
        if (info.elevation)
            tileTable(kElevationTable, GpkgTileTable::DataType::GriddedCoverage, "Lacet elevation pyramid: z_m (m) at cell centres",
                      info.elevationSize);
        db_.exec(std::string("CREATE TABLE ") + kInfoTable + " (key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL)");
        db_.exec(std::string("CREATE TABLE ") + kQuadsTable +
                 " (level INTEGER NOT NULL, quad_x INTEGER NOT NULL, quad_y INTEGER NOT NULL, digest INTEGER NOT NULL, "
                 "PRIMARY KEY (level, quad_x, quad_y)) WITHOUT ROWID");
        for (const char* t : {kInfoTable, kQuadsTable})
            db_.exec(std::string("INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) VALUES ('") +
                     t + "', 'attributes', '" + t + "', '" +
                     (t == kInfoTable ? "Lacet pyramid: what it was built for (key/value)"
                                      : "Lacet pyramid: digest of the inputs of each quad (quad_y grows northwards)") +
                     "', strftime('%Y-%m-%dT%H:%M:%fZ','now'))");
        writeInfo(info);
    });
}

void PyramidStore::writeInfo(const PyramidInfo& i) {
    return named([&] {
        char inputs[32];
        std::snprintf(inputs, sizeof inputs, "%016llx", static_cast<unsigned long long>(i.inputs));
        const std::map<std::string, std::string> kv = {
            {"format_version", std::to_string(i.formatVersion)}, {"min_level", std::to_string(i.minLevel)},
            {"max_level", std::to_string(i.maxLevel)},           {"vector_level", std::to_string(i.vectorLevel)},
            {"appearance", i.appearance ? "1" : "0"},            {"elevation", i.elevation ? "1" : "0"},
            {"tile_size", std::to_string(i.tileSize)},           {"elevation_size", std::to_string(i.elevationSize)},
            {"encoding", i.encoding},                            {"min_x", gpkgReal(i.extent.min.x)},
            {"min_y", gpkgReal(i.extent.min.y)},                    {"max_x", gpkgReal(i.extent.max.x)},
            {"max_y", gpkgReal(i.extent.max.y)},                    {"crs_wkt", i.crsWkt},
            {"inputs", inputs},                                  {"complete", i.complete ? "1" : "0"},
            {"scene_checksum", i.sceneChecksum}};
        auto st = db_.prepare(std::string("INSERT OR REPLACE INTO ") + kInfoTable + " (key, value) VALUES (?, ?)");
        for (const auto& [k, v] : kv) {
            st.bindText(1, k);
            st.bindText(2, v);
            st.step();
            st.reset();
        }
    });
}

namespace {
std::int64_t geopackageRow(const PyramidKey& q) { return (std::int64_t(1) << q.level) - 1 - std::int64_t(q.ty); }
}  // namespace

std::optional<std::vector<std::uint8_t>> PyramidStore::tile(const char* table, const PyramidKey& q) {
    return named([&] {
        std::lock_guard lock(mutex_);
        return readTile(table, q);
    });
}

std::optional<std::vector<std::uint8_t>> PyramidStore::readTile(const char* table, const PyramidKey& q) {
    auto& st = statement(std::string("SELECT tile_data FROM \"") + table +
                         "\" WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
    st.bind(1, std::int64_t(q.level));
    st.bind(2, std::int64_t(q.tx));
    st.bind(3, geopackageRow(q));
    if (!st.step()) return std::nullopt;
    const auto b = st.blob(0);
    std::vector<std::uint8_t> bytes(b.begin(), b.end());
    st.reset();  // no read left open on the table
    return bytes;
}

bool PyramidStore::putTile(const char* table, const PyramidKey& q, std::span<const std::uint8_t> bytes) {
    return named([&] {
        std::lock_guard lock(mutex_);
        return writeTile(table, q, bytes);
    });
}

bool PyramidStore::writeTile(const char* table, const PyramidKey& q, std::span<const std::uint8_t> bytes) {
    if (auto old = readTile(table, q); old && std::equal(old->begin(), old->end(), bytes.begin(), bytes.end())) return false;
    auto& st = statement(std::string("INSERT INTO \"") + table +
                          "\" (zoom_level, tile_column, tile_row, tile_data) VALUES (?, ?, ?, ?) ON CONFLICT (zoom_level, "
                          "tile_column, tile_row) DO UPDATE SET tile_data = excluded.tile_data");
    st.bind(1, std::int64_t(q.level));
    st.bind(2, std::int64_t(q.tx));
    st.bind(3, geopackageRow(q));
    st.bindBlob(4, bytes);
    st.step();
    return true;
}

bool PyramidStore::putElevation(const PyramidKey& q, std::span<const std::uint8_t> bytes, double min, double max, double mean,
                                double stdDev) {
    return named([&] {
        std::lock_guard lock(mutex_);
        if (!writeTile(kElevationTable, q, bytes)) return false;
        auto& id = statement(std::string("SELECT id FROM \"") + kElevationTable +
                              "\" WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
        id.bind(1, std::int64_t(q.level));
        id.bind(2, std::int64_t(q.tx));
        id.bind(3, geopackageRow(q));
        id.step();
        const std::int64_t rowId = id.integer(0);
        id.reset();
        auto& st = statement(
            "INSERT INTO gpkg_2d_gridded_tile_ancillary (tpudt_name, tpudt_id, scale, offset, min, max, mean, std_dev) VALUES "
            "(?, ?, 1.0, 0.0, ?, ?, ?, ?) ON CONFLICT (tpudt_name, tpudt_id) DO UPDATE SET min = excluded.min, max = "
            "excluded.max, mean = excluded.mean, std_dev = excluded.std_dev");
        st.bindText(1, kElevationTable);
        st.bind(2, rowId);
        st.bind(3, min);
        st.bind(4, max);
        st.bind(5, mean);
        st.bind(6, stdDev);
        st.step();
        return true;
    });
}

bool PyramidStore::removeTile(const char* table, const PyramidKey& q) {
    return named([&] {
        std::lock_guard lock(mutex_);
        auto& st = statement(std::string("DELETE FROM \"") + table + "\" WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
        st.bind(1, std::int64_t(q.level));
        st.bind(2, std::int64_t(q.tx));
        st.bind(3, geopackageRow(q));
        st.step();
        auto& changes = statement("SELECT changes()");
        changes.step();
        const bool removed = changes.integer(0) > 0;
        changes.reset();
        return removed;
    });
}

std::size_t PyramidStore::tileCount(const char* table) {
    return named([&] {
        if (!db_.hasTable(table)) return std::size_t(0);
        return std::size_t(db_.queryInteger(std::string("SELECT count(*) FROM \"") + table + "\""));
    });
}

std::uint64_t PyramidStore::tileBytes(const char* table) {
    return named([&] {
        if (!db_.hasTable(table)) return std::uint64_t(0);
        return std::uint64_t(db_.queryInteger(std::string("SELECT coalesce(sum(length(tile_data)), 0) FROM \"") + table + "\""));
    });
}

QuadDigestMap PyramidStore::digests() {
    return named([&] {
        QuadDigestMap m;
        if (!db_.hasTable(kQuadsTable)) return m;
        auto st = db_.prepare(std::string("SELECT level, quad_x, quad_y, digest FROM ") + kQuadsTable);
        while (st.step())
            m[PyramidKey{int(st.integer(0)), std::uint32_t(st.integer(1)), std::uint32_t(st.integer(2))}] =
                std::uint64_t(st.integer(3));
        return m;
    });
}

void PyramidStore::putDigest(const PyramidKey& q, std::uint64_t digest) {
    return named([&] {
        std::lock_guard lock(mutex_);
        auto& st = statement(std::string("INSERT OR REPLACE INTO ") + kQuadsTable + " (level, quad_x, quad_y, digest) VALUES (?, ?, ?, ?)");
        st.bind(1, std::int64_t(q.level));
        st.bind(2, std::int64_t(q.tx));
        st.bind(3, std::int64_t(q.ty));
        st.bind(4, std::int64_t(digest));
        st.step();
    });
}

std::vector<std::pair<PyramidKey, std::vector<std::uint8_t>>> PyramidStore::allTiles(const char* table) {
    return named([&] {
        std::vector<std::pair<PyramidKey, std::vector<std::uint8_t>>> out;
        if (!db_.hasTable(table)) return out;
        auto st = db_.prepare(std::string("SELECT zoom_level, tile_column, tile_row, tile_data FROM \"") + table +
                              "\" ORDER BY zoom_level, tile_column, tile_row");
        while (st.step()) {
            const std::int64_t level = st.integer(0), column = st.integer(1), row = st.integer(2);
            // A tile a pyramid cannot hold (a damaged or foreign table): refused, never shifted by it.
            if (level < 0 || level > kMaxPyramidLevel || column < 0 || row < 0 || column >= (std::int64_t(1) << level) ||
                row >= (std::int64_t(1) << level))
                throw PyramidError(std::string("table ") + table + " holds a tile at an impossible place: level " + std::to_string(level) +
                                   ", column " + std::to_string(column) + ", row " + std::to_string(row));
            const auto b = st.blob(3);
            out.push_back({PyramidKey{int(level), std::uint32_t(column), std::uint32_t((std::int64_t(1) << level) - 1 - row)},
                           std::vector<std::uint8_t>(b.begin(), b.end())});
        }
        return out;
    });
}

}  // namespace lacet
