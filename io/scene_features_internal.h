#pragma once
// Internals of the feature tables (io/scene_features.h), shared by their writer
// (scene_features.cpp: whole tables) and their editor (scene_features_edit.cpp: the features of
// edited elements, in place) and by nothing else.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/le_bytes.h"
#include "io/scene_features.h"

namespace lacet::feature_tables {

inline constexpr std::int64_t kUndefinedCartesianSrsId = -1;
inline constexpr const char* kGeometryColumn = "geom";

bool isLayerOfLines(LayerKind kind);
// A curve is a LINESTRING feature when alive and bordering no alive area of its layer.
bool isLineFeature(const Layer& layer, const Curve& c);

// Lowercase ASCII letters and digits; every run of other bytes becomes one '_'; no '_' at the ends.
std::string identifierPart(std::string_view s);
bool reservedTableName(const std::string& s);
// The name of a layer's first feature table before it is made unique (io/scene_features.h).
std::string tableBaseName(const std::string& layerName);
// `base`, else `base`_2, _3... : the first not in `taken`, which it joins.
std::string uniqueName(const std::string& base, std::set<std::string>& taken);
std::string quoted(const std::string& identifier);
// The columns every feature table has (attribute columns never take these names).
std::set<std::string> fixedColumnNames();
// The name of the column of source attribute `key` before it is made unique (io/scene_features.h).
std::string attributeColumnBase(const std::string& key, const std::set<std::string>& taken);

struct Envelope {
    double minX = std::numeric_limits<double>::infinity(), maxX = -std::numeric_limits<double>::infinity();
    double minY = std::numeric_limits<double>::infinity(), maxY = -std::numeric_limits<double>::infinity();
    void add(Vec2 p) {
        minX = std::min(minX, p.x);
        maxX = std::max(maxX, p.x);
        minY = std::min(minY, p.y);
        maxY = std::max(maxY, p.y);
    }
    void add(const Envelope& e) {
        minX = std::min(minX, e.minX);
        maxX = std::max(maxX, e.maxX);
        minY = std::min(minY, e.minY);
        maxY = std::max(maxY, e.maxY);
    }
    bool empty() const { return !(minX <= maxX); }
};

// Exterior ring first (counter-clockwise), then the holes (clockwise), in loop order.
std::vector<std::vector<Vec2>> polygonRings(const Layer& layer, const Area& area, double tolerance);
// The GeoPackage geometry blob of a polyline or polygon, into `w`; returns its envelope.
Envelope lineStringBlob(ByteWriter& w, const std::vector<Vec2>& points, std::int64_t srsId);
Envelope polygonBlob(ByteWriter& w, const std::vector<std::vector<Vec2>>& rings, std::int64_t srsId);
// The envelope as SQLite's R-tree stores it (32-bit floats rounded outward); none when empty.
std::optional<Box> rtreeBox(const Envelope& e);

// One table's parts: its CREATE TABLE with the attribute `columns` (key, column name), its R-tree
// and extension row, its gpkg_contents and gpkg_geometry_columns rows, its R-tree triggers, GDAL's
// feature count row and triggers.
void createTable(SqliteDb& db, const FeatureTable& t, const std::vector<std::pair<std::string, std::string>>& columns);
void createRtree(SqliteDb& db, const FeatureTable& t);
void registerTable(SqliteDb& db, const Layer& layer, const FeatureTable& t, const Envelope& e, std::int64_t srsId,
                   double tolerance);
void createRtreeTriggers(SqliteDb& db, const FeatureTable& t);
void recordFeatureCount(SqliteDb& db, const FeatureTable& t);

}  // namespace lacet::feature_tables
