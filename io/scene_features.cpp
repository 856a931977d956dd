#include "io/scene_features.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "io/dem_lod.h"
#include "io/gpkg_dem.h"
#include "io/le_bytes.h"
#include "io/scene_features_internal.h"

namespace lacet {
namespace feature_tables {

// Halvings of one Bezier piece stop here: a piece within kMaxCoordinate (model/validate.h) is flat
// within 2e9 / 4^24 < 1e-5 m after 24, so any tolerance above that is met; a smaller one is not
// worth 16 million points per piece.
constexpr int kMaxHalvings = 24;

// GDAL numbers the CRSs it cannot identify from 100000; a new row for the scene's WKT does too.
constexpr std::int64_t kFirstCustomSrsId = 100000;

constexpr const char* kRtreeDefinition = "http://www.geopackage.org/spec120/#extension_rtree";

bool isLayerOfLines(LayerKind kind) { return kind == LayerKind::Roads || kind == LayerKind::Rivers; }

// A curve is a LINESTRING feature when alive and bordering no alive area of its layer.
bool isLineFeature(const Layer& layer, const Curve& c) {
    return c.alive && std::none_of(c.areas.begin(), c.areas.end(),
                                   [&](ElementId a) { return a < layer.areas.size() && layer.areas[a].alive; });
}

bool isAsciiAlnum(char ch) { return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9'); }
bool isAsciiLetter(char ch) { return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z'); }

// Lowercase ASCII letters and digits; every run of other bytes becomes one '_'; no '_' at the ends.
std::string identifierPart(std::string_view s) {
    std::string out;
    for (char ch : s) {
        if (isAsciiAlnum(ch))
            out += (ch >= 'A' && ch <= 'Z') ? char(ch - 'A' + 'a') : ch;
        else if (!out.empty() && out.back() != '_')
            out += '_';
    }
    while (!out.empty() && out.back() == '_') out.pop_back();
    return out;
}

bool reservedTableName(const std::string& s) {
    return s == "dem" || s.starts_with("lacet_") || s.starts_with("gpkg_") || s.starts_with("rtree_") ||
           s.starts_with("sqlite_");
}

// `base`, else `base`_2, _3... : the first not in `taken`, which it joins.
std::string tableBaseName(const std::string& layerName) {
    const std::string base = identifierPart(layerName);
    if (base.empty()) return "layer";
    return !isAsciiLetter(base[0]) || reservedTableName(base) ? "layer_" + base : base;
}

std::string uniqueName(const std::string& base, std::set<std::string>& taken) {
    std::string name = base;
    for (int k = 2; taken.contains(name); ++k) name = base + "_" + std::to_string(k);
    taken.insert(name);
    return name;
}

std::string quoted(const std::string& identifier) {
    std::string out = "\"";
    for (char ch : identifier) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return out + "\"";
}

// ---- geometry ----

void flattenPiece(const BezierPiece& b, double tolerance, int depth, std::vector<Vec2>& out) {
    if (depth >= kMaxHalvings || flatness(b) <= tolerance) {
        if (out.back() != b.end()) out.push_back(b.end());
        return;
    }
    const auto [left, right] = splitHalf(b);
    flattenPiece(left, tolerance, depth + 1, out);
    flattenPiece(right, tolerance, depth + 1, out);
}

// Twice the signed area of a closed ring (first point repeated last): > 0 counter-clockwise.
double twiceSignedArea(const std::vector<Vec2>& ring) {
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < ring.size(); ++i)
        sum += (ring[i].x - ring[0].x) * (ring[i + 1].y - ring[0].y) - (ring[i + 1].x - ring[0].x) * (ring[i].y - ring[0].y);
    return sum;
}

// Exterior ring first (counter-clockwise), then the holes (clockwise), in loop order.
std::vector<std::vector<Vec2>> polygonRings(const Layer& layer, const Area& area, double tolerance) {
    std::vector<std::vector<Vec2>> rings;
    std::vector<double> areas;
    for (const auto& loop : area.loops) {
        const std::vector<Vertex> chain = loopVertices(layer, loop);
        std::vector<Vec2> ring = flattenSpline(chain, tolerance);
        if (ring.empty()) continue;  // an empty loop: validate() refuses it
        ring.back() = ring.front();  // the chain is closed; make the ring so bit for bit
        areas.push_back(twiceSignedArea(ring));
        rings.push_back(std::move(ring));
    }
    std::size_t outer = 0;
    for (std::size_t k = 1; k < rings.size(); ++k)
        if (std::abs(areas[k]) > std::abs(areas[outer])) outer = k;
    std::vector<std::vector<Vec2>> ordered;
    ordered.reserve(rings.size());
    for (std::size_t k = 0; k < rings.size(); ++k) {
        const bool wantCounterClockwise = k == outer;
        if ((areas[k] > 0.0) != wantCounterClockwise && areas[k] != 0.0) std::reverse(rings[k].begin(), rings[k].end());
        if (k == outer)
            ordered.insert(ordered.begin(), std::move(rings[k]));
        else
            ordered.push_back(std::move(rings[k]));
    }
    return ordered;
}

// GeoPackage binary geometry (GPKG 1.2 §2.1.3): "GP", version 0, flags (little-endian header, an
// [minx, maxx, miny, maxy] envelope), srs_id, the envelope, then little-endian WKB (ISO 2D).
constexpr std::uint8_t kGpFlagsLittleEndianXyEnvelope = 0x01 | (1u << 1);
constexpr std::uint32_t kWkbLineString = 2, kWkbPolygon = 3;

void gpHeader(ByteWriter& w, std::int64_t srsId, const Envelope& e) {
    w.clear();
    w.u8('G');
    w.u8('P');
    w.u8(0);
    w.u8(kGpFlagsLittleEndianXyEnvelope);
    w.u32(std::uint32_t(std::int32_t(srsId)));
    w.f64(e.minX);
    w.f64(e.maxX);
    w.f64(e.minY);
    w.f64(e.maxY);
}

void wkbPoints(ByteWriter& w, const std::vector<Vec2>& points) {
    w.u32(std::uint32_t(points.size()));
    for (Vec2 p : points) {
        w.f64(p.x);
        w.f64(p.y);
    }
}

Envelope lineStringBlob(ByteWriter& w, const std::vector<Vec2>& points, std::int64_t srsId) {
    Envelope e;
    for (Vec2 p : points) e.add(p);
    gpHeader(w, srsId, e);
    w.u8(1);  // WKB little-endian
    w.u32(kWkbLineString);
    wkbPoints(w, points);
    return e;
}

Envelope polygonBlob(ByteWriter& w, const std::vector<std::vector<Vec2>>& rings, std::int64_t srsId) {
    Envelope e;
    for (const auto& ring : rings)
        for (Vec2 p : ring) e.add(p);
    gpHeader(w, srsId, e);
    w.u8(1);
    w.u32(kWkbPolygon);
    w.u32(std::uint32_t(rings.size()));
    for (const auto& ring : rings) wkbPoints(w, ring);
    return e;
}

// ---- attributes ----

struct ElementKey {
    LayerId layer;
    ElementKind kind;
    ElementId id;
    auto operator<=>(const ElementKey&) const = default;
};

// (layer, kind, id) -> key -> first value.
using AttributeIndex = std::map<ElementKey, std::map<std::string, std::string>>;

AttributeIndex indexAttributes(const SceneDocument& doc) {
    AttributeIndex index;
    for (const ElementAttribute& a : doc.attributes) index[{a.layer, a.kind, a.id}].emplace(a.key, a.value);
    return index;
}

// Source keys of the table's elements, in key order, with their column names.
std::vector<std::pair<std::string, std::string>> attributeColumns(const FeatureTable& t, const AttributeIndex& index) {
    const ElementKind kind = t.polygons ? ElementKind::Area : ElementKind::Curve;
    std::set<std::string> keys;
    for (ElementId id : t.elements)
        if (const auto it = index.find({t.layer, kind, id}); it != index.end())
            for (const auto& entry : it->second) keys.insert(entry.first);
    std::set<std::string> taken = fixedColumnNames();
    std::vector<std::pair<std::string, std::string>> columns;
    for (const std::string& key : keys) columns.emplace_back(key, uniqueName(attributeColumnBase(key, taken), taken));
    return columns;
}

std::set<std::string> fixedColumnNames() { return {"fid", kGeometryColumn, "lacet_id", "class", "w", "wf", "bridge", "tunnel"}; }

std::string attributeColumnBase(const std::string& key, const std::set<std::string>& taken) {
    const std::string name = identifierPart(key);
    if (name.empty()) return "attr";
    return !isAsciiLetter(name[0]) || taken.contains(name) ? "attr_" + name : name;
}

// ---- one table ----

void createTable(SqliteDb& db, const FeatureTable& t, const std::vector<std::pair<std::string, std::string>>& columns) {
    std::string sql = "CREATE TABLE " + quoted(t.name) + " (fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, " +
                      kGeometryColumn + (t.polygons ? " POLYGON" : " LINESTRING") +
                      ", lacet_id INTEGER NOT NULL, class INTEGER NOT NULL";
    sql += t.polygons ? ", wf REAL NOT NULL" : ", w REAL NOT NULL, wf REAL NOT NULL, bridge BOOLEAN NOT NULL, tunnel BOOLEAN NOT NULL";
    for (const auto& column : columns) sql += ", " + quoted(column.second) + " TEXT";
    db.exec(sql + ")");
}

std::string description(const Layer& layer, const FeatureTable& t, double tolerance) {
    char tol[32];
    std::snprintf(tol, sizeof tol, "%g", tolerance);
    return "Lacet " + std::string(toString(layer.kind)) + " layer '" + layer.name + "': " +
           (t.polygons ? "areas" : "curves") + " sampled within " + tol +
           " m of their Bezier splines (derived; the truth is in lacet_curves and lacet_areas)";
}

void registerTable(SqliteDb& db, const Layer& layer, const FeatureTable& t, const Envelope& e, std::int64_t srsId,
                   double tolerance) {
    auto s = db.prepare(
        "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change, min_x, min_y, max_x, "
        "max_y, srs_id) VALUES (?, 'features', ?, ?, strftime('%Y-%m-%dT%H:%M:%fZ', 'now'), ?, ?, ?, ?, ?)");
    s.bindText(1, t.name);
    s.bindText(2, t.name);
    s.bindText(3, description(layer, t, tolerance));
    if (!e.empty()) {
        s.bind(4, e.minX);
        s.bind(5, e.minY);
        s.bind(6, e.maxX);
        s.bind(7, e.maxY);
    }
    s.bind(8, srsId);
    s.step();
    auto g = db.prepare(
        "INSERT INTO gpkg_geometry_columns (table_name, column_name, geometry_type_name, srs_id, z, m) "
        "VALUES (?, ?, ?, ?, 0, 0)");
    g.bindText(1, t.name);
    g.bindText(2, kGeometryColumn);
    g.bindText(3, t.polygons ? "POLYGON" : "LINESTRING");
    g.bind(4, srsId);
    g.step();
}

// The R-tree and its extension row; the triggers come after the features, which fill it directly.
void createRtree(SqliteDb& db, const FeatureTable& t) {
    db.exec("CREATE VIRTUAL TABLE " + quoted(featureRtreeName(t.name)) +
            " USING rtree(id, minx, maxx, miny, maxy)");
    auto s = db.prepare(
        "INSERT INTO gpkg_extensions (table_name, column_name, extension_name, definition, scope) "
        "VALUES (?, ?, 'gpkg_rtree_index', ?, 'write-only')");
    s.bindText(1, t.name);
    s.bindText(2, kGeometryColumn);
    s.bindText(3, kRtreeDefinition);
    s.step();
}

// The triggers of GeoPackage 1.2 Annex F.3 (as GDAL writes them), which keep the index right when a
// GIS tool edits the table.
void createRtreeTriggers(SqliteDb& db, const FeatureTable& t) {
    const std::string table = quoted(t.name), c = std::string("\"") + kGeometryColumn + "\"",
                      rtree = quoted(featureRtreeName(t.name)),
                      prefix = featureRtreeName(t.name);
    const std::string insertRow = "INSERT OR REPLACE INTO " + rtree + " VALUES (NEW.\"fid\", ST_MinX(NEW." + c +
                                  "), ST_MaxX(NEW." + c + "), ST_MinY(NEW." + c + "), ST_MaxY(NEW." + c + "));";
    const std::string nonEmpty = "(NEW." + c + " NOTNULL AND NOT ST_IsEmpty(NEW." + c + "))";
    const std::string empty = "(NEW." + c + " ISNULL OR ST_IsEmpty(NEW." + c + "))";
    db.exec("CREATE TRIGGER " + quoted(prefix + "_insert") + " AFTER INSERT ON " + table + " WHEN " + nonEmpty +
            " BEGIN " + insertRow + " END");
    db.exec("CREATE TRIGGER " + quoted(prefix + "_update1") + " AFTER UPDATE OF " + c + " ON " + table +
            " WHEN OLD.\"fid\" = NEW.\"fid\" AND " + nonEmpty + " BEGIN " + insertRow + " END");
    db.exec("CREATE TRIGGER " + quoted(prefix + "_update2") + " AFTER UPDATE OF " + c + " ON " + table +
            " WHEN OLD.\"fid\" = NEW.\"fid\" AND " + empty + " BEGIN DELETE FROM " + rtree +
            " WHERE id = OLD.\"fid\"; END");
    db.exec("CREATE TRIGGER " + quoted(prefix + "_update3") + " AFTER UPDATE ON " + table +
            " WHEN OLD.\"fid\" != NEW.\"fid\" AND " + nonEmpty + " BEGIN DELETE FROM " + rtree +
            " WHERE id = OLD.\"fid\"; " + insertRow + " END");
    db.exec("CREATE TRIGGER " + quoted(prefix + "_update4") + " AFTER UPDATE ON " + table +
            " WHEN OLD.\"fid\" != NEW.\"fid\" AND " + empty + " BEGIN DELETE FROM " + rtree +
            " WHERE id IN (OLD.\"fid\", NEW.\"fid\"); END");
    db.exec("CREATE TRIGGER " + quoted(prefix + "_delete") + " AFTER DELETE ON " + table + " WHEN OLD." + c +
            " NOT NULL BEGIN DELETE FROM " + rtree + " WHERE id = OLD.\"fid\"; END");
}

// GDAL's cached feature count (gpkg_ogr_contents) and the triggers that keep it, as GDAL writes them.
void recordFeatureCount(SqliteDb& db, const FeatureTable& t) {
    auto s = db.prepare("INSERT INTO gpkg_ogr_contents (table_name, feature_count) VALUES (?, ?)");
    s.bindText(1, t.name);
    s.bind(2, std::int64_t(t.elements.size()));
    s.step();
    std::string literal = "'";
    for (char ch : t.name) literal += ch == '\'' ? std::string("''") : std::string(1, ch);
    literal += "'";
    db.exec("CREATE TRIGGER " + quoted("trigger_insert_feature_count_" + t.name) + " AFTER INSERT ON " +
            quoted(t.name) + " BEGIN UPDATE gpkg_ogr_contents SET feature_count = feature_count + 1 WHERE "
            "lower(table_name) = lower(" + literal + "); END");
    db.exec("CREATE TRIGGER " + quoted("trigger_delete_feature_count_" + t.name) + " AFTER DELETE ON " +
            quoted(t.name) + " BEGIN UPDATE gpkg_ogr_contents SET feature_count = feature_count - 1 WHERE "
            "lower(table_name) = lower(" + literal + "); END");
}

constexpr const char* kCreateGpkgVectorTables = R"sql(
CREATE TABLE IF NOT EXISTS gpkg_geometry_columns (
  table_name TEXT NOT NULL, column_name TEXT NOT NULL, geometry_type_name TEXT NOT NULL,
  srs_id INTEGER NOT NULL, z TINYINT NOT NULL, m TINYINT NOT NULL,
  CONSTRAINT pk_geom_cols PRIMARY KEY (table_name, column_name),
  CONSTRAINT uk_gc_table_name UNIQUE (table_name),
  CONSTRAINT fk_gc_tn FOREIGN KEY (table_name) REFERENCES gpkg_contents(table_name),
  CONSTRAINT fk_gc_srs FOREIGN KEY (srs_id) REFERENCES gpkg_spatial_ref_sys (srs_id));
CREATE TABLE IF NOT EXISTS gpkg_extensions (
  table_name TEXT, column_name TEXT, extension_name TEXT NOT NULL, definition TEXT NOT NULL,
  scope TEXT NOT NULL, CONSTRAINT ge_tce UNIQUE (table_name, column_name, extension_name));
)sql";

}  // namespace feature_tables

using namespace feature_tables;

// ---- the SRS ----

std::int64_t featureSrsId(SqliteDb& db, const SceneDocument& doc) {
    if (!doc.georeference.valid || doc.georeference.crsWkt.empty()) return kUndefinedCartesianSrsId;
    // The DEM's row: GDAL's for the raster (which it leaves at -1 or 0, undefined, when it could
    // not read the WKT), saveScene's for a streamed DEM's tree (made here before its copy).
    for (const char* table : {doc.dem ? kDemRasterTable : nullptr, doc.demLod ? kDemLodTable : nullptr}) {
        if (!table) continue;
        auto s = db.prepare("SELECT srs_id FROM gpkg_contents WHERE table_name = ?");
        s.bindText(1, table);
        if (s.step() && s.type(0) == SQLITE_INTEGER && s.integer(0) > 0) return s.integer(0);
    }
    const std::int64_t srsId =
        std::max(kFirstCustomSrsId, db.queryInteger("SELECT coalesce(max(srs_id), 0) + 1 FROM gpkg_spatial_ref_sys"));
    auto s = db.prepare(
        "INSERT INTO gpkg_spatial_ref_sys (srs_name, srs_id, organization, organization_coordsys_id, definition, "
        "description) VALUES ('Lacet scene CRS', ?, 'NONE', ?, ?, 'Transverse Mercator of the scene (io/georeference.h)')");
    s.bind(1, srsId);
    s.bind(2, srsId);
    s.bindText(3, doc.georeference.crsWkt);
    s.step();
    return srsId;
}

std::vector<Vec2> flattenSpline(std::span<const Vertex> vertices, double tolerance) {
    if (!(tolerance > 0.0)) throw std::invalid_argument("flattenSpline: tolerance must be > 0 m");
    std::vector<Vec2> out;
    if (vertices.empty()) return out;
    out.push_back(vertices.front().p);
    forEachPiece(vertices, [&](const BezierPiece& b, std::size_t) { flattenPiece(b, tolerance, 0, out); });
    if (out.size() == 1) out.push_back(out.front());
    return out;
}

namespace feature_tables {

// SQLite's R-tree keeps 32-bit floats, the lower bound rounded down and the upper bound up, as
// its rtreeValueDown and rtreeValueUp do (a factor of 1 -/+ 2^-23 where the cast rounded the
// wrong way).
constexpr double kRoundTowards = 1.0 - 1.0 / 8388608.0, kRoundAway = 1.0 + 1.0 / 8388608.0;
double floatDown(double v) {
    float f = float(v);
    if (double(f) > v) f = float(v * (v < 0.0 ? kRoundAway : kRoundTowards));
    return f;
}
double floatUp(double v) {
    float f = float(v);
    if (double(f) < v) f = float(v * (v < 0.0 ? kRoundTowards : kRoundAway));
    return f;
}
std::optional<Box> rtreeBox(const Envelope& e) {
    if (e.empty()) return std::nullopt;
    return Box{{floatDown(e.minX), floatDown(e.minY)}, {floatUp(e.maxX), floatUp(e.maxY)}};
}

}  // namespace feature_tables

std::optional<Box> featureBox(const Layer& layer, const Curve& c, double tolerance) {
    if (!isLineFeature(layer, c)) return std::nullopt;
    Envelope e;
    for (Vec2 p : flattenSpline(c.vertices, tolerance)) e.add(p);
    return rtreeBox(e);
}

std::optional<Box> featureBox(const Layer& layer, const Area& a, double tolerance) {
    if (!a.alive) return std::nullopt;
    Envelope e;
    for (const auto& ring : polygonRings(layer, a, tolerance))
        for (Vec2 p : ring) e.add(p);
    return rtreeBox(e);
}

std::vector<FeatureTable> planFeatureTables(const SceneDocument& doc, const std::vector<std::string>& takenNames) {
    std::set<std::string> taken(takenNames.begin(), takenNames.end());
    std::vector<FeatureTable> tables;
    for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) {
        const Layer& layer = doc.scene.layers[l];
        FeatureTable lines{.name = {}, .layer = LayerId(l), .polygons = false, .elements = {}};
        FeatureTable areas{.name = {}, .layer = LayerId(l), .polygons = true, .elements = {}};
        for (std::size_t id = 0; id < layer.areas.size(); ++id)
            if (layer.areas[id].alive) areas.elements.push_back(ElementId(id));
        for (std::size_t id = 0; id < layer.curves.size(); ++id) {
            if (isLineFeature(layer, layer.curves[id])) lines.elements.push_back(ElementId(id));
        }
        const std::string base = tableBaseName(layer.name);
        const bool linesFirst = isLayerOfLines(layer.kind);
        FeatureTable& first = linesFirst ? lines : areas;
        FeatureTable& second = linesFirst ? areas : lines;
        first.name = uniqueName(base, taken);
        tables.push_back(std::move(first));
        if (!second.elements.empty()) {
            second.name = uniqueName(base + (linesFirst ? "_areas" : "_lines"), taken);
            tables.push_back(std::move(second));
        }
    }
    return tables;
}

// ---- the writer ----

// One table being written: its statements, next fid, and what its row of gpkg_contents and of the
// feature index say once every feature is in.
struct FeatureTablesWriter::Table {
    FeatureTable plan;
    std::vector<std::pair<std::string, std::string>> columns;
    std::unique_ptr<SqliteStatement> insert, rtree;
    std::int64_t fid = 0;  // the table is new: AUTOINCREMENT gives 1, 2, 3...
    Envelope envelope;
    double curveWf = 0.0, areaWf = 0.0;  // the largest wf of its curves (a polygon table's: of its areas' curves), of its areas
};

struct FeatureTablesWriter::State {
    AttributeIndex attributes;
    std::vector<std::unique_ptr<Table>> tables;
    std::int64_t srsId = kUndefinedCartesianSrsId;
    bool gdalCounts = false;
};

namespace {

// planFeatureTables of a scene known by the kinds of its layers' features (FeatureKindsPlan): the
// same names and order, the second table of a layer where it will have features.
std::vector<FeatureTable> planFeatureTablesOfKinds(const Scene& scene, const std::vector<FeatureKindsPlan>& kinds,
                                                   const std::vector<std::string>& takenNames) {
    std::set<std::string> taken(takenNames.begin(), takenNames.end());
    std::vector<FeatureTable> tables;
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        const Layer& layer = scene.layers[l];
        const bool linesFirst = isLayerOfLines(layer.kind);
        const std::string base = tableBaseName(layer.name);
        tables.push_back({.name = uniqueName(base, taken), .layer = LayerId(l), .polygons = !linesFirst, .elements = {}});
        const bool second = l < kinds.size() && (linesFirst ? kinds[l].areas : kinds[l].lines);
        if (second)
            tables.push_back({.name = uniqueName(base + (linesFirst ? "_areas" : "_lines"), taken), .layer = LayerId(l), .polygons = linesFirst,
                              .elements = {}});
    }
    return tables;
}

std::vector<std::pair<std::string, std::string>> attributeColumnsOfKeys(const std::set<std::string>& keys) {
    std::set<std::string> taken = fixedColumnNames();
    std::vector<std::pair<std::string, std::string>> columns;
    for (const std::string& key : keys) columns.emplace_back(key, uniqueName(attributeColumnBase(key, taken), taken));
    return columns;
}

}  // namespace

FeatureTablesWriter::FeatureTablesWriter(SqliteDb& db, const SceneDocument& head, const FeatureTableParams& params,
                                         const std::vector<FeatureKindsPlan>* kinds)
    : db_(db), head_(head), params_(params), state_(std::make_unique<State>()) {
    if (!(params.tolerance > 0.0)) throw std::invalid_argument("writeFeatureTables: tolerance must be > 0 m");
    db.exec(kCreateGpkgVectorTables);
    std::vector<std::string> taken;
    {
        auto s = db.prepare("SELECT lower(name) FROM sqlite_master");
        while (s.step()) taken.push_back(s.text(0));
    }
    state_->gdalCounts = db.hasTable("gpkg_ogr_contents");
    state_->srsId = featureSrsId(db, head);
    state_->attributes = indexAttributes(head);
    for (FeatureTable& t : kinds ? planFeatureTablesOfKinds(head.scene, *kinds, taken) : planFeatureTables(head, taken)) {
        auto table = std::make_unique<Table>();
        if (kinds) {
            const FeatureKindsPlan* k = t.layer < kinds->size() ? &(*kinds)[t.layer] : nullptr;
            table->columns = k ? attributeColumnsOfKeys(t.polygons ? k->areaKeys : k->lineKeys) : decltype(table->columns){};
        } else {
            table->columns = attributeColumns(t, state_->attributes);
        }
        t.elements.clear();  // refilled by add(), in fid order
        table->plan = std::move(t);
        const FeatureTable& p = table->plan;
        createTable(db, p, table->columns);
        createRtree(db, p);
        const int fixed = p.polygons ? 4 : 7;  // geom, lacet_id, class, wf (w, wf, bridge, tunnel)
        std::string sql = "INSERT INTO " + quoted(p.name) + " (" + kGeometryColumn + ", lacet_id, class" +
                          (p.polygons ? ", wf" : ", w, wf, bridge, tunnel");
        for (const auto& column : table->columns) sql += ", " + quoted(column.second);
        sql += ") VALUES (?";
        for (std::size_t k = 1; k < std::size_t(fixed) + table->columns.size(); ++k) sql += ", ?";
        table->insert = db.prepareKept(sql + ")");
        table->rtree = db.prepareKept("INSERT INTO " + quoted(featureRtreeName(p.name)) + " VALUES (?, ?, ?, ?, ?)");
        state_->tables.push_back(std::move(table));
    }
}

FeatureTablesWriter::~FeatureTablesWriter() = default;

void FeatureTablesWriter::add(LayerId layerId, const Layer& part, const ElementOffsets& o,
                              const std::vector<ElementAttribute>* partAttributes) {
    if (layerId >= head_.scene.layers.size())
        throw std::invalid_argument("writeFeatureTables: layer " + std::to_string(layerId) + " does not exist");
    Table* lines = nullptr;
    Table* polygons = nullptr;
    for (const auto& t : state_->tables)
        if (t->plan.layer == layerId) (t->plan.polygons ? polygons : lines) = t.get();
    const double tolerance = params_.tolerance;
    // The part's own attributes, at the ids its elements are written with.
    AttributeIndex own;
    if (partAttributes)
        for (const ElementAttribute& a : *partAttributes)
            if (a.layer == layerId)
                own[{a.layer, a.kind, a.id + (a.kind == ElementKind::Area ? o.areas : a.kind == ElementKind::Curve ? o.curves : o.nodes)}]
                    .emplace(a.key, a.value);
    const AttributeIndex& attributes = partAttributes ? own : state_->attributes;
    ByteWriter blob;
    // One feature: its geometry in `blob`, its fixed columns bound by the caller.
    const auto finishRow = [&](Table& t, ElementId id, const Envelope& e) {
        SqliteStatement& s = *t.insert;
        const int fixed = t.plan.polygons ? 4 : 7;
        const ElementKind kind = t.plan.polygons ? ElementKind::Area : ElementKind::Curve;
        if (const auto it = attributes.find({layerId, kind, id}); it != attributes.end())
            for (std::size_t k = 0; k < t.columns.size(); ++k)
                if (const auto value = it->second.find(t.columns[k].first); value != it->second.end())
                    s.bindText(fixed + 1 + int(k), value->second);
        s.step();
        s.reset();
        SqliteStatement& r = *t.rtree;
        r.bind(1, ++t.fid);
        r.bind(2, e.minX);
        r.bind(3, e.maxX);
        r.bind(4, e.minY);
        r.bind(5, e.maxY);
        r.step();
        r.reset();
        t.envelope.add(e);
        t.plan.elements.push_back(id);
    };
    const auto missing = [&](const char* what) {
        return std::invalid_argument("writeFeatureTables: layer " + std::to_string(layerId) + " ('" +
                                     head_.scene.layers[layerId].name + "') gets " + what +
                                     " but its feature tables were planned without them");
    };
    for (std::size_t local = 0; local < part.areas.size(); ++local) {
        const Area& a = part.areas[local];
        if (!a.alive) continue;
        if (!polygons) throw missing("areas");
        const Envelope e = polygonBlob(blob, polygonRings(part, a, tolerance), state_->srsId);
        SqliteStatement& s = *polygons->insert;
        const ElementId id = ElementId(local) + o.areas;
        s.bindBlob(1, blob.bytes());
        s.bind(2, std::int64_t(id));
        s.bind(3, std::int64_t(a.cls));
        s.bind(4, double(a.wf));
        polygons->areaWf = std::max(polygons->areaWf, double(a.wf));
        for (const auto& loop : a.loops)
            for (const AreaEdge& edge : loop) polygons->curveWf = std::max(polygons->curveWf, double(part.curves[edge.curve].wf));
        if (a.axial != kNoElement) polygons->curveWf = std::max(polygons->curveWf, double(part.curves[a.axial].wf));
        finishRow(*polygons, id, e);
    }
    for (std::size_t local = 0; local < part.curves.size(); ++local) {
        const Curve& c = part.curves[local];
        if (!isLineFeature(part, c)) continue;
        if (!lines) throw missing("curves outside areas");
        const Envelope e = lineStringBlob(blob, flattenSpline(c.vertices, tolerance), state_->srsId);
        SqliteStatement& s = *lines->insert;
        const ElementId id = ElementId(local) + o.curves;
        s.bindBlob(1, blob.bytes());
        s.bind(2, std::int64_t(id));
        s.bind(3, std::int64_t(c.cls));
        s.bind(4, double(c.w));
        s.bind(5, double(c.wf));
        s.bind(6, std::int64_t((c.flags & kBridge) != 0));
        s.bind(7, std::int64_t((c.flags & kTunnel) != 0));
        lines->curveWf = std::max(lines->curveWf, double(c.wf));
        finishRow(*lines, id, e);
    }
}

std::vector<FeatureTable> FeatureTablesWriter::finish() {
    SqliteDb& db = db_;
    std::vector<FeatureTable> written;
    for (const auto& table : state_->tables) {
        const FeatureTable& t = table->plan;
        table->insert.reset();
        table->rtree.reset();
        registerTable(db, head_.scene.layers[t.layer], t, table->envelope, state_->srsId, params_.tolerance);
        createRtreeTriggers(db, t);
        if (state_->gdalCounts) recordFeatureCount(db, t);
    }
    // kFeatureIndexTable: which table holds which layer's curves or areas, for loadSceneRegion.
    db.exec(std::string("CREATE TABLE ") + kFeatureIndexTable +
            " (table_name TEXT PRIMARY KEY NOT NULL, layer INTEGER NOT NULL, polygons BOOLEAN NOT NULL, tolerance REAL NOT "
            "NULL, max_curve_wf REAL NOT NULL, max_area_wf REAL NOT NULL)");
    db.exec(std::string("INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) VALUES ('") +
            kFeatureIndexTable + "', 'attributes', '" + kFeatureIndexTable +
            "', 'Lacet scene: the layer of each feature table (derived)', strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))");
    auto s = db.prepare(std::string("INSERT INTO ") + kFeatureIndexTable + " VALUES (?, ?, ?, ?, ?, ?)");
    for (const auto& table : state_->tables) {
        const FeatureTable& t = table->plan;
        s.bindText(1, t.name);
        s.bind(2, std::int64_t(t.layer));
        s.bind(3, std::int64_t(t.polygons));
        s.bind(4, params_.tolerance);
        s.bind(5, table->curveWf);
        s.bind(6, table->areaWf);
        s.step();
        s.reset();
        written.push_back(std::move(table->plan));
    }
    state_->tables.clear();
    return written;
}

std::vector<FeatureTable> writeFeatureTables(SqliteDb& db, const SceneDocument& doc, const FeatureTableParams& params) {
    FeatureTablesWriter writer(db, doc, params);
    for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) writer.add(LayerId(l), doc.scene.layers[l], {});
    return writer.finish();
}

}  // namespace lacet
