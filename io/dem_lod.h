#pragma once
// A DEM larger than memory: a tree of non-redundant level-of-detail blocks in the scene file
// (Lerbour, Marvie & Gautron, "generic streaming", §4.2 and §5), stored as a GeoPackage 2D gridded
// coverage so that gdalinfo and GIS tools list it, written row by row (never the whole grid in
// memory) and read block by block.
//
// Levels. The finest grid (level n - 1) is the DEM at its own resolution: width x height samples,
// sample (i, t) at column i from the left and row t from the TOP (GeoPackage order), its position
// origin + (i, -t) * cell, origin being the top-left sample's centre. Level l keeps every
// step(l) = 2^(n-1-l)-th sample of it on both axes: level sample (k, r) is finest sample
// (k * step, r * step). The grid is padded to blockSide * 2^(n-1) samples a side, so level l is
// exactly 2^l x 2^l blocks of blockSide x blockSide samples and the root (level 0) is one block;
// n is the smallest count for which the padded side covers max(width, height).
//
// Non-redundancy. A sample is stored once, in the coarsest level that has it: a block of level
// l > 0 leaves its samples at even local (column, row) to its parent, which holds them (blockSide is
// even, so block (c, r)'s even samples are its parent's samples ((c & 1) * blockSide / 2 + m / 2,
// ...)). Stored tiles hold kDemNull there and beyond the grid (padding); a block wholly beyond the
// grid has no tile. A reader rebuilds a block (every sample of its level) from its tile and its
// parent's rebuilt block: inheritFromParent().
//
// GeoPackage mapping. Table kDemLodTable, data_type '2d-gridded-coverage', one tile matrix per level
// (zoom_level = l, matrix 2^l x 2^l, tiles blockSide x blockSide, pixel size cell * step(l)); the
// tile matrix set's min x is origin.x, its max y is origin.y (grid-value-is-corner: a pixel's value
// is at its top-left corner, the same point at every level); data_null = kDemNull; each tile is a
// float TIFF (io/tile_codec.h: encodeFloatTiffDeflate, with the floating-point predictor: 2.07 MB
// for 2.8 MB of floats where the uncompressed TIFFs take 4.46 MB). GIS tools see level 0 whole and the finer levels with
// nulls where the parent holds the value. Every tile has its gpkg_2d_gridded_tile_ancillary row
// (min, max, mean, std_dev of its non-null samples; NULL when it has none).
//
// Lacet's own metadata: table kDemLodMetaTable (key TEXT, value TEXT; an 'attributes' entry of
// gpkg_contents), so that a file holding only the tree (an import's output) is complete without a
// scene's lacet_meta: version (kDemLodFormatVersion), width, height, cell, origin_x, origin_y (C hex
// floats, exact), block_side, levels, digest (16 hex digits, DemLodWriter::digest()). It is written
// by DemLodWriter::finish(): a tree whose writer did not finish has none and is refused.
//
// Order of calls. Write: DemLodWriter (or writeDemLod() from an in-memory Dem), addRow() height
// times, finish(), then the caller commits. Read: DemLodFile, then readBlock() from the root down
// (each block needs its parent's rebuilt block), or readDemLevel() for a whole level. Copy into
// another GeoPackage (a scene being saved): copyDemLod().
//
// Units: positions in scene metres, heights in metres.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/digest.h"
#include "model/types.h"
#include "raster/dem.h"

namespace lacet {

class SqliteDb;
class SqliteStatement;

inline constexpr const char* kDemLodTable = "dem_lod";
inline constexpr const char* kDemLodMetaTable = "lacet_dem_lod";  // Lacet's key/value metadata (above)
inline constexpr int kDemLodFormatVersion = 1;
// The null of the coverage (GDAL's usual Float32 nodata): inherited and padding samples.
inline constexpr float kDemNull = -std::numeric_limits<float>::max();
inline constexpr int kDefaultDemBlockSide = 256;  // samples
// More levels than any tree has (blocks of at least 4 samples, at most 2^31 samples a side: 30).
inline constexpr std::size_t kMaxDemLevels = 32;
// The largest level a scene holds in memory (SceneDocument::dem of a streamed DEM): samples a side.
inline constexpr int kInMemoryDemSide = 4096;

// A DEM LOD tree that cannot be read: the message names the file, and the block when one is at fault.
class DemLodError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DemLodLayout {
    int width = 0, height = 0;   // the finest grid, samples
    double cell = 0.0;           // metres between finest samples (both axes)
    Vec2 origin{0.0};            // the top-left sample's centre, scene metres
    int blockSide = kDefaultDemBlockSide;  // samples, even, >= 4
    int levels = 0;              // n; set by make()

    // Throws std::invalid_argument for sizes < 2, a cell <= 0 or not finite, an odd or small block,
    // or more than 2^31 samples a side.
    static DemLodLayout make(int width, int height, double cell, Vec2 origin, int blockSide = kDefaultDemBlockSide);

    int step(int level) const { return 1 << (levels - 1 - level); }
    double levelCell(int level) const { return cell * double(step(level)); }
    // Samples of level l that lie on the grid: ceil(width / step), ceil(height / step).
    int levelWidth(int level) const { return (width + step(level) - 1) / step(level); }
    int levelHeight(int level) const { return (height + step(level) - 1) / step(level); }
    int blocksPerSide(int level) const { return 1 << level; }
    // Whether block (col, row) of a level holds any sample of the grid.
    bool hasBlock(int level, int col, int row) const {
        return col * blockSide < levelWidth(level) && row * blockSide < levelHeight(level);
    }
    // The blocks of a level that hasBlock() says exist: columns 0 .. blockColumns - 1, rows
    // 0 .. blockRows - 1 (each at most blocksPerSide()).
    int blockColumns(int level) const { return (levelWidth(level) + blockSide - 1) / blockSide; }
    int blockRows(int level) const { return (levelHeight(level) + blockSide - 1) / blockSide; }
    // Every tile the tree stores, all levels together.
    std::int64_t tileCount() const;
    // The Dem extent of the finest grid (cells centred on the samples): what an in-memory Dem of the
    // same samples covers.
    Box extent() const;
    // The coarsest level whose sample spacing (levelCell) is at most `spacing` metres, i.e. the
    // coarsest that still resolves it; the finest level when none is fine enough. Throws
    // std::invalid_argument for a NaN spacing.
    int levelFor(double spacing) const;
    friend bool operator==(const DemLodLayout&, const DemLodLayout&) = default;
};

// Fills the inherited samples of a rebuilt block (blockSide^2, rows from the top) of level l > 0
// at (col, row) from its parent's rebuilt block. Throws std::invalid_argument on a size other than
// blockSide^2, an odd or small blockSide, or a negative col or row.
void inheritFromParent(std::span<float> block, std::span<const float> parent, int col, int row, int blockSide);

// Writes the tree of blocks into an open GeoPackage (inside the caller's transaction) from the
// finest grid's rows, top row first. Memory: blockSide rows of every level (about
// 2 * width * blockSide floats), whatever the height. Also digests every sample (see digest()).
class DemLodWriter {
public:
    // Creates kDemLodTable and its GeoPackage rows (contents, tile matrix set and matrices, coverage
    // ancillary, extensions); `srsId` names an existing gpkg_spatial_ref_sys row (-1: GeoPackage's
    // undefined Cartesian, what a scene without a CRS uses; 0 is its undefined geographic). Throws
    // SqliteError, or std::invalid_argument when the table (or kDemLodMetaTable) exists, the srs row
    // does not, or `layout` is not what DemLodLayout::make() gives.
    DemLodWriter(SqliteDb& db, const DemLodLayout& layout, int srsId);
    ~DemLodWriter();
    // Row t = rows added so far; `heights` holds width finite values other than kDemNull. Throws
    // std::invalid_argument on a wrong size, a non-finite or null height (naming the sample), or a
    // row beyond the height. Writes the block rows this row completes (SqliteError on failure).
    void addRow(std::span<const float> heights);
    // Writes the blocks still buffered and kDemLodMetaTable; throws std::invalid_argument when fewer
    // than height rows were added or when called twice.
    void finish();
    std::uint64_t tilesWritten() const { return tiles_; }
    std::uint64_t bytesWritten() const { return bytes_; }
    // A digest of the layout and every sample in row order (16 hex digits), for the scene checksum.
    std::string digest() const;

private:
    struct LevelStrip;
    void flushLevel(int level, int blockRow, int rows);
    SqliteDb& db_;
    DemLodLayout layout_;
    std::vector<LevelStrip> strips_;
    std::unique_ptr<SqliteStatement> insert_, ancillary_;
    int rowsAdded_ = 0;
    bool finished_ = false;
    std::uint64_t tiles_ = 0, bytes_ = 0;
    Digest digest_;
};

// Reads blocks of the tree from a GeoPackage: its own read-only connection, safe to call from
// several threads (reads are serialized; decoding is not).
class DemLodFile {
public:
    // Reads the layout from kDemLodMetaTable and checks it against the tile matrix set and the tile
    // matrices. Throws DemLodError naming the file and what is missing or inconsistent.
    explicit DemLodFile(const std::string& path);
    ~DemLodFile();
    const std::string& path() const { return path_; }
    const DemLodLayout& layout() const { return layout_; }
    const std::string& digest() const { return digest_; }
    // The stored samples of a block (blockSide^2, rows from the top, kDemNull where inherited or
    // beyond the grid); all kDemNull when the block has no tile (!hasBlock). Throws DemLodError
    // naming the file and block when its tile is missing although hasBlock() says it exists, does
    // not decode, has the wrong size, or holds a value where it must hold kDemNull or a null or
    // non-finite value where it must hold a height; std::out_of_range for a block outside the level.
    std::vector<float> readStored(int level, int col, int row) const;
    // The rebuilt block: readStored() with the inherited samples from `parent` (the parent's rebuilt
    // block; empty only for level 0, where it is ignored). Samples beyond the grid stay kDemNull.
    // Throws as readStored(), and std::invalid_argument for a parent of another size.
    std::vector<float> readBlock(int level, int col, int row, std::span<const float> parent) const;

private:
    std::string path_;
    DemLodLayout layout_;
    std::string digest_;
    std::unique_ptr<SqliteDb> db_;
    std::unique_ptr<SqliteStatement> select_;
    mutable std::mutex mutex_;
};

// The whole of a level in memory: its levelWidth x levelHeight samples on the grid (no padding) as
// a Dem (rows j growing with y: Dem row j is level row levelHeight - 1 - j), with cells of
// levelCell(level) centred on the samples (the top-left sample's centre is layout.origin), built
// block by block from the root down (blocks decoded in parallel). Throws DemLodError as readBlock()
// does, std::out_of_range for a level outside 0 .. levels - 1.
Dem readDemLevel(const DemLodFile& file, int level);

// The finest level whose levelWidth and levelHeight are both at most `maxSide` samples; level 0 when
// none is (maxSide below the root's size). Throws std::invalid_argument for maxSide < 1.
int levelAtMost(const DemLodLayout& layout, int maxSide);

// Copies kDemLodTable, kDemLodMetaTable and their GeoPackage rows (contents, tile matrix set, tile
// matrices, coverage and tile ancillary, extensions) from the GeoPackage at `from` into the open
// `db` (a scene file being saved), out of core (SQLite ATTACH, read-only: a missing `from` is never
// created), in its own transaction: call it outside one. The copied tree's gpkg_contents and
// gpkg_tile_matrix_set rows get `srsId`, a row of `db`'s gpkg_spatial_ref_sys (the scene's CRS, or
// -1, undefined Cartesian, for a scene without one), whatever the source's: a tree is written in
// scene metres under -1 (io/dem_import_lod.h). Throws DemLodError naming `from` when it does not
// exist, is not a regular file or holds no complete tree, and when `db` already has a tree or no
// row of `srsId`; SqliteError on failure.
void copyDemLod(SqliteDb& db, const std::string& from, std::int64_t srsId);

// Writes an in-memory Dem as a tree into the open GeoPackage `db`, in its own transaction (for tests
// and small DEMs): the finest grid is the Dem's samples, rows from the top (Dem row height - 1
// first), origin = dem.samplePosition(0, height - 1), cell = the Dem's (square) cell. Stores the
// layout in *out when given. Throws std::invalid_argument for cells that are not square and as
// DemLodLayout::make() and DemLodWriter do.
void writeDemLod(SqliteDb& db, const Dem& dem, int blockSide, int srsId, DemLodLayout* out = nullptr);

}  // namespace lacet
