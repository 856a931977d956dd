// The reader of the DEM LOD tree (io/dem_lod.h): the layout checked against the GeoPackage rows,
// one read-only connection (reads serialized, decoding not), every stored sample checked; and a
// whole level in memory (readDemLevel).
#include <bit>
#include <charconv>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>

#include "io/dem_lod.h"
#include "io/dem_lod_internal.h"
#include "io/gpkg_coverage.h"
#include "io/sqlite_db.h"
#include "io/tile_codec.h"

namespace lacet {

using namespace dem_lod_detail;

namespace {

constexpr int kBusyTimeoutMs = 30000;  // ms a statement waits for another connection's lock

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
                refuse(path, "the tile matrix set's corner (" + gpkgReal(s.real(0)) + ", " + gpkgReal(s.real(1)) +
                                 ") is not the origin (" + gpkgReal(layout_.origin.x) + ", " + gpkgReal(layout_.origin.y) + ")");
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

}  // namespace lacet
