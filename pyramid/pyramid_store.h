#pragma once
// The GeoPackage of a tile pyramid (§7): what `lacet pyramid build` writes and `lacet pyramid
// update`, the editor and `lacet info` read. GIS tools (gdalinfo, gdal_translate, QGIS) open its
// tables as they are:
// - kAppearanceTable: the appearance's colour, a tile table (gpkg_contents 'tiles') of RGB JPEG,
//   PNG or WebP (gpkg_webp extension) tiles of tileSize^2 texels;
// - kWaterTable: the water mask, a tile table of grey PNG tiles, holding only tiles with water
//   (a missing tile is no water, as the GeoPackage conventions allow);
// - kElevationTable: z_m, a 2D gridded coverage ('2d-gridded-coverage', float, TIFF tiles of
//   elevationSize^2 cells, grid-value-is-center, metres), with its gpkg_2d_gridded_tile_ancillary
//   row per tile;
// each with one tile matrix set (the scene's square extent, in the scene's CRS) and a tile matrix
// per level (level l: 2^l x 2^l tiles; GeoPackage tile_row 0 is the northmost row, quad ty
// 2^l - 1). Lacet's own tables: lacet_pyramid (key, value: what the pyramid was built for, see
// PyramidInfo) and lacet_pyramid_quads (the digest of each quad's inputs, pyramid/quad_digest.h).
//
// Writes happen inside begin() / commit(): an interrupted build or update leaves the previous
// pyramid as it was (SQLite's rollback journal). Errors throw PyramidError naming the file.
// tile(), putTile(), putElevation(), removeTile() and putDigest() may be called from several
// threads at once (one at a time gets the connection); the others from one thread.

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "io/sqlite_db.h"
#include "model/types.h"

namespace lacet {

class PyramidError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

inline constexpr const char* kAppearanceTable = "lacet_appearance";
inline constexpr const char* kWaterTable = "lacet_water";
inline constexpr const char* kElevationTable = "lacet_elevation";
inline constexpr int kPyramidFormatVersion = 1;
inline constexpr int kMaxPyramidLevel = 30;  // deepest level a pyramid may hold (2^30 tiles a side)

struct PyramidInfo {
    int formatVersion = kPyramidFormatVersion;
    int minLevel = 0, maxLevel = 0;  // levels stored, inclusive
    int vectorLevel = 0;             // levels >= this are made from vector data, those below mipmapped
    bool appearance = true, elevation = true;  // the layers stored
    int tileSize = 256;              // appearance texels per tile side
    int elevationSize = 24;          // elevation cells per tile side
    std::string encoding;            // the appearance tiles' encoding ("jpeg:90", "png:1", "webp:90")
    Box extent;                      // the scene's extent (m, scene CRS)
    std::string crsWkt;              // the scene's CRS, empty when it has none
    std::uint64_t inputs = 0;        // digest of the DEM, the scene's layers and every knob
    bool complete = false;           // every tile of the levels is stored
    std::string sceneChecksum;       // io/scene_checksum.h's text of the scene the tiles show; empty: unknown
};

struct PyramidKey {
    int level = 0;
    std::uint32_t tx = 0, ty = 0;
    friend bool operator==(const PyramidKey&, const PyramidKey&) = default;
};
struct PyramidKeyHash {
    std::size_t operator()(const PyramidKey& k) const {
        return std::hash<std::uint64_t>()((std::uint64_t(k.level) << 58) ^ (std::uint64_t(k.tx) << 29) ^ k.ty);
    }
};
using QuadDigestMap = std::unordered_map<PyramidKey, std::uint64_t, PyramidKeyHash>;

// Whether `path` is a GeoPackage holding a Lacet pyramid (a lacet_pyramid table); never throws.
bool isPyramidFile(const std::string& path);

class PyramidStore {
public:
    enum class Mode { ReadOnly, ReadWrite };
    // ReadWrite creates a new GeoPackage when `path` does not exist; an existing file must be a
    // GeoPackage (its tables are kept; the pyramid's are added or replaced).
    PyramidStore(const std::string& path, Mode mode);

    const std::string& path() const { return path_; }
    // What lacet_pyramid says; nullopt when the file holds no pyramid. Throws PyramidError when
    // the table is there but unreadable or of a later format.
    std::optional<PyramidInfo> info();

    void begin();
    void commit();
    void rollback();  // quiet when no transaction is open

    // Drops the pyramid's tables if any and creates them empty for `info` (inside a transaction).
    void create(const PyramidInfo& info);
    // Rewrites lacet_pyramid (e.g. `complete` at the end of a build).
    void writeInfo(const PyramidInfo& info);

    // A tile's stored bytes; nullopt when missing.
    std::optional<std::vector<std::uint8_t>> tile(const char* table, const PyramidKey& q);
    // Stores a tile unless the same bytes are stored already; true when it wrote.
    bool putTile(const char* table, const PyramidKey& q, std::span<const std::uint8_t> bytes);
    // An elevation tile with its ancillary statistics (metres).
    bool putElevation(const PyramidKey& q, std::span<const std::uint8_t> bytes, double min, double max, double mean,
                      double stdDev);
    // Removes a tile; true when there was one.
    bool removeTile(const char* table, const PyramidKey& q);
    std::size_t tileCount(const char* table);
    std::uint64_t tileBytes(const char* table);

    QuadDigestMap digests();
    void putDigest(const PyramidKey& q, std::uint64_t digest);

    // Every tile key and its size in bytes, of one table (for lacet info and the tests).
    std::vector<std::pair<PyramidKey, std::vector<std::uint8_t>>> allTiles(const char* table);

    SqliteDb& db() { return db_; }

private:
    // f(), its SQLite errors (the reason only) and its own PyramidErrors thrown as PyramidError naming
// this file.
    template <class F>
    auto named(F&& f) -> decltype(f()) {
        try {
            return f();
        } catch (const SqliteError& e) {
            throw PyramidError(path_ + ": " + e.what());
        } catch (const PyramidError& e) {
            throw PyramidError(path_ + ": " + e.what());
        }
    }
    void dropPyramid();
    // A prepared statement of `sql`, kept for the next call (reset, no bindings). Under mutex_.
    SqliteStatement& statement(const std::string& sql);
    std::optional<std::vector<std::uint8_t>> readTile(const char* table, const PyramidKey& q);  // under mutex_
    bool writeTile(const char* table, const PyramidKey& q, std::span<const std::uint8_t> bytes);  // under mutex_

    std::string path_;
    SqliteDb db_;
    bool inTransaction_ = false;
    std::mutex mutex_;  // tile reads and writes may come from several threads (a mipmap's children)
    std::unordered_map<std::string, std::unique_ptr<SqliteStatement>> statements_;  // finalized before db_ closes
};

}  // namespace lacet
