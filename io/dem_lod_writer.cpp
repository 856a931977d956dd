// The writer of the DEM LOD tree (io/dem_lod.h): rows in, block rows out as deflated float TIFF
// tiles with their ancillary rows, the layout and digest in kDemLodMetaTable at the end; and
// writeDemLod() from an in-memory Dem.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "io/dem_lod.h"
#include "io/dem_lod_internal.h"
#include "io/gpkg_coverage.h"
#include "io/sqlite_db.h"
#include "io/tile_codec.h"

namespace lacet {

using namespace dem_lod_detail;

namespace {

// zlib level of the tiles: 6 (zlib's default), with TIFF's floating-point predictor. Measured on a
// smooth 1000 x 700 DEM in 17 tiles of 256^2 (tests/io/dem_lod_test.cpp, DemLod.TileEncodingSizes):
// uncompressed 4.46 MB, deflate 2.46 MB, deflate with the predictor 2.07 MB (2.8 MB of floats: the
// nulls of the padding and of the inherited samples compress away).
constexpr int kTileDeflateLevel = 6;
constexpr bool kTileFloatPredictor = true;

}  // namespace

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
    const std::string table = kDemLodTable;
    const int bs = layout.blockSide, n = layout.levels;
    const double side = double(std::int64_t(bs) << (n - 1)) * layout.cell;  // the padded grid, metres
    const Vec2 o = layout.origin;
    GpkgTileTable t;
    t.name = table;
    t.dataType = GpkgTileTable::DataType::GriddedCoverage;
    t.description = "Lacet DEM: non-redundant LOD blocks (heights in m; null where a coarser level holds the sample)";
    // grid-value-is-corner: a pixel's value is at its top-left corner, so the data's bounds run from
    // the top-left sample to one cell beyond the last sample.
    t.contents = {{o.x, o.y - double(layout.height) * layout.cell}, {o.x + double(layout.width) * layout.cell, o.y}};
    t.matrixSet = {{o.x, o.y - side}, {o.x + side, o.y}};
    t.srsId = srsId;
    for (int l = 0; l < n; ++l)
        t.matrices.push_back({.zoomLevel = l,
                              .matrixWidth = layout.blocksPerSide(l),
                              .matrixHeight = layout.blocksPerSide(l),
                              .tileWidth = bs,
                              .tileHeight = bs,
                              .pixelXSize = layout.levelCell(l),
                              .pixelYSize = layout.levelCell(l)});
    createGpkgTileTable(db, t, {.precision = 0.0, .dataNull = double(kDemNull), .gridCellEncoding = "grid-value-is-corner", .uom = "m"});
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
