#pragma once
// The scene file: a scene, its georeference and its DEM in one GeoPackage (OGC GPKG 1.2, an SQLite
// database), so that `ogrinfo` and `gdalinfo` open it and GIS tools can look inside.
//
// Contents (format version 1):
//   dem           the DEM as a GPKG 2D gridded coverage raster, Float32 in lossless TIFF tiles, written
//                 through GDAL (io/gpkg_dem.h). Absent when the document has no DEM: the file is then
//                 a vector-only GeoPackage, which `gdalinfo` refuses ("not recognized") though
//                 `ogrinfo` opens it.
//   dem_lod, lacet_dem_lod  instead of dem, when the document's DEM is streamed (doc.demLod): the
//                 non-redundant LOD block tree of io/dem_lod.h (a 2D gridded coverage, one tile matrix
//                 per level) and its layout, copied from the file doc.demLod reads; lacet_meta 'dem'
//                 is then 'dem_lod' and dem_width, dem_height, dem_extent_* give its finest grid.
//                 Loading checks that every tile the layout needs is there, opens the tree
//                 (doc.demLod) and reads the level levelAtMost(layout, kInMemoryDemSide) into doc.dem;
//                 the checksum covers the tree's layout and digest instead of doc.dem.
//   lacet_meta    key/value text: format, format_version, the extent, the georeference, crs_wkt and the
//                 DEM's grid (dem, dem_width, dem_height, dem_extent_*), and a 64-bit checksum of
//                 the whole document's values (checksum, 16 hex digits; io/scene_checksum.h, in the
//                 form of the file's version), with, from version 2, its two parts (checksum_head,
//                 checksum_elements) that a save in place updates. Doubles are C hex floats
//                 ("0x1.f4p+9", exact; a NaN as "nan:" and its 16 hex digits of bits).
//   lacet_layers  id, name, kind (toString(LayerKind)).
//   lacet_nodes   layer, id, x, y, alive, curves (BLOB, u32 ids), roundabout (REAL, the ring's
//                 radius in metres, 0 for none; files written before it load with 0).
//   lacet_curves  layer, id, start, end, w, wf, cls, flags, alive, vertices (BLOB: every x, y as
//                 f64, then one flag byte per vertex: bit 0 on-curve, bit 1 closing), areas (BLOB, u32).
//   lacet_areas   layer, id, wf, cls, axial, alive, loops (BLOB: u32 loop count, then per loop a u32
//                 edge count and per edge a u32 curve id and a u8 reversed flag).
//   lacet_attributes  layer, kind (0 node, 1 curve, 2 area), id, key, value: attributes kept from the
//                 source data (names, bridge, tunnel, layer...), in the document's order.
//   feature tables  the alive curves and areas of each layer as GeoPackage LINESTRING and POLYGON
//                 features in the scene CRS, sampled from the Bezier splines within 0.1 m, with their
//                 id, class, widths, flags and source attributes as columns and an R-tree index, so
//                 QGIS and ogrinfo see them (io/scene_features.h: names, columns, SRS). Derived data,
//                 rewritten by every save: loadScene ignores them, the checksum does not cover them,
//                 and files without them (written before them) load the same.
// All binary values are little-endian. Every slot is stored, deleted ones too (alive = 0), so ids
// survive. The lacet_* tables are 'attributes' entries of gpkg_contents. Doubles and floats in REAL
// columns are exact (SQLite REAL is a 64-bit double), except the two values SQLite cannot keep in a
// REAL column, -0.0 (kept as 0) and NaN (kept as NULL): a row with one of those also carries the exact
// bytes of its REAL fields in its `exact` BLOB column (x, y as f64; w, wf or wf as f32), NULL otherwise.
// The file is for Lacet to write: a GIS tool may read it, but a value edited outside Lacet no longer
// matches the checksum, and the file is refused as corrupt.

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/document.h"

namespace lacet {

class SceneFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// saveSceneOver's refusal: the file changed since it was read (another editor or command saved it).
class SceneFileChangedError : public SceneFileError {
public:
    using SceneFileError::SceneFileError;
};

// Current version of the format above; loadScene refuses files of a later version.
// Files of version 1 load as before (their checksum is format 1's, io/scene_checksum.h); a save
// in place of edits (io/scene_save_edits.h) makes such a file version 2.
constexpr int kSceneFormatVersion = 2;

// Saves atomically: writes `path` + ".tmp" (removing a stale one and its SQLite journal), fsyncs
// it, then renames it over `path` and fsyncs the directory; a crash or an exception at any point
// leaves a previous file at `path` intact (after an exception, the temporary file is removed).
// The SQLite part (everything but the DEM raster) is written in one transaction. Refuses a scene
// that fails validate() (it could not be loaded back) and one with more than 65536 layers. Throws
// SceneFileError naming the file and the reason.
void saveScene(const std::string& path, const SceneDocument& doc);

// saveScene of a scene too large for memory, made while it is written (lacet synth --out): `head` is
// the document but for the parts of layer `layer`, which `produce` makes, calling its argument with
// each part in id order (model/graph.h: a layer part, its elements referring only to each other by
// ids from 0). The file is the one saveScene would write for `head` with the parts appended to that
// layer (appendLayerPart): the same rows, feature tables and checksum, so loadScene and
// loadSceneRegion read it as any other. Each part is checked by validate() on its own, and the
// checksum is summed over the rows written, read back. Memory: `head`, one part, and SQLite's cache.
// Parts carry no attributes; one with curves outside areas in an areal layer that `head` leaves
// empty of them (no table of lines planned for it) is refused. An exception from `produce` or a
// refused part leaves `path` as it was. Throws SceneFileError naming the file and the reason.
void saveSceneStreamed(const std::string& path, const SceneDocument& head, LayerId layer,
                       const std::function<void(const std::function<void(Layer&& part)>& sink)>& produce);

// saveScene of a scene made a square part at a time over every layer (an import out of core,
// io/scene_import.h): `head` is the document but for the parts' elements (its layers' names and
// kinds; elements of its own come first), `kinds` plans the feature tables (io/scene_features.h:
// per layer, whether lines and areas come and their attribute keys), and `produce` calls its
// argument with each part. A part holds every layer of head, its elements referring to each other
// by ids from 0, its attributes by those ids, and per layer its border nodes: a border node at the
// same point of the same layer as one of an earlier part is that node (its curves joined), the
// others are appended after the elements so far. Parts come in increasing `index`; `lastPartAt(p)`
// is the last index whose part can have a border node at p: once that part is written, the node's
// row is final (rewritten with every curve) and it leaves memory. Each part is checked by
// validate() alone; the checksum is summed over the rows written, read back. Memory: `head`, one
// part, the border nodes still open and SQLite's cache. An exception from `produce` or a refused
// part leaves `path` as it was. Throws SceneFileError naming the file and the reason.
struct ScenePart {
    std::size_t index = 0;
    Scene scene;
    std::vector<ElementAttribute> attributes;
    std::vector<std::vector<ElementId>> borderNodes;  // per layer
};
struct FeatureKindsPlan;  // io/scene_features.h
void saveSceneInParts(const std::string& path, const SceneDocument& head, const std::vector<FeatureKindsPlan>& kinds,
                      const std::function<std::size_t(Vec2)>& lastPartAt,
                      const std::function<void(const std::function<void(ScenePart&& part)>& sink)>& produce);

// Loads what saveScene wrote: the same model bit for bit (every layer, node, curve, area, dead slots
// included, every double exact; the DEM's heights exact). Throws SceneFileError naming the file and
// the reason for a missing, empty, truncated or corrupt file (SQLite's page count and quick_check
// first, then every value read is checked, then the checksum), a file that is not a Lacet scene or
// is of a later format version, or one whose model fails validate() (model/validate.h).
SceneDocument loadScene(const std::string& path);
// The same, and the checksum the file stores (lacet_meta), which saveSceneOver expects.
SceneDocument loadScene(const std::string& path, std::string& storedChecksum);

// The checksum the scene file at `path` stores (lacet_meta), read alone (not checked against the
// contents: loadScene does that). Throws SceneFileError naming the file.
std::string storedSceneChecksum(const std::string& path);

// saveScene over the file a document was read from, when no one else saved it since: two editors of
// one file, or an editor and a command, take turns and never lose an edit. Under an SQLite write
// lock of the file at `path` (BEGIN IMMEDIATE, which another saver holding it makes this wait for,
// up to `lockWaitMs`; a saver that replaced the file meanwhile makes this lock the new one), its
// stored checksum must be `expected` (loadScene's, or the previous saveSceneOver's): else
// SceneFileChangedError naming the file, which is left as it is. Returns the checksum the new file
// stores. Throws SceneFileError as saveScene does, and when the file is gone or the lock is not given.
std::string saveSceneOver(const std::string& path, const SceneDocument& doc, const std::string& expected, int lockWaitMs = 30000);

// Whether `path` is a file Lacet wrote: a GeoPackage whose lacet_meta says it is a Lacet scene.
// Reads only the header and one table (not the checksum); never throws. The import replaces an
// existing file only when this says so (or when forced): it never overwrites what it does not own.
bool isLacetScene(const std::string& path);

// Whether `path` is what a save killed before its rename leaves as its temporary file: empty (killed
// as it was created), a GeoPackage holding no more than the DEM part a save writes first (GeoPackage
// tables, the DEM raster or tree; its SQLite part rolled back from its journal), or a whole scene.
// A file a user named so holds anything else and is not removed. Never throws.
bool isStaleSaveTemporary(const std::string& path);

class SqliteDb;

// A scene file kept open between reads of its parts (io/scene_region.h), by one thread: one SQLite
// connection, so that a read of a few rows (an edit's, a river search's) pays neither the open nor
// the parse of the file's schema (a GeoPackage's tables, R-trees and triggers: most of such a
// read's time). Opened by its first read, with that read's checks and errors; opened again when the
// file at the path is another one since (renamed over). Each read sees the file as it is then, as
// a read by path does.
class SceneFileConnection {
public:
    explicit SceneFileConnection(std::string path);
    ~SceneFileConnection();
    SceneFileConnection(const SceneFileConnection&) = delete;
    SceneFileConnection& operator=(const SceneFileConnection&) = delete;
    const std::string& path() const { return path_; }

    // Internal (io/scene_format.h: loadSceneParts): the connection to the file whose device and
    // inode are `device`, `inode`, opened now if it is not open to that file.
    SqliteDb& open(std::uint64_t device, std::uint64_t inode);

private:
    std::string path_;
    std::unique_ptr<SqliteDb> db_;
    std::uint64_t device_ = 0, inode_ = 0;
};

}  // namespace lacet
