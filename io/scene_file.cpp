// Saving and loading a scene file: the order of the work and its errors (io/scene_file.h); the
// tables themselves are in scene_schema.cpp and scene_elements.cpp (io/scene_format.h).
#include "io/scene_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "io/atomic_file.h"
#include "io/dem_lod.h"
#include "io/gpkg_dem.h"
#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/scene_format.h"
#include "io/sqlite_db.h"
#include "model/validate.h"

namespace lacet {
namespace {

using namespace scene_format;

// saveScene writes every tile of the DEM raster (io/gpkg_dem.h), but GDAL reads a missing tile as
// zeros: count the tiles of the finest zoom level. GDAL anchors the raster at the top left corner of
// its tile matrix set (which it may extend to a square), so ceil(width / tile width) x
// ceil(height / tile height) tiles cover it.
void checkDemTiles(SqliteDb& db, std::int64_t width, std::int64_t height) {
    const std::string table = kDemRasterTable;
    if (!db.hasTable(table)) throw FormatError("no DEM raster table '" + table + "'");
    auto s = db.prepare(
        "SELECT zoom_level, tile_width, tile_height FROM gpkg_tile_matrix WHERE table_name = ? "
        "ORDER BY zoom_level DESC LIMIT 1");
    s.bindText(1, table);
    if (!s.step()) throw FormatError("corrupt DEM: no tile matrix for raster table '" + table + "'");
    const std::int64_t zoom = s.integer(0), tileWidth = s.integer(1), tileHeight = s.integer(2);
    if (tileWidth < 1 || tileHeight < 1)
        throw FormatError("corrupt DEM: tiles of " + std::to_string(tileWidth) + " x " + std::to_string(tileHeight));
    const std::int64_t expected = ((width + tileWidth - 1) / tileWidth) * ((height + tileHeight - 1) / tileHeight);
    auto n = db.prepare("SELECT count(*) FROM \"" + table + "\" WHERE zoom_level = ?");
    n.bind(1, zoom);
    n.step();
    if (n.integer(0) != expected)
        throw FormatError("corrupt DEM: raster table '" + table + "' holds " + std::to_string(n.integer(0)) + " of its " +
                          std::to_string(expected) + " tiles");
}

// A streamed DEM's tree must hold every tile its layout says exists (a missing one would be read as
// damage only when the view reaches it): the tiles of each level inside its blocks, and no others.
void checkDemLodTiles(SqliteDb& db, const DemLodLayout& layout) {
    const std::string table = kDemLodTable;
    if (!db.hasTable(table)) throw FormatError("no DEM LOD table '" + table + "'");
    const std::int64_t total = db.queryInteger("SELECT count(*) FROM \"" + table + "\"");
    auto s = db.prepare("SELECT count(*) FROM \"" + table +
                        "\" WHERE zoom_level = ? AND tile_column >= 0 AND tile_column < ? AND tile_row >= 0 AND tile_row < ?");
    for (int l = 0; l < layout.levels; ++l) {
        const std::int64_t expected = std::int64_t(layout.blockColumns(l)) * std::int64_t(layout.blockRows(l));
        s.bind(1, std::int64_t(l));
        s.bind(2, std::int64_t(layout.blockColumns(l)));
        s.bind(3, std::int64_t(layout.blockRows(l)));
        s.step();
        if (s.integer(0) != expected)
            throw FormatError("corrupt DEM: table '" + table + "' holds " + std::to_string(s.integer(0)) + " of the " +
                              std::to_string(expected) + " tiles of level " + std::to_string(l));
        s.reset();
    }
    if (total != layout.tileCount())
        throw FormatError("corrupt DEM: table '" + table + "' holds " + std::to_string(total) + " tiles, " +
                          std::to_string(layout.tileCount()) + " expected");
}

}  // namespace

namespace {

void save(const std::string& path, const SceneDocument& doc, const StreamedLayer* streamed, const StreamedParts* parts = nullptr) {
    if (auto problems = validate(doc.scene); !problems.empty())
        throw SceneFileError(path + ": cannot save an invalid scene: " + ValidationError(std::move(problems)).what());
    for (const Layer& l : doc.scene.layers)
        if (l.isPart())
            throw SceneFileError(path + ": cannot save: layer '" + l.name +
                                 "' holds a part of a scene file's layer (a region read); the rest of it would be lost");
    if (doc.scene.layers.size() > kMaxLayers)
        throw SceneFileError(path + ": cannot save more than " + std::to_string(kMaxLayers) + " layers");
    if (streamed && streamed->layer >= doc.scene.layers.size())
        throw SceneFileError(path + ": cannot save: the streamed layer " + std::to_string(streamed->layer) + " does not exist");
    try {
        replaceFileAtomically(path, [&](const std::string& tmp) {
            if (doc.demLod) {
                // The tree's tiles, copied from the file it is read from (which may be `path`: it is
                // replaced only after this), not the derived doc.dem.
                // Its CRS row is the one the feature tables get (-1 without a georeference).
                createEmptyGpkg(tmp);
                SqliteDb db(tmp, SqliteDb::Mode::ReadWrite);
                copyDemLod(db, doc.demLod->path(), featureSrsId(db, doc));
                db.close();
            } else if (doc.dem) {
                createGpkgWithDem(tmp, *doc.dem, doc.georeference.valid ? doc.georeference.crsWkt : std::string());
            } else {
                createEmptyGpkg(tmp);
            }
            writeSceneTables(tmp, doc, streamed, parts);
        });
    } catch (const std::exception& e) {
        throw SceneFileError(path + ": cannot save: " + e.what());
    }
}

}  // namespace

void saveScene(const std::string& path, const SceneDocument& doc) { save(path, doc, nullptr); }

void saveSceneStreamed(const std::string& path, const SceneDocument& head, LayerId layer,
                       const std::function<void(const std::function<void(Layer&& part)>& sink)>& produce) {
    const StreamedLayer streamed{layer, produce};
    save(path, head, &streamed);
}

void saveSceneInParts(const std::string& path, const SceneDocument& head, const std::vector<FeatureKindsPlan>& kinds,
                      const std::function<std::size_t(Vec2)>& lastPartAt,
                      const std::function<void(const std::function<void(ScenePart&& part)>& sink)>& produce) {
    const StreamedParts parts{&kinds, lastPartAt, produce};
    save(path, head, nullptr, &parts);
}

bool isLacetScene(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0) return false;
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        if (db.queryInteger("PRAGMA application_id") != kGpkgApplicationId || !db.hasTable("lacet_meta")) return false;
        auto s = db.prepare("SELECT value FROM lacet_meta WHERE key = 'format'");
        return s.step() && s.text(0) == kFormatName;
    } catch (const std::exception&) {
        return false;
    }
}

bool isStaleSaveTemporary(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
    if (st.st_size == 0 || isLacetScene(path)) return true;
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);  // rolls back a hot journal first
        if (db.queryInteger("PRAGMA application_id") != kGpkgApplicationId) return false;
        auto tables = db.prepare("SELECT name FROM sqlite_master WHERE type = 'table'");
        while (tables.step()) {
            const std::string name = tables.text(0);
            const bool saveWritesItFirst = name.rfind("gpkg_", 0) == 0 || name.rfind("rtree_", 0) == 0 ||
                                           name.rfind("sqlite_", 0) == 0 || name == kDemRasterTable || name == kDemLodTable ||
                                           name == kDemLodMetaTable;
            if (!saveWritesItFirst) return false;
        }
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

namespace {

// loadSceneParts of the file at `path`, over `connection` (kept open) or a connection of its own.
std::string loadParts(const std::string& path, SceneFileConnection* connection, SceneDocument& doc,
                      const std::function<void(SqliteDb&, SceneDocument&)>& readElements, bool readDem, bool wholeFileCheck,
                      int* formatVersion) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw SceneFileError(path + ": cannot open: " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw SceneFileError(path + ": is a directory, not a Lacet scene");
    if (st.st_size == 0) throw SceneFileError(path + ": empty file, not a Lacet scene");
    std::string checksum;
    try {
        std::optional<SqliteDb> own;
        SqliteDb& db = connection ? connection->open(std::uint64_t(st.st_dev), std::uint64_t(st.st_ino))
                                  : own.emplace(path, SqliteDb::Mode::ReadOnly);
        const Meta meta = openSceneTables(db, std::int64_t(st.st_size), wholeFileCheck);
        doc.scene.extent = metaBox(meta, "extent");
        doc.georeference.valid = metaInteger(meta, "georeference_valid", 0, 1) != 0;
        doc.georeference.lon0 = metaDouble(meta, "georeference_lon0");
        doc.georeference.lat0 = metaDouble(meta, "georeference_lat0");
        doc.georeference.originShift = {metaDouble(meta, "georeference_origin_shift_x"),
                                        metaDouble(meta, "georeference_origin_shift_y")};
        doc.georeference.crsWkt = metaValue(meta, "crs_wkt");
        checksum = metaValue(meta, "checksum");
        if (formatVersion) *formatVersion = int(metaInteger(meta, "format_version", 1, kSceneFormatVersion));
        readElements(db, doc);
        const std::string& dem = readDem ? metaValue(meta, "dem") : std::string("none");
        std::int64_t demWidth = 0, demHeight = 0;
        if (dem == kDemRasterTable || dem == kDemLodTable) {
            demWidth = metaInteger(meta, "dem_width", 1, INT32_MAX);
            demHeight = metaInteger(meta, "dem_height", 1, INT32_MAX);
        }
        if (dem == kDemRasterTable) checkDemTiles(db, demWidth, demHeight);
        if (dem == kDemLodTable) {
            if (!db.hasTable(kDemLodTable)) throw FormatError(std::string("no DEM LOD table '") + kDemLodTable + "'");
            auto lod = std::make_shared<const DemLodFile>(path);
            const DemLodLayout& layout = lod->layout();
            if (layout.width != demWidth || layout.height != demHeight)
                throw FormatError("corrupt DEM: the LOD tree is " + std::to_string(layout.width) + " x " +
                                  std::to_string(layout.height) + ", lacet_meta says " + std::to_string(demWidth) + " x " +
                                  std::to_string(demHeight));
            checkDemLodTiles(db, layout);
            doc.demLod = std::move(lod);
        }
        if (own) own->close();
        if (doc.demLod) {
            doc.dem = readDemLevel(*doc.demLod, levelAtMost(doc.demLod->layout(), kInMemoryDemSide));
        } else if (dem == kDemRasterTable) {
            const Box extent = metaBox(meta, "dem_extent");
            std::vector<float> heights = readGpkgDem(path, int(demWidth), int(demHeight));
            try {
                doc.dem.emplace(extent, int(demWidth), int(demHeight), std::move(heights));
            } catch (const std::invalid_argument& e) {
                throw FormatError(std::string("corrupt DEM: ") + e.what());
            }
        } else if (dem != "none") {
            throw FormatError("lacet_meta 'dem' = '" + dem + "' names no known raster");
        }
    } catch (const FormatError& e) {
        throw SceneFileError(path + ": " + e.what());
    } catch (const DemLodError& e) {
        throw SceneFileError(e.what());  // names the file (`path`) and the block
    } catch (const SqliteError& e) {
        throw SceneFileError(path + ": not a GeoPackage, or corrupt: " + e.what());
    } catch (const std::bad_alloc&) {
        throw SceneFileError(path + ": out of memory while loading");
    } catch (const SceneFileError&) {
        throw;  // names the file already (a region read's budget, io/scene_region.h)
    } catch (const std::exception& e) {
        throw SceneFileError(path + ": cannot load: " + e.what());
    }
    if (auto problems = validate(doc.scene); !problems.empty())
        throw SceneFileError(path + ": invalid scene: " + ValidationError(std::move(problems)).what());
    return checksum;
}

}  // namespace

std::string scene_format::loadSceneParts(const std::string& path, SceneDocument& doc,
                                          const std::function<void(SqliteDb&, SceneDocument&)>& readElements, bool readDem,
                                          bool wholeFileCheck, int* formatVersion) {
    return loadParts(path, nullptr, doc, readElements, readDem, wholeFileCheck, formatVersion);
}

std::string scene_format::loadSceneParts(SceneFileConnection& connection, SceneDocument& doc,
                                          const std::function<void(SqliteDb&, SceneDocument&)>& readElements, bool readDem,
                                          bool wholeFileCheck, int* formatVersion) {
    return loadParts(connection.path(), &connection, doc, readElements, readDem, wholeFileCheck, formatVersion);
}

SceneFileConnection::SceneFileConnection(std::string path) : path_(std::move(path)) {}
SceneFileConnection::~SceneFileConnection() = default;

SqliteDb& SceneFileConnection::open(std::uint64_t device, std::uint64_t inode) {
    if (!db_ || device != device_ || inode != inode_) {
        db_.reset();
        db_ = std::make_unique<SqliteDb>(path_, SqliteDb::Mode::ReadOnly);
        device_ = device;
        inode_ = inode;
    }
    return *db_;
}

SceneDocument loadScene(const std::string& path, std::string& storedChecksum) {
    SceneDocument doc;
    int version = 0;
    const std::string checksum = scene_format::loadSceneParts(path, doc, readElementTables, true, true, &version);
    if (const std::string sum = sceneChecksumText(doc, version); sum != checksum)
        throw SceneFileError(path + ": corrupt file (its contents do not match their checksum: " + sum + ", not " +
                             checksum + ")");
    storedChecksum = checksum;
    return doc;
}

SceneDocument loadScene(const std::string& path) {
    std::string unused;
    return loadScene(path, unused);
}

namespace {

std::string storedChecksumOf(SqliteDb& db, const std::string& path) {
    try {
        return db.queryText("SELECT value FROM lacet_meta WHERE key = 'checksum'");
    } catch (const SqliteError& e) {
        throw SceneFileError(path + ": cannot read its stored checksum (not a Lacet scene?): " + e.what());
    }
}

}  // namespace

std::string storedSceneChecksum(const std::string& path) {
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        return storedChecksumOf(db, path);
    } catch (const SqliteError& e) {
        throw SceneFileError(path + ": cannot open: " + e.what());
    }
}

std::string saveSceneOver(const std::string& path, const SceneDocument& doc, const std::string& expected, int lockWaitMs) {
    const auto storedChecksum = [&](SqliteDb& db) { return storedChecksumOf(db, path); };
    // A saver that renamed a new file over `path` while this one waited for the old file's lock:
    // lock the new one (a few times at most: each is a save that finished).
    constexpr int kAttempts = 16;
    for (int attempt = 0; attempt < kAttempts; ++attempt) {
        struct stat before {};
        if (::stat(path.c_str(), &before) != 0)
            throw SceneFileError(path + ": cannot save over it: " + std::strerror(errno) + " (moved or removed since it was read)");
        std::optional<SqliteDb> lock;
        try {
            lock.emplace(path, SqliteDb::Mode::ReadWrite);
            lock->busyTimeout(lockWaitMs);
            lock->exec("BEGIN IMMEDIATE");
        } catch (const SqliteError& e) {
            throw SceneFileError(path + ": cannot save over it: another program is writing it (waited " + std::to_string(lockWaitMs) +
                                 " ms): " + e.what());
        }
        struct stat now {};
        if (::stat(path.c_str(), &now) != 0 || now.st_dev != before.st_dev || now.st_ino != before.st_ino) continue;
        if (const std::string stored = storedChecksum(*lock); stored != expected)
            throw SceneFileChangedError(path + ": changed since it was read (another editor or command saved it: its checksum is " +
                                        stored + ", was " + expected + "): not saved over, so that neither save is lost; save "
                                        "under another name, or open it again");
        saveScene(path, doc);
        // Read while the old file's lock still makes the other savers wait.
        SqliteDb saved(path, SqliteDb::Mode::ReadOnly);
        const std::string checksum = storedChecksum(saved);
        saved.close();
        try {
            lock->exec("ROLLBACK");
        } catch (const SqliteError&) {
        }
        return checksum;
    }
    throw SceneFileError(path + ": cannot save over it: replaced " + std::to_string(kAttempts) + " times while waiting for its lock");
}

}  // namespace lacet
