#pragma once
// Internals of the scene file (io/scene_file.h), shared by its parts and by nothing else:
//   scene_schema.cpp    the format's tables and their gpkg_contents entries, lacet_meta (doubles as
//                       exact hex text), the checks made on opening a file
//   scene_elements.cpp  the element tables: lacet_layers, lacet_nodes, lacet_curves, lacet_areas,
//                       lacet_attributes, written and read back
//   scene_file.cpp      saveScene (atomically, io/atomic_file.h), loadScene (with its DEM), isLacetScene
// Order of calls. Save: writeSceneTables (one transaction: the schema, lacet_meta, writeElementTables,
// the feature tables). Load: openSceneTables (returns lacet_meta), readElementTables, then the DEM.

#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "io/document.h"
#include "io/sqlite_db.h"

namespace lacet::scene_format {

inline constexpr const char* kFormatName = "lacet-scene";
inline constexpr std::int64_t kGpkgApplicationId = 0x47504B47;  // 'GPKG'
inline constexpr std::size_t kMaxLayers = 65536;                // LayerId is 16 bits

// A problem with the file's contents (reason only); loadScene adds the file name.
class FormatError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// ---- scene_schema.cpp ----

// Adds the lacet_* tables (and the feature tables, io/scene_features.h) to the GeoPackage at `path`,
// in one transaction.
void writeSceneTables(const std::string& path, const SceneDocument& doc);

using Meta = std::map<std::string, std::string>;

// Checks that `db` is an intact GeoPackage holding a Lacet scene of a known version (its size is
// `fileSize` bytes); returns its lacet_meta. Throws FormatError.
Meta openSceneTables(SqliteDb& db, std::int64_t fileSize);

// Values of lacet_meta; each throws FormatError naming the key when it is missing or malformed.
const std::string& metaValue(const Meta& meta, const std::string& key);
double metaDouble(const Meta& meta, const std::string& key);
std::int64_t metaInteger(const Meta& meta, const std::string& key, std::int64_t lo, std::int64_t hi);
Box metaBox(const Meta& meta, const std::string& prefix);  // prefix_min_x ... prefix_max_y

// ---- scene_elements.cpp ----

// Writes lacet_layers, lacet_nodes, lacet_curves, lacet_areas and lacet_attributes (created empty).
void writeElementTables(SqliteDb& db, const SceneDocument& doc);

// Reads them back into doc.scene's layers and doc.attributes; throws FormatError naming the row.
void readElementTables(SqliteDb& db, SceneDocument& doc);

}  // namespace lacet::scene_format
