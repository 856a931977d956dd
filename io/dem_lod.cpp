// The DEM's non-redundant LOD block tree as a GeoPackage 2D gridded coverage (io/dem_lod.h): the
// layout, the writer (rows in, block rows out), the reader (one connection, reads serialized,
// decoding not), a whole level in memory, and the copy into a scene file being saved.
#include "io/dem_lod.h"

#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <string_view>
#include <utility>

#include <tbb/parallel_for.h>

#include "io/sqlite_db.h"
#include "io/tile_codec.h"

namespace lacet {
namespace {

constexpr int kBusyTimeoutMs = 30000;  // ms a statement waits for another connection's lock
// zlib level of the tiles: 6 (zlib's default), with TIFF's floating-point predictor. Measured on a
// smooth 1000 x 700 DEM in 17 tiles of 256^2 (tests/io/dem_lod_test.cpp, DemLod.TileEncodingSizes):
// uncompressed 4.46 MB, deflate 2.46 MB, deflate with the predictor 2.07 MB (2.8 MB of floats: the
// nulls of the padding and of the inherited samples compress away).
constexpr int kTileDeflateLevel = 6;
constexpr bool kTileFloatPredictor = true;
constexpr const char* kGriddedDef = "http://docs.opengeospatial.org/is/17-066r1/17-066r1.html";
constexpr const char* kSourceSchema = "lacet_dem_lod_source";  // the ATTACH name of copyDemLod's source

// ---- exact text of doubles (kDemLodMetaTable) ----

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

// Whether local sample (m, q) of a block of `level` is inherited from its parent.
bool inherited(int level, int m, int q) { return level > 0 && m % 2 == 0 && q % 2 == 0; }

}  // namespace

// ---- the layout ----

DemLodLayout DemLodLayout::make(int width, int height, double cell, Vec2 origin, int blockSide) {
    if (width < 2 || height < 2)
        throw std::invalid_argument("DemLodLayout::make(): a grid of " + std::to_string(width) + " x " +
                                    std::to_string(height) + " samples (at least 2 x 2)");
    if (!(cell > 0.0) || !std::isfinite(cell))
        throw std::invalid_argument("DemLodLayout::make(): cell " + std::to_string(cell) + " m is not finite and > 0");
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y))
        throw std::invalid_argument("DemLodLayout::make(): the origin is not finite");
    if (blockSide < 4 || blockSide % 2 != 0 || blockSide > kMaxTileSide)
        throw std::invalid_argument("DemLodLayout::make(): block side " + std::to_string(blockSide) +
                                    " is not even and in 4.." + std::to_string(kMaxTileSide));
    DemLodLayout l;
    l.width = width;
    l.height = height;
    l.cell = cell;
    l.origin = origin;
    l.blockSide = blockSide;
    const std::int64_t side = std::max(width, height);
    l.levels = 1;
    while ((std::int64_t(blockSide) << (l.levels - 1)) < side) ++l.levels;
    return l;
}

Box DemLodLayout::extent() const {
    return {{origin.x - 0.5 * cell, origin.y - (double(height) - 0.5) * cell},
            {origin.x + (double(width) - 0.5) * cell, origin.y + 0.5 * cell}};
}

int DemLodLayout::levelFor(double spacing) const {
    if (std::isnan(spacing)) throw std::invalid_argument("DemLodLayout::levelFor(): spacing is NaN");
    for (int l = 0; l < levels; ++l)
        if (levelCell(l) <= spacing) return l;
    return levels - 1;
}

std::int64_t DemLodLayout::tileCount() const {
    std::int64_t n = 0;
    for (int l = 0; l < levels; ++l) n += std::int64_t(blockColumns(l)) * std::int64_t(blockRows(l));
    return n;
}

int levelAtMost(const DemLodLayout& layout, int maxSide) {
    if (maxSide < 1) throw std::invalid_argument("levelAtMost(): maxSide " + std::to_string(maxSide) + " < 1");
    for (int l = layout.levels - 1; l > 0; --l)
        if (layout.levelWidth(l) <= maxSide && layout.levelHeight(l) <= maxSide) return l;
    return 0;
}

void inheritFromParent(std::span<float> block, std::span<const float> parent, int col, int row, int blockSide) {
    if (blockSide < 4 || blockSide % 2 != 0)
        throw std::invalid_argument("inheritFromParent(): block side " + std::to_string(blockSide) + " is odd or < 4");
    const std::size_t n = std::size_t(blockSide) * std::size_t(blockSide);
    if (block.size() != n || parent.size() != n)
        throw std::invalid_argument("inheritFromParent(): blocks of " + std::to_string(block.size()) + " and " +
                                    std::to_string(parent.size()) + " samples, " + std::to_string(n) + " expected");
    if (col < 0 || row < 0) throw std::invalid_argument("inheritFromParent(): negative block column or row");
    const std::size_t side = std::size_t(blockSide), half = side / 2;
    const std::size_t ox = std::size_t(col & 1) * half, oy = std::size_t(row & 1) * half;
    for (std::size_t q = 0; q < side; q += 2)
        for (std::size_t m = 0; m < side; m += 2) block[q * side + m] = parent[(oy + q / 2) * side + ox + m / 2];
}

// ---- the writer ----

struct DemLodWriter::LevelStrip {
    int width = 0;               // samples of the level on the grid (levelWidth)
    std::size_t stride = 0;      // blockColumns * blockSide
    int rows = 0;                // rows buffered
    int blockRow = 0;            // the block row they belong to
    std::vector<float> samples;  // blockSide rows of `stride`
};

DemLodWriter::DemLodWriter(SqliteDb& db, const DemLodLayout& layout, int srsId) : db_(db), layout_(layout) {
    if (layout.levels < 1 ||
        !(DemLodLayout::make(layout.width, layout.height, layout.cell, layout.origin, layout.blockSide) == layout))
        throw std::invalid_argument("DemLodWriter: the layout is not DemLodLayout::make()'s");
    if (db.hasTable(kDemLodTable) || db.hasTable(kDemLodMetaTable))
        throw std::invalid_argument(std::string("DemLodWriter: the GeoPackage already has a table '") + kDemLodTable +
                                    "' or '" + kDemLodMetaTable + "'");
    {
        auto s = db.prepare("SELECT 1 FROM gpkg_spatial_ref_sys WHERE srs_id = ?");
        s.bind(1, std::int64_t(srsId));
        if (!s.step())
            throw std::invalid_argument("DemLodWriter: no gpkg_spatial_ref_sys row of srs_id " + std::to_string(srsId));
    }
    const std::string table = kDemLodTable, srs = std::to_string(srsId);
    const int bs = layout.blockSide, n = layout.levels;
    const double side = double(std::int64_t(bs) << (n - 1)) * layout.cell;  // the padded grid, metres
    const Vec2 o = layout.origin;
    // grid-value-is-corner: a pixel's value is at its top-left corner, so the data's bounds run from
    // the top-left sample to one cell beyond the last sample.
    const std::string contents = sqlReal(o.x) + ", " + sqlReal(o.y - double(layout.height) * layout.cell) + ", " +
                                 sqlReal(o.x + double(layout.width) * layout.cell) + ", " + sqlReal(o.y);
    const std::string matrixSet = sqlReal(o.x) + ", " + sqlReal(o.y - side) + ", " + sqlReal(o.x + side) + ", " + sqlReal(o.y);
    ensureCoverageTables(db);
    db.exec(createTileTableSql("main"));
    db.exec("INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change, min_x, min_y, max_x, "
            "max_y, srs_id) VALUES ('" +
            table + "', '2d-gridded-coverage', '" + table +
            "', 'Lacet DEM: non-redundant LOD blocks (heights in m; null where a coarser level holds the sample)', "
            "strftime('%Y-%m-%dT%H:%M:%fZ','now'), " +
            contents + ", " + srs + ")");
    db.exec("INSERT INTO gpkg_tile_matrix_set (table_name, srs_id, min_x, min_y, max_x, max_y) VALUES ('" + table + "', " +
            srs + ", " + matrixSet + ")");
    {
        auto s = db.prepare(
            "INSERT INTO gpkg_tile_matrix (table_name, zoom_level, matrix_width, matrix_height, tile_width, tile_height, "
            "pixel_x_size, pixel_y_size) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
        for (int l = 0; l < n; ++l) {
            s.bindText(1, table);
            s.bind(2, std::int64_t(l));
            s.bind(3, std::int64_t(layout.blocksPerSide(l)));
            s.bind(4, std::int64_t(layout.blocksPerSide(l)));
            s.bind(5, std::int64_t(bs));
            s.bind(6, std::int64_t(bs));
            s.bind(7, layout.levelCell(l));
            s.bind(8, layout.levelCell(l));
            s.step();
            s.reset();
        }
    }
    for (const char* t : {"gpkg_2d_gridded_coverage_ancillary", "gpkg_2d_gridded_tile_ancillary"})
        db.exec(std::string("INSERT OR IGNORE INTO gpkg_extensions VALUES ('") + t + "', NULL, 'gpkg_2d_gridded_coverage', '" +
                kGriddedDef + "', 'read-write')");
    db.exec("INSERT OR IGNORE INTO gpkg_extensions VALUES ('" + table + "', 'tile_data', 'gpkg_2d_gridded_coverage', '" +
            kGriddedDef + "', 'read-write')");
    {
        auto s = db.prepare(
            "INSERT INTO gpkg_2d_gridded_coverage_ancillary (tile_matrix_set_name, datatype, scale, offset, precision, "
            "data_null, grid_cell_encoding, uom) VALUES (?, 'float', 1.0, 0.0, 0.0, ?, 'grid-value-is-corner', 'm')");
        s.bindText(1, table);
        s.bind(2, double(kDemNull));
        s.step();
    }
    insert_ = db.prepareKept("INSERT INTO \"" + table + "\" (id, zoom_level, tile_column, tile_row, tile_data) VALUES (?, ?, ?, ?, ?)");
    ancillary_ = db.prepareKept(
        "INSERT INTO gpkg_2d_gridded_tile_ancillary (tpudt_name, tpudt_id, scale, offset, min, max, mean, std_dev) VALUES "
        "(?, ?, 1.0, 0.0, ?, ?, ?, ?)");
    strips_.resize(std::size_t(n));
    for (int l = 0; l < n; ++l) {
        LevelStrip& s = strips_[std::size_t(l)];
        s.width = layout.levelWidth(l);
        s.stride = std::size_t(layout.blockColumns(l)) * std::size_t(bs);
        s.samples.assign(s.stride * std::size_t(bs), kDemNull);
    }
    digest_.word(kDemLodFormatVersion);
    digest_.word(std::uint64_t(layout.width) << 32 | std::uint64_t(layout.height));
    digest_.real(layout.cell).real(layout.origin.x).real(layout.origin.y);
    digest_.word(std::uint64_t(layout.blockSide));
}

DemLodWriter::~DemLodWriter() = default;

void DemLodWriter::addRow(std::span<const float> heights) {
    if (finished_) throw std::invalid_argument("DemLodWriter::addRow(): after finish()");
    if (heights.size() != std::size_t(layout_.width))
        throw std::invalid_argument("DemLodWriter::addRow(): " + std::to_string(heights.size()) + " heights, " +
                                    std::to_string(layout_.width) + " expected");
    if (rowsAdded_ >= layout_.height)
        throw std::invalid_argument("DemLodWriter::addRow(): all " + std::to_string(layout_.height) + " rows already added");
    const int t = rowsAdded_;
    for (std::size_t i = 0; i < heights.size(); ++i)
        if (!std::isfinite(heights[i]) || heights[i] == kDemNull)
            throw std::invalid_argument("DemLodWriter::addRow(): sample (" + std::to_string(i) + ", " + std::to_string(t) +
                                        ") is " + std::to_string(heights[i]) + ", not a finite height other than the null");
    digest_.reals(heights);
    for (int l = 0; l < layout_.levels; ++l) {
        const int step = layout_.step(l);
        if (t % step != 0) continue;
        LevelStrip& s = strips_[std::size_t(l)];
        const int r = t / step, q = r % layout_.blockSide;
        float* dst = s.samples.data() + std::size_t(q) * s.stride;
        for (int k = 0; k < s.width; ++k) dst[k] = heights[std::size_t(k) * std::size_t(step)];
        s.rows = q + 1;
        s.blockRow = r / layout_.blockSide;
        if (s.rows == layout_.blockSide) {
            flushLevel(l, s.blockRow, s.rows);
            s.rows = 0;
        }
    }
    ++rowsAdded_;
}

void DemLodWriter::flushLevel(int level, int blockRow, int rows) {
    const LevelStrip& s = strips_[std::size_t(level)];
    const int bs = layout_.blockSide;
    std::vector<float> tile(std::size_t(bs) * std::size_t(bs));
    for (int c = 0; c < layout_.blockColumns(level); ++c) {
        double sum = 0.0, sum2 = 0.0, lo = 0.0, hi = 0.0;
        std::int64_t count = 0;
        for (int q = 0; q < bs; ++q)
            for (int m = 0; m < bs; ++m) {
                const int k = c * bs + m;
                float v = kDemNull;
                if (q < rows && k < s.width && !inherited(level, m, q)) {
                    v = s.samples[std::size_t(q) * s.stride + std::size_t(k)];
                    const double d = v;
                    lo = count == 0 ? d : std::min(lo, d);
                    hi = count == 0 ? d : std::max(hi, d);
                    sum += d;
                    sum2 += d * d;
                    ++count;
                }
                tile[std::size_t(q) * std::size_t(bs) + std::size_t(m)] = v;
            }
        const std::vector<std::uint8_t> bytes = encodeFloatTiffDeflate(tile, bs, bs, kTileDeflateLevel, kTileFloatPredictor);
        const auto id = std::int64_t(tiles_ + 1);
        insert_->reset();
        insert_->bind(1, id);
        insert_->bind(2, std::int64_t(level));
        insert_->bind(3, std::int64_t(c));
        insert_->bind(4, std::int64_t(blockRow));
        insert_->bindBlob(5, bytes);
        insert_->step();
        ancillary_->reset();
        ancillary_->bindText(1, kDemLodTable);
        ancillary_->bind(2, id);
        if (count > 0) {
            const double mean = sum / double(count);
            ancillary_->bind(3, lo);
            ancillary_->bind(4, hi);
            ancillary_->bind(5, mean);
            ancillary_->bind(6, std::sqrt(std::max(0.0, sum2 / double(count) - mean * mean)));
        } else {
            for (int i = 3; i <= 6; ++i) ancillary_->bindNull(i);
        }
        ancillary_->step();
        ++tiles_;
        bytes_ += bytes.size();
    }
}

void DemLodWriter::finish() {
    if (finished_) throw std::invalid_argument("DemLodWriter::finish(): called twice");
    if (rowsAdded_ < layout_.height)
        throw std::invalid_argument("DemLodWriter::finish(): " + std::to_string(rowsAdded_) + " of " +
                                    std::to_string(layout_.height) + " rows added");
    for (int l = 0; l < layout_.levels; ++l) {
        LevelStrip& s = strips_[std::size_t(l)];
        if (s.rows > 0) flushLevel(l, s.blockRow, s.rows);
        s.rows = 0;
        s.samples = {};
    }
    insert_.reset();
    ancillary_.reset();
    finished_ = true;
    db_.exec(createMetaTableSql("main"));
    db_.exec(std::string("INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) VALUES ('") +
             kDemLodMetaTable + "', 'attributes', '" + kDemLodMetaTable +
             "', 'Lacet DEM LOD tree: its layout and digest (key/value)', strftime('%Y-%m-%dT%H:%M:%fZ','now'))");
    const std::pair<const char*, std::string> kv[] = {
        {"version", std::to_string(kDemLodFormatVersion)},
        {"width", std::to_string(layout_.width)},
        {"height", std::to_string(layout_.height)},
        {"cell", hexText(layout_.cell)},
        {"origin_x", hexText(layout_.origin.x)},
        {"origin_y", hexText(layout_.origin.y)},
        {"block_side", std::to_string(layout_.blockSide)},
        {"levels", std::to_string(layout_.levels)},
        {"digest", digest()},
    };
    auto s = db_.prepare(std::string("INSERT INTO ") + kDemLodMetaTable + " (key, value) VALUES (?, ?)");
    for (const auto& [k, v] : kv) {
        s.bindText(1, k);
        s.bindText(2, v);
        s.step();
        s.reset();
    }
}

std::string DemLodWriter::digest() const {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(digest_.value()));
    return buf;
}

// ---- the reader ----

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& reason) {
    throw DemLodError(path + ": DEM LOD tree '" + kDemLodTable + "': " + reason);
}

}  // namespace

DemLodFile::DemLodFile(const std::string& path) : path_(path) {
    try {
        db_ = std::make_unique<SqliteDb>(path, SqliteDb::Mode::ReadOnly);
        db_->busyTimeout(kBusyTimeoutMs);
        if (!db_->hasTable(kDemLodTable)) refuse(path, "no such table");
        if (!db_->hasTable(kDemLodMetaTable))
            refuse(path, std::string("no table ") + kDemLodMetaTable + " (a tree whose writer did not finish)");
        std::map<std::string, std::string> kv;
        {
            auto s = db_->prepare(std::string("SELECT key, value FROM ") + kDemLodMetaTable);
            while (s.step()) kv[s.text(0)] = s.text(1);
        }
        const auto text = [&](const char* key) -> const std::string& {
            const auto it = kv.find(key);
            if (it == kv.end()) refuse(path, std::string(kDemLodMetaTable) + " has no '" + key + "'");
            return it->second;
        };
        const auto integer = [&](const char* key, std::int64_t lo, std::int64_t hi) {
            const std::string& t = text(key);
            std::int64_t v = 0;
            const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
            if (r.ec != std::errc() || r.ptr != t.data() + t.size() || v < lo || v > hi)
                refuse(path, std::string(kDemLodMetaTable) + " '" + key + "' = '" + t + "' is not an integer in [" +
                                 std::to_string(lo) + ", " + std::to_string(hi) + "]");
            return v;
        };
        const auto real = [&](const char* key) {
            double v = 0.0;
            if (!parseHex(text(key), v))
                refuse(path, std::string(kDemLodMetaTable) + " '" + key + "' = '" + text(key) + "' is not a finite hex float");
            return v;
        };
        const std::int64_t version = integer("version", 1, INT32_MAX);
        if (version > kDemLodFormatVersion)
            refuse(path, "format version " + std::to_string(version) + ", this program reads up to " +
                             std::to_string(kDemLodFormatVersion));
        try {
            layout_ = DemLodLayout::make(int(integer("width", 2, INT32_MAX)), int(integer("height", 2, INT32_MAX)),
                                         real("cell"), {real("origin_x"), real("origin_y")},
                                         int(integer("block_side", 4, kMaxTileSide)));
        } catch (const std::invalid_argument& e) {
            refuse(path, std::string("impossible layout in ") + kDemLodMetaTable + ": " + e.what());
        }
        if (integer("levels", 1, 31) != layout_.levels)
            refuse(path, "'levels' = " + text("levels") + ", the grid needs " + std::to_string(layout_.levels));
        digest_ = text("digest");
        if (digest_.size() != 16 || digest_.find_first_not_of("0123456789abcdef") != std::string::npos)
            refuse(path, "'digest' = '" + digest_ + "' is not 16 hex digits");
        {
            auto s = db_->prepare("SELECT min_x, max_y FROM gpkg_tile_matrix_set WHERE table_name = ?");
            s.bindText(1, kDemLodTable);
            if (!s.step()) refuse(path, "no gpkg_tile_matrix_set row");
            if (s.real(0) != layout_.origin.x || s.real(1) != layout_.origin.y)
                refuse(path, "the tile matrix set's corner (" + sqlReal(s.real(0)) + ", " + sqlReal(s.real(1)) +
                                 ") is not the origin (" + sqlReal(layout_.origin.x) + ", " + sqlReal(layout_.origin.y) + ")");
        }
        {
            auto s = db_->prepare(
                "SELECT zoom_level, matrix_width, matrix_height, tile_width, tile_height, pixel_x_size, pixel_y_size FROM "
                "gpkg_tile_matrix WHERE table_name = ? ORDER BY zoom_level");
            s.bindText(1, kDemLodTable);
            int l = 0;
            for (; s.step(); ++l) {
                const double cell = layout_.levelCell(l);
                if (l >= layout_.levels || s.integer(0) != l || s.integer(1) != layout_.blocksPerSide(l) ||
                    s.integer(2) != layout_.blocksPerSide(l) || s.integer(3) != layout_.blockSide ||
                    s.integer(4) != layout_.blockSide || s.real(5) != cell || s.real(6) != cell)
                    refuse(path, "tile matrix of zoom level " + std::to_string(s.integer(0)) + " does not match the layout (" +
                                     std::to_string(layout_.levels) + " levels of " + std::to_string(layout_.blockSide) +
                                     "-sample blocks)");
            }
            if (l != layout_.levels)
                refuse(path, std::to_string(l) + " tile matrices, " + std::to_string(layout_.levels) + " levels expected");
        }
        select_ = db_->prepareKept(std::string("SELECT tile_data FROM \"") + kDemLodTable +
                                   "\" WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?");
    } catch (const DemLodError&) {
        throw;
    } catch (const std::exception& e) {
        refuse(path, std::string("cannot read: ") + e.what());
    }
}

DemLodFile::~DemLodFile() = default;

std::vector<float> DemLodFile::readStored(int level, int col, int row) const {
    const DemLodLayout& L = layout_;
    if (level < 0 || level >= L.levels || col < 0 || row < 0 || col >= L.blocksPerSide(level) ||
        row >= L.blocksPerSide(level))
        throw std::out_of_range("DemLodFile::readStored(): " + blockName(level, col, row) + " outside the tree of " +
                                std::to_string(L.levels) + " levels");
    const int bs = L.blockSide;
    if (!L.hasBlock(level, col, row)) return std::vector<float>(std::size_t(bs) * std::size_t(bs), kDemNull);
    std::vector<std::uint8_t> bytes;
    {
        std::lock_guard lock(mutex_);
        try {
            select_->reset();
            select_->bind(1, std::int64_t(level));
            select_->bind(2, std::int64_t(col));
            select_->bind(3, std::int64_t(row));
            if (!select_->step()) {
                select_->reset();
                refuse(path_, blockName(level, col, row) + ": its tile is missing");
            }
            const auto b = select_->blob(0);
            bytes.assign(b.begin(), b.end());
            select_->reset();  // no read left open on the table
        } catch (const SqliteError& e) {
            select_->reset();
            refuse(path_, blockName(level, col, row) + ": cannot read its tile: " + e.what());
        }
    }
    DecodedFloats tile;
    try {
        tile = decodeFloatTiff(bytes);
    } catch (const TileDecodeError& e) {
        refuse(path_, blockName(level, col, row) + ": its tile does not decode: " + e.what());
    }
    if (tile.width != bs || tile.height != bs)
        refuse(path_, blockName(level, col, row) + ": a tile of " + std::to_string(tile.width) + " x " +
                          std::to_string(tile.height) + " samples, " + std::to_string(bs) + " x " + std::to_string(bs) +
                          " expected");
    const int w = L.levelWidth(level), h = L.levelHeight(level);
    for (int q = 0; q < bs; ++q)
        for (int m = 0; m < bs; ++m) {
            const float v = tile.values[std::size_t(q) * std::size_t(bs) + std::size_t(m)];
            const bool null = col * bs + m >= w || row * bs + q >= h || inherited(level, m, q);
            if (null ? std::bit_cast<std::uint32_t>(v) != std::bit_cast<std::uint32_t>(kDemNull)
                     : (!std::isfinite(v) || v == kDemNull))
                refuse(path_, blockName(level, col, row) + ": sample (" + std::to_string(m) + ", " + std::to_string(q) +
                                  ") of its tile is " + std::to_string(v) + " where " +
                                  (null ? "the null is expected" : "a height is expected"));
        }
    return std::move(tile.values);
}

std::vector<float> DemLodFile::readBlock(int level, int col, int row, std::span<const float> parent) const {
    const std::size_t n = std::size_t(layout_.blockSide) * std::size_t(layout_.blockSide);
    if (level > 0 && parent.size() != n)
        throw std::invalid_argument("DemLodFile::readBlock(): a parent of " + std::to_string(parent.size()) + " samples, " +
                                    std::to_string(n) + " expected");
    std::vector<float> block = readStored(level, col, row);
    if (level > 0) inheritFromParent(block, parent, col, row, layout_.blockSide);
    return block;
}

Dem readDemLevel(const DemLodFile& file, int level) {
    const DemLodLayout& L = file.layout();
    if (level < 0 || level >= L.levels)
        throw std::out_of_range("readDemLevel(): level " + std::to_string(level) + " outside 0.." + std::to_string(L.levels - 1));
    // The rebuilt blocks of one level, blockColumns x blockRows, row by row; then its children's.
    std::vector<std::vector<float>> parents, blocks;
    for (int l = 0; l <= level; ++l) {
        const int cols = L.blockColumns(l), rows = L.blockRows(l), parentCols = l > 0 ? L.blockColumns(l - 1) : 0;
        blocks.assign(std::size_t(cols) * std::size_t(rows), {});
        tbb::parallel_for(std::size_t(0), blocks.size(), [&](std::size_t k) {
            const int c = int(k % std::size_t(cols)), r = int(k / std::size_t(cols));
            std::span<const float> parent;
            if (l > 0) parent = parents[std::size_t(r / 2) * std::size_t(parentCols) + std::size_t(c / 2)];
            blocks[k] = file.readBlock(l, c, r, parent);
        });
        parents.swap(blocks);
    }
    const int w = L.levelWidth(level), h = L.levelHeight(level), bs = L.blockSide, cols = L.blockColumns(level);
    std::vector<float> heights(std::size_t(w) * std::size_t(h));
    for (int t = 0; t < h; ++t) {
        float* dst = heights.data() + std::size_t(h - 1 - t) * std::size_t(w);
        for (int k = 0; k < w; ++k) {
            const auto& block = parents[std::size_t(t / bs) * std::size_t(cols) + std::size_t(k / bs)];
            dst[k] = block[std::size_t(t % bs) * std::size_t(bs) + std::size_t(k % bs)];
            if (dst[k] == kDemNull)
                refuse(file.path(), "level " + std::to_string(level) + " sample (" + std::to_string(k) + ", " +
                                        std::to_string(t) + ") is null after its rebuild");
        }
    }
    const double c = L.levelCell(level);
    const Box extent{{L.origin.x - 0.5 * c, L.origin.y - (double(h) - 0.5) * c},
                     {L.origin.x + (double(w) - 0.5) * c, L.origin.y + 0.5 * c}};
    return Dem(extent, w, h, std::move(heights));
}

// ---- the copy ----

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

// ---- an in-memory Dem ----

void writeDemLod(SqliteDb& db, const Dem& dem, int blockSide, int srsId, DemLodLayout* out) {
    const Vec2 cell = dem.cellSize();
    if (cell.x != cell.y)
        throw std::invalid_argument("writeDemLod(): cells of " + std::to_string(cell.x) + " x " + std::to_string(cell.y) +
                                    " m are not square");
    const int w = dem.width(), h = dem.height();
    const DemLodLayout layout = DemLodLayout::make(w, h, cell.x, dem.samplePosition(0, h - 1), blockSide);
    db.exec("BEGIN IMMEDIATE");
    try {
        DemLodWriter writer(db, layout, srsId);
        for (int t = 0; t < h; ++t)
            writer.addRow(std::span<const float>(dem.heights()).subspan(std::size_t(h - 1 - t) * std::size_t(w), std::size_t(w)));
        writer.finish();
        db.exec("COMMIT");
    } catch (...) {
        try {
            db.exec("ROLLBACK");
        } catch (const std::exception&) {
        }
        throw;
    }
    if (out) *out = layout;
}

}  // namespace lacet
