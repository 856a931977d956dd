// The scene file's schema and lacet_meta (io/scene_format.h).
#include <sqlite3.h>

#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <vector>

#include "io/dem_lod.h"
#include "io/gpkg_dem.h"
#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_format.h"
#include "model/validate.h"

namespace lacet::scene_format {
namespace {

// ---- exact text of doubles (lacet_meta) ----

// C hex float ("0x1.f4p+9", "-0x0p+0", "inf"), exact and locale-independent; a NaN as "nan:" and
// its 16 hex digits of bits, so that its payload survives too.
std::string doubleText(double v) {
    if (std::isnan(v)) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "nan:%016llx", static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(v)));
        return buf;
    }
    const std::string sign = std::signbit(v) ? "-" : "";
    if (std::isinf(v)) return sign + "inf";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, std::fabs(v), std::chars_format::hex);
    return sign + "0x" + std::string(buf, r.ptr);
}

bool parseDouble(const std::string& s, double& v) {
    const char* end = s.data() + s.size();
    if (s.starts_with("nan:")) {
        std::uint64_t bits = 0;
        const auto r = std::from_chars(s.data() + 4, end, bits, 16);
        if (s.size() != 20 || r.ec != std::errc() || r.ptr != end) return false;
        v = std::bit_cast<double>(bits);
        return std::isnan(v);
    }
    const bool negative = s.starts_with("-");
    const std::string_view body = std::string_view(s).substr(negative ? 1 : 0);
    if (body == "inf") {
        v = negative ? -HUGE_VAL : HUGE_VAL;
        return true;
    }
    if (!body.starts_with("0x") || body.size() < 3 || !std::isxdigit(static_cast<unsigned char>(body[2]))) return false;
    const auto r = std::from_chars(body.data() + 2, end, v, std::chars_format::hex);
    if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v)) return false;
    if (negative) v = -v;
    return true;
}

// ---- the tables ----

constexpr const char* kCreateTables = R"sql(
CREATE TABLE lacet_meta (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, key TEXT NOT NULL UNIQUE, value TEXT NOT NULL);
CREATE TABLE lacet_layers (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, id INTEGER NOT NULL UNIQUE, name TEXT NOT NULL,
  kind TEXT NOT NULL);
CREATE TABLE lacet_nodes (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, layer INTEGER NOT NULL, id INTEGER NOT NULL,
  x REAL, y REAL, alive BOOLEAN NOT NULL, curves BLOB NOT NULL, exact BLOB,
  roundabout REAL NOT NULL DEFAULT 0, UNIQUE (layer, id));
CREATE TABLE lacet_curves (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, layer INTEGER NOT NULL, id INTEGER NOT NULL,
  start INTEGER NOT NULL, "end" INTEGER NOT NULL, w FLOAT, wf FLOAT, cls INTEGER NOT NULL,
  flags INTEGER NOT NULL, alive BOOLEAN NOT NULL, vertices BLOB NOT NULL, areas BLOB NOT NULL, exact BLOB,
  UNIQUE (layer, id));
CREATE TABLE lacet_areas (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, layer INTEGER NOT NULL, id INTEGER NOT NULL,
  wf FLOAT, cls INTEGER NOT NULL, axial INTEGER NOT NULL, alive BOOLEAN NOT NULL, loops BLOB NOT NULL,
  exact BLOB, UNIQUE (layer, id));
CREATE TABLE lacet_attributes (
  fid INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, layer INTEGER NOT NULL, kind INTEGER NOT NULL,
  id INTEGER NOT NULL, key TEXT NOT NULL, value TEXT NOT NULL);
CREATE INDEX lacet_attributes_element ON lacet_attributes (layer, kind, id);
CREATE INDEX lacet_nodes_roundabout ON lacet_nodes (roundabout) WHERE roundabout > 0;
)sql";

struct TableInfo {
    const char* name;
    const char* description;
};
constexpr TableInfo kTables[] = {
    {"lacet_meta", "Lacet scene: format, extent, georeference, DEM grid (key/value)"},
    {"lacet_layers", "Lacet scene: layers"},
    {"lacet_nodes", "Lacet scene: nodes of the spline networks (scene CRS metres; roundabout: ring radius in m, 0 for none)"},
    {"lacet_curves", "Lacet scene: Bezier curves (vertices: little-endian f64 x, y then flag bytes)"},
    {"lacet_areas", "Lacet scene: areas (loops of curves)"},
    {"lacet_attributes", "Lacet scene: attributes kept from the source data (kind 0 node, 1 curve, 2 area)"},
};

// The parts of the streamed layer after doc's own elements of it: each validated alone, its features
// written with its local references, then its rows with its ids shifted.
void writeStreamedParts(const SceneDocument& doc, const StreamedLayer& streamed, ElementTablesWriter& elements,
                        FeatureTablesWriter& features) {
    const Layer& layer = doc.scene.layers[streamed.layer];
    std::uint64_t nodes = layer.nodes.size(), curves = layer.curves.size(), areas = layer.areas.size();
    std::size_t index = 0;
    streamed.produce([&](Layer&& part) {
        const std::string name = "part " + std::to_string(index++) + " of layer " + std::to_string(streamed.layer);
        if (nodes + part.nodes.size() > std::uint64_t(kMaxId) || curves + part.curves.size() > std::uint64_t(kMaxId) ||
            areas + part.areas.size() > std::uint64_t(kMaxId))
            throw FormatError(name + ": more than 2^32 - 1 elements of a kind in the layer");
        Scene alone;
        alone.extent = doc.scene.extent;
        alone.layers.push_back(std::move(part));
        auto problems = validate(alone);
        part = std::move(alone.layers.front());
        if (!problems.empty()) throw FormatError(name + " is invalid: " + ValidationError(std::move(problems)).what());
        const ElementOffsets o{ElementId(nodes), ElementId(curves), ElementId(areas)};
        features.add(streamed.layer, part, o);
        offsetElementIds(part, o);
        elements.elements(streamed.layer, part, o);
        nodes += part.nodes.size();
        curves += part.curves.size();
        areas += part.areas.size();
    });
}

// A border node of a scene written in parts: its id and, once every part is written, its row.
struct BorderNode {
    ElementId id = 0;
    Node node;
};
using BorderKey = std::tuple<LayerId, std::uint64_t, std::uint64_t>;

// saveSceneInParts's parts after doc's elements (io/scene_file.h): each validated alone, its
// features written with its local references, then its rows with their ids in the scene, the
// border nodes met before left out (their rows rewritten with every curve once their last part is
// written), then its attributes in its order.
void writeSceneParts(SqliteDb& db, const SceneDocument& doc, const StreamedParts& parts, ElementTablesWriter& elements,
                     FeatureTablesWriter& features) {
    const std::size_t layers = doc.scene.layers.size();
    std::vector<ElementOffsets> next(layers);
    for (std::size_t l = 0; l < layers; ++l) {
        const Layer& layer = doc.scene.layers[l];
        next[l] = {ElementId(layer.nodes.size()), ElementId(layer.curves.size()), ElementId(layer.areas.size())};
    }
    std::map<BorderKey, BorderNode> border;
    std::map<std::size_t, std::vector<BorderKey>> lastPart;  // the border nodes by the last part that can have them
    auto attribute = db.prepare("INSERT INTO lacet_attributes (layer, kind, id, key, value) VALUES (?, ?, ?, ?, ?)");
    ElementTablesWriter replace(db, true);
    // The rows of the border nodes no part after `done` can have, again with every curve.
    const auto finish = [&](std::size_t done) {
        while (!lastPart.empty() && lastPart.begin()->first <= done) {
            for (const BorderKey& key : lastPart.begin()->second) {
                const auto it = border.find(key);
                Layer one;
                one.nodes.push_back(std::move(it->second.node));
                replace.elements(std::get<0>(key), one, {it->second.id, 0, 0});
                border.erase(it);
            }
            lastPart.erase(lastPart.begin());
        }
    };
    std::optional<std::size_t> last;
    parts.produce([&](ScenePart&& part) {
        const std::string name = "part " + std::to_string(part.index);
        if (last && part.index <= *last)
            throw FormatError(name + " comes after part " + std::to_string(*last) + ": parts must come in increasing order");
        last = part.index;
        if (part.scene.layers.size() != layers)
            throw FormatError(name + " has " + std::to_string(part.scene.layers.size()) + " layers, the scene " + std::to_string(layers));
        part.scene.extent = doc.scene.extent;
        if (auto problems = validate(part.scene); !problems.empty())
            throw FormatError(name + " is invalid: " + ValidationError(std::move(problems)).what());
        std::vector<ElementOffsets> offsets(layers);
        std::vector<std::vector<ElementId>> nodeIds(layers);
        for (std::size_t l = 0; l < layers; ++l) {
            Layer& p = part.scene.layers[l];
            const ElementOffsets o = next[l];
            offsets[l] = o;
            if (std::uint64_t(o.nodes) + p.nodes.size() > std::uint64_t(kMaxId) || std::uint64_t(o.curves) + p.curves.size() > std::uint64_t(kMaxId) ||
                std::uint64_t(o.areas) + p.areas.size() > std::uint64_t(kMaxId))
                throw FormatError(name + ": more than 2^32 - 1 elements of a kind in layer " + std::to_string(l));
            features.add(LayerId(l), p, o, &part.attributes);
            std::vector<char> isBorder(p.nodes.size(), 0);
            if (l < part.borderNodes.size())
                for (ElementId n : part.borderNodes[l]) {
                    if (n >= p.nodes.size()) throw FormatError(name + ": border node " + std::to_string(n) + " of layer " + std::to_string(l) + " does not exist");
                    isBorder[n] = 1;
                }
            // Ids in the scene: border nodes met before keep theirs, the others follow the layer's.
            std::vector<ElementId>& ids = nodeIds[l];
            ids.resize(p.nodes.size());
            std::vector<BorderNode*> met(p.nodes.size(), nullptr);
            Layer rows;
            for (std::size_t n = 0; n < p.nodes.size(); ++n) {
                const BorderKey key{LayerId(l), std::bit_cast<std::uint64_t>(p.nodes[n].p.x), std::bit_cast<std::uint64_t>(p.nodes[n].p.y)};
                if (isBorder[n])
                    if (const auto it = border.find(key); it != border.end()) {
                        ids[n] = it->second.id;
                        met[n] = &it->second;
                        continue;
                    }
                ids[n] = o.nodes + ElementId(rows.nodes.size());
                rows.nodes.push_back(p.nodes[n]);
                for (ElementId& c : rows.nodes.back().curves) c += o.curves;
                if (isBorder[n]) {
                    border[key] = {ids[n], rows.nodes.back()};
                    lastPart[std::max(parts.lastPartAt(p.nodes[n].p), part.index)].push_back(key);
                }
            }
            for (std::size_t n = 0; n < p.nodes.size(); ++n)
                if (met[n])
                    for (ElementId c : p.nodes[n].curves) met[n]->node.curves.push_back(c + o.curves);
            for (Curve& c : p.curves) {
                c.start = ids[c.start];
                c.end = ids[c.end];
                for (ElementId& a : c.areas) a += o.areas;
            }
            for (Area& a : p.areas) {
                for (auto& loop : a.loops)
                    for (AreaEdge& e : loop) e.curve += o.curves;
                if (a.axial != kNoElement) a.axial += o.curves;
            }
            rows.curves = std::move(p.curves);
            rows.areas = std::move(p.areas);
            elements.elements(LayerId(l), rows, o);
            next[l] = {ElementId(o.nodes + rows.nodes.size()), ElementId(o.curves + rows.curves.size()), ElementId(o.areas + rows.areas.size())};
        }
        for (const ElementAttribute& a : part.attributes) {
            const std::size_t l = a.layer;
            const std::size_t count = l >= layers                      ? 0
                                      : a.kind == ElementKind::Area    ? next[l].areas - offsets[l].areas
                                      : a.kind == ElementKind::Curve ? next[l].curves - offsets[l].curves
                                                                       : nodeIds[l].size();
            if (a.id >= count) throw FormatError(name + ": an attribute names a missing element " + std::to_string(a.id) + " of layer " + std::to_string(l));
            attribute.bind(1, std::int64_t(a.layer));
            attribute.bind(2, std::int64_t(a.kind));
            attribute.bind(3, std::int64_t(a.kind == ElementKind::Area    ? a.id + offsets[l].areas
                                           : a.kind == ElementKind::Curve ? a.id + offsets[l].curves
                                                                          : nodeIds[l][a.id]));
            attribute.bindText(4, a.key);
            attribute.bindText(5, a.value);
            attribute.step();
            attribute.reset();
        }
        finish(part.index);
    });
    finish(std::numeric_limits<std::size_t>::max());
}

void writeMeta(SqliteDb& db, const SceneDocument& doc, const SceneChecksumParts& checksum) {
    std::vector<std::pair<std::string, std::string>> meta = {
        {"format", kFormatName},
        {"format_version", std::to_string(kSceneFormatVersion)},
        {"extent_min_x", doubleText(doc.scene.extent.min.x)},
        {"extent_min_y", doubleText(doc.scene.extent.min.y)},
        {"extent_max_x", doubleText(doc.scene.extent.max.x)},
        {"extent_max_y", doubleText(doc.scene.extent.max.y)},
        {"georeference_valid", doc.georeference.valid ? "1" : "0"},
        {"georeference_lon0", doubleText(doc.georeference.lon0)},
        {"georeference_lat0", doubleText(doc.georeference.lat0)},
        {"georeference_origin_shift_x", doubleText(doc.georeference.originShift.x)},
        {"georeference_origin_shift_y", doubleText(doc.georeference.originShift.y)},
        {"crs_wkt", doc.georeference.crsWkt},
        {"dem", doc.demLod ? kDemLodTable : doc.dem ? kDemRasterTable : "none"},
        {"checksum", checksum.text},
        {"checksum_head", SceneChecksum::hex(checksum.head)},
        {"checksum_elements", SceneChecksum::hex(checksum.elements)},
    };
    if (doc.demLod) {
        // The finest grid of the tree (its layout itself is in kDemLodMetaTable, io/dem_lod.h).
        const DemLodLayout& l = doc.demLod->layout();
        const Box e = l.extent();
        meta.insert(meta.end(), {{"dem_width", std::to_string(l.width)},
                                 {"dem_height", std::to_string(l.height)},
                                 {"dem_extent_min_x", doubleText(e.min.x)},
                                 {"dem_extent_min_y", doubleText(e.min.y)},
                                 {"dem_extent_max_x", doubleText(e.max.x)},
                                 {"dem_extent_max_y", doubleText(e.max.y)}});
    } else if (doc.dem) {
        const Box& e = doc.dem->extent();
        meta.insert(meta.end(), {{"dem_width", std::to_string(doc.dem->width())},
                                 {"dem_height", std::to_string(doc.dem->height())},
                                 {"dem_extent_min_x", doubleText(e.min.x)},
                                 {"dem_extent_min_y", doubleText(e.min.y)},
                                 {"dem_extent_max_x", doubleText(e.max.x)},
                                 {"dem_extent_max_y", doubleText(e.max.y)}});
    }
    auto s = db.prepare("INSERT INTO lacet_meta (key, value) VALUES (?, ?)");
    for (const auto& [key, value] : meta) {
        s.bindText(1, key);
        s.bindText(2, value);
        s.step();
        s.reset();
    }
}

}  // namespace

void writeSceneTables(const std::string& path, const SceneDocument& doc, const StreamedLayer* streamed, const StreamedParts* parts) {
    SqliteDb db(path, SqliteDb::Mode::ReadWrite);
    db.exec("BEGIN IMMEDIATE");
    db.exec(kCreateTables);
    {
        auto s = db.prepare(
            "INSERT INTO gpkg_contents (table_name, data_type, identifier, description, last_change) "
            "VALUES (?, 'attributes', ?, ?, strftime('%Y-%m-%dT%H:%M:%fZ', 'now'))");
        for (const TableInfo& t : kTables) {
            s.bindText(1, t.name);
            s.bindText(2, t.name);
            s.bindText(3, t.description);
            s.step();
            s.reset();
        }
    }
    // A streamed layer's checksum is known once its rows are written: a placeholder until then.
    writeMeta(db, doc, streamed || parts ? SceneChecksumParts{std::string(16, '0'), 0, 0} : sceneChecksumParts(doc));
    if (parts) {
        {
            ElementTablesWriter elements(db);
            elements.layers(doc.scene);
            FeatureTablesWriter features(db, doc, {}, parts->kinds);
            for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) {
                elements.elements(LayerId(l), doc.scene.layers[l], {});
                features.add(LayerId(l), doc.scene.layers[l], {}, &doc.attributes);
            }
            elements.attributes(doc);
            writeSceneParts(db, doc, *parts, elements, features);
            features.finish();
        }
        writeChecksum(db, checksumOfAllRows(db, doc));
    } else {
        // Their statements are finalized at the end of this block, before the connection closes.
        ElementTablesWriter elements(db);
        elements.layers(doc.scene);
        FeatureTablesWriter features(db, doc);
        for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) {
            const Layer& layer = doc.scene.layers[l];
            elements.elements(LayerId(l), layer, {});
            features.add(LayerId(l), layer, {});
            if (streamed && streamed->layer == l) writeStreamedParts(doc, *streamed, elements, features);
        }
        elements.attributes(doc);
        features.finish();
    }
    if (streamed) writeChecksum(db, checksumOfRows(db, doc, [&](LayerId l) { return l == streamed->layer; }));
    // GDAL writes GPKG 1.2 as asked; set the header anyway, it is what makes the file a GeoPackage.
    db.exec("PRAGMA application_id = 1196444487; PRAGMA user_version = 10200");
    db.exec("COMMIT");
    db.close();
}

void writeChecksum(SqliteDb& db, const SceneChecksumParts& checksum) {
    auto s = db.prepare("UPDATE lacet_meta SET value = ? WHERE key = ?");
    for (const auto& [key, value] : {std::pair<const char*, std::string>{"checksum", checksum.text},
                                     {"checksum_head", SceneChecksum::hex(checksum.head)},
                                     {"checksum_elements", SceneChecksum::hex(checksum.elements)}}) {
        s.bindText(1, value);
        s.bindText(2, key);
        s.step();
        s.reset();
        if (db.queryInteger("SELECT changes()") == 0) {  // a key a format-1 file has not
            auto i = db.prepare("INSERT INTO lacet_meta (key, value) VALUES (?, ?)");
            i.bindText(1, key);
            i.bindText(2, value);
            i.step();
        }
    }
}

SceneChecksumParts checksumOfRows(SqliteDb& db, const SceneDocument& doc, const std::function<bool(LayerId)>& fromRows) {
    SceneChecksum sum(doc.scene);
    for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) {
        if (!fromRows(LayerId(l))) {
            sum.layer(doc.scene.layers[l]);
            continue;
        }
        sum.layerHead(doc.scene.layers[l]);
        const auto counted = [&](std::size_t n) { sum.count(n); };
        forEachNodeRow(db, LayerId(l), counted, [&](const Node& n) { sum.node(n); });
        forEachCurveRow(db, LayerId(l), counted, [&](const Curve& c) { sum.curve(c); });
        forEachAreaRow(db, LayerId(l), counted, [&](const Area& a) { sum.area(a); });
    }
    return sum.finish(doc);
}

SceneChecksumParts checksumOfAllRows(SqliteDb& db, const SceneDocument& doc) {
    SceneChecksum sum(doc.scene);
    for (std::size_t l = 0; l < doc.scene.layers.size(); ++l) {
        sum.layerHead(doc.scene.layers[l]);
        const auto counted = [&](std::size_t n) { sum.count(n); };
        forEachNodeRow(db, LayerId(l), counted, [&](const Node& n) { sum.node(n); });
        forEachCurveRow(db, LayerId(l), counted, [&](const Curve& c) { sum.curve(c); });
        forEachAreaRow(db, LayerId(l), counted, [&](const Area& a) { sum.area(a); });
    }
    sum.attributeCount(std::size_t(db.queryInteger("SELECT count(*) FROM lacet_attributes")));
    auto s = db.prepare("SELECT layer, kind, id, key, value FROM lacet_attributes ORDER BY fid");
    while (s.step())
        sum.attribute({LayerId(s.integer(0)), ElementKind(s.integer(1)), ElementId(s.integer(2)), s.text(3), s.text(4)});
    return sum.finishAfterAttributes(doc);
}

namespace {

Meta readMeta(SqliteDb& db) {
    Meta meta;
    auto s = db.prepare("SELECT key, value FROM lacet_meta");
    while (s.step()) {
        if (s.type(0) != SQLITE_TEXT || s.type(1) != SQLITE_TEXT)
            throw FormatError("lacet_meta holds a non-text key or value");
        meta[s.text(0)] = s.text(1);
    }
    return meta;
}

}  // namespace

const std::string& metaValue(const Meta& meta, const std::string& key) {
    const auto it = meta.find(key);
    if (it == meta.end()) throw FormatError("lacet_meta has no '" + key + "'");
    return it->second;
}

double metaDouble(const Meta& meta, const std::string& key) {
    double v = 0.0;
    if (!parseDouble(metaValue(meta, key), v))
        throw FormatError("lacet_meta '" + key + "' = '" + metaValue(meta, key) + "' is not a hex float");
    return v;
}

std::int64_t metaInteger(const Meta& meta, const std::string& key, std::int64_t lo, std::int64_t hi) {
    const std::string& text = metaValue(meta, key);
    std::int64_t v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < lo || v > hi)
        throw FormatError("lacet_meta '" + key + "' = '" + text + "' is not an integer in [" + std::to_string(lo) + ", " +
                          std::to_string(hi) + "]");
    return v;
}

Box metaBox(const Meta& meta, const std::string& prefix) {
    return {{metaDouble(meta, prefix + "_min_x"), metaDouble(meta, prefix + "_min_y")},
            {metaDouble(meta, prefix + "_max_x"), metaDouble(meta, prefix + "_max_y")}};
}

Meta openSceneTables(SqliteDb& db, std::int64_t fileSize, bool wholeFileCheck) {
    const std::int64_t applicationId = db.queryInteger("PRAGMA application_id");
    if (applicationId != kGpkgApplicationId) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%08llx", static_cast<unsigned long long>(applicationId & 0xffffffff));
        throw FormatError(std::string("not a GeoPackage (SQLite application_id ") + hex + ", not 0x47504b47 'GPKG')");
    }
    // SQLite reads missing pages at the end of a truncated file as zeros; its header knows the size.
    const std::int64_t expectedSize = db.queryInteger("PRAGMA page_count") * db.queryInteger("PRAGMA page_size");
    if (fileSize < expectedSize)
        throw FormatError("truncated file (" + std::to_string(fileSize) + " bytes, its SQLite header says " +
                          std::to_string(expectedSize) + ")");
    // Reads every page: finds a damaged file before anything is trusted.
    if (wholeFileCheck) {
        const std::string check = db.queryText("PRAGMA quick_check(1)");
        if (check != "ok") throw FormatError("corrupt file (SQLite quick_check: " + check + ")");
    }
    if (!db.hasTable("lacet_meta")) throw FormatError("not a Lacet scene (a GeoPackage without a lacet_meta table)");
    Meta meta = readMeta(db);
    const auto format = meta.find("format");
    if (format == meta.end() || format->second != kFormatName)
        throw FormatError("not a Lacet scene (lacet_meta 'format' is not '" + std::string(kFormatName) + "')");
    const std::int64_t version = metaInteger(meta, "format_version", 1, INT32_MAX);
    if (version > kSceneFormatVersion)
        throw FormatError("written in scene format version " + std::to_string(version) + ", this program reads up to " +
                          std::to_string(kSceneFormatVersion));
    for (const TableInfo& t : kTables)
        if (!db.hasTable(t.name)) throw FormatError(std::string("not a complete Lacet scene (no ") + t.name + " table)");
    return meta;
}

}  // namespace lacet::scene_format
