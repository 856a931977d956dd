// The element tables of the scene file (io/scene_format.h).
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <span>
#include <sstream>
#include <vector>

#include "io/le_bytes.h"
#include "io/scene_format.h"

namespace lacet::scene_format {
namespace {

constexpr std::uint8_t kOnCurveBit = 1u, kClosingBit = 2u;

// ---- writing ----

// True when SQLite cannot keep `v` in a REAL column: it stores -0.0 as the integer 0 and a NaN as NULL.
bool realLoses(double v) { return std::isnan(v) || (v == 0.0 && std::signbit(v)); }

void bindReal(SqliteStatement& s, int i, double v) {
    if (std::isnan(v))
        s.bindNull(i);
    else
        s.bind(i, v);
}

std::span<const std::uint8_t> idList(ByteWriter& w, const std::vector<ElementId>& ids) {
    w.clear();
    for (ElementId id : ids) w.u32(id);
    return w.bytes();
}

void writeLayers(SqliteDb& db, const Scene& scene) {
    auto s = db.prepare("INSERT INTO lacet_layers (id, name, kind) VALUES (?, ?, ?)");
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        s.bind(1, std::int64_t(l));
        s.bindText(2, scene.layers[l].name);
        s.bindText(3, toString(scene.layers[l].kind));
        s.step();
        s.reset();
    }
}

constexpr const char* kInsertNode =
    "INSERT INTO lacet_nodes (layer, id, x, y, alive, curves, exact, roundabout) VALUES (?, ?, ?, ?, ?, ?, ?, ?)";

// The rows of `part`'s nodes, ids from `first`.
void writeNodes(SqliteStatement& s, std::size_t l, const Layer& part, std::int64_t first) {
    ByteWriter list, exact;
    {
        const auto& nodes = part.nodes;
        for (std::size_t local = 0; local < nodes.size(); ++local) {
            const Node& n = nodes[local];
            const std::int64_t id = first + std::int64_t(local);
            s.bind(1, std::int64_t(l));
            s.bind(2, id);
            bindReal(s, 3, n.p.x);
            bindReal(s, 4, n.p.y);
            s.bind(5, std::int64_t(n.alive));
            s.bindBlob(6, idList(list, n.curves));
            if (realLoses(n.p.x) || realLoses(n.p.y)) {
                exact.clear();
                exact.f64(n.p.x);
                exact.f64(n.p.y);
                s.bindBlob(7, exact.bytes());
            }
            // A radius is a finite float >= 0 (model/roundabouts.h); -0 is kept as 0.
            if (!std::isfinite(n.roundabout) || n.roundabout < 0.0f) {
                std::ostringstream what;
                what << "layer " << l << " node " << id << ": roundabout radius " << n.roundabout
                     << " is not a finite number >= 0";
                throw FormatError(what.str());
            }
            s.bind(8, n.roundabout == 0.0f ? 0.0 : double(n.roundabout));
            s.step();
            s.reset();
        }
    }
}

constexpr const char* kInsertCurve =
    "INSERT INTO lacet_curves (layer, id, start, \"end\", w, wf, cls, flags, alive, vertices, areas, exact) "
    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";

// The rows of `part`'s curves, ids from `first`.
void writeCurves(SqliteStatement& s, std::size_t l, const Layer& part, std::int64_t first) {
    ByteWriter vertices, list, exact;
    {
        const auto& curves = part.curves;
        for (std::size_t local = 0; local < curves.size(); ++local) {
            const Curve& c = curves[local];
            s.bind(1, std::int64_t(l));
            s.bind(2, first + std::int64_t(local));
            s.bind(3, std::int64_t(c.start));
            s.bind(4, std::int64_t(c.end));
            bindReal(s, 5, double(c.w));
            bindReal(s, 6, double(c.wf));
            s.bind(7, std::int64_t(c.cls));
            s.bind(8, std::int64_t(c.flags));
            s.bind(9, std::int64_t(c.alive));
            vertices.clear();
            for (const Vertex& v : c.vertices) {
                vertices.f64(v.p.x);
                vertices.f64(v.p.y);
            }
            for (const Vertex& v : c.vertices)
                vertices.u8(std::uint8_t((v.onCurve ? kOnCurveBit : 0u) | (v.closing ? kClosingBit : 0u)));
            s.bindBlob(10, vertices.bytes());
            s.bindBlob(11, idList(list, c.areas));
            if (realLoses(double(c.w)) || realLoses(double(c.wf))) {
                exact.clear();
                exact.f32(c.w);
                exact.f32(c.wf);
                s.bindBlob(12, exact.bytes());
            }
            s.step();
            s.reset();
        }
    }
}

constexpr const char* kInsertArea =
    "INSERT INTO lacet_areas (layer, id, wf, cls, axial, alive, loops, exact) VALUES (?, ?, ?, ?, ?, ?, ?, ?)";

// The rows of `part`'s areas, ids from `first`.
void writeAreas(SqliteStatement& s, std::size_t l, const Layer& part, std::int64_t first) {
    ByteWriter loops, exact;
    {
        const auto& areas = part.areas;
        for (std::size_t local = 0; local < areas.size(); ++local) {
            const Area& a = areas[local];
            s.bind(1, std::int64_t(l));
            s.bind(2, first + std::int64_t(local));
            bindReal(s, 3, double(a.wf));
            s.bind(4, std::int64_t(a.cls));
            s.bind(5, std::int64_t(a.axial));
            s.bind(6, std::int64_t(a.alive));
            loops.clear();
            loops.u32(std::uint32_t(a.loops.size()));
            for (const auto& loop : a.loops) {
                loops.u32(std::uint32_t(loop.size()));
                for (const AreaEdge& e : loop) {
                    loops.u32(e.curve);
                    loops.u8(e.reversed ? 1 : 0);
                }
            }
            s.bindBlob(7, loops.bytes());
            if (realLoses(double(a.wf))) {
                exact.clear();
                exact.f32(a.wf);
                s.bindBlob(8, exact.bytes());
            }
            s.step();
            s.reset();
        }
    }
}

void writeAttributes(SqliteDb& db, const SceneDocument& doc) {
    auto s = db.prepare("INSERT INTO lacet_attributes (layer, kind, id, key, value) VALUES (?, ?, ?, ?, ?)");
    for (const ElementAttribute& a : doc.attributes) {
        s.bind(1, std::int64_t(a.layer));
        s.bind(2, std::int64_t(a.kind));
        s.bind(3, std::int64_t(a.id));
        s.bindText(4, a.key);
        s.bindText(5, a.value);
        s.step();
        s.reset();
    }
}

// ---- reading ----

// The row being read, named in messages (built only when there is a problem).
struct Row {
    const char* table;
    std::int64_t layer = -1, id = -1;
    [[noreturn]] void fail(const std::string& what) const {
        std::string where = std::string(table) + " row";
        if (layer >= 0) where += " (layer " + std::to_string(layer) + (id >= 0 ? ", id " + std::to_string(id) : "") + ")";
        throw FormatError(where + ": " + what);
    }
};

std::int64_t integerColumn(const SqliteStatement& s, int col, std::int64_t lo, std::int64_t hi, const char* name,
                           const Row& row) {
    if (s.type(col) != SQLITE_INTEGER) row.fail(std::string(name) + " is not an integer");
    const std::int64_t v = s.integer(col);
    if (v < lo || v > hi) row.fail(std::string(name) + " = " + std::to_string(v) + " is out of range");
    return v;
}

bool boolColumn(const SqliteStatement& s, int col, const char* name, const Row& row) {
    return integerColumn(s, col, 0, 1, name, row) != 0;
}

double realColumn(const SqliteStatement& s, int col, const char* name, const Row& row) {
    const int t = s.type(col);
    if (t != SQLITE_FLOAT && t != SQLITE_INTEGER) row.fail(std::string(name) + " is not a number");
    return s.real(col);
}

float floatColumn(const SqliteStatement& s, int col, const char* name, const Row& row) {
    const double d = realColumn(s, col, name, row);
    const auto f = static_cast<float>(d);
    if (double(f) != d) row.fail(std::string(name) + " is not a 32-bit float");
    return f;
}

std::span<const std::uint8_t> blobColumn(const SqliteStatement& s, int col, const char* name, const Row& row) {
    if (s.type(col) != SQLITE_BLOB) row.fail(std::string(name) + " is not a blob");
    return s.blob(col);
}

// The `exact` column: empty when NULL, else a blob of exactly `size` bytes.
std::span<const std::uint8_t> exactColumn(const SqliteStatement& s, int col, std::size_t size, const Row& row) {
    if (s.type(col) == SQLITE_NULL) return {};
    const auto b = blobColumn(s, col, "exact", row);
    if (b.size() != size)
        row.fail("exact blob of " + std::to_string(b.size()) + " bytes, expected " + std::to_string(size));
    return b;
}

std::vector<ElementId> idListColumn(const SqliteStatement& s, int col, const char* name, const Row& row) {
    const auto b = blobColumn(s, col, name, row);
    if (b.size() % 4 != 0)
        row.fail(std::string(name) + " blob of " + std::to_string(b.size()) + " bytes, not a multiple of 4");
    std::vector<ElementId> ids(b.size() / 4);
    ByteReader r(b);
    for (auto& id : ids) r.u32(id);
    return ids;
}

// Reads the layer and id columns (0 and 1) of a row of an element table; checks that ids run
// 0, 1, 2... in each layer (rows come ordered by layer, id).
template <class Element>
Layer& rowLayer(const SqliteStatement& s, std::vector<Layer>& layers, std::vector<Element> Layer::*elements,
                Row& row) {
    row.layer = integerColumn(s, 0, 0, std::int64_t(layers.size()) - 1, "layer", row);
    row.id = integerColumn(s, 1, 0, kMaxId, "id", row);
    Layer& layer = layers[std::size_t(row.layer)];
    const std::size_t expected = (layer.*elements).size();
    if (std::size_t(row.id) != expected)
        row.fail("ids are not 0, 1, 2... in their layer (id " + std::to_string(expected) + " expected)");
    return layer;
}

void readLayers(SqliteDb& db, Scene& scene) {
    auto s = db.prepare("SELECT id, name, kind FROM lacet_layers ORDER BY id");
    while (s.step()) {
        Row row{"lacet_layers"};
        const std::int64_t id = integerColumn(s, 0, 0, std::int64_t(kMaxLayers) - 1, "id", row);
        row.layer = id;
        if (std::size_t(id) != scene.layers.size())
            row.fail("layer ids are not 0, 1, 2... (id " + std::to_string(scene.layers.size()) + " expected)");
        if (s.type(1) != SQLITE_TEXT || s.type(2) != SQLITE_TEXT) row.fail("name or kind is not text");
        Layer layer;
        layer.name = s.text(1);
        const std::string kind = s.text(2);
        bool known = false;
        for (int k = 0; k <= int(LayerKind::Other) && !known; ++k)
            if (toString(LayerKind(k)) == kind) {
                layer.kind = LayerKind(k);
                known = true;
            }
        if (!known) row.fail("unknown layer kind '" + kind + "'");
        scene.layers.push_back(std::move(layer));
    }
}

// Columns: layer, id, x, y, alive, curves, exact, roundabout.
Node decodeNode(const SqliteStatement& s, const Row& row) {
    Node n;
    if (const auto exact = exactColumn(s, 6, 16, row); !exact.empty()) {
        ByteReader r(exact);
        r.f64(n.p.x);
        r.f64(n.p.y);
    } else {
        n.p = {realColumn(s, 2, "x", row), realColumn(s, 3, "y", row)};
    }
    n.alive = boolColumn(s, 4, "alive", row);
    n.curves = idListColumn(s, 5, "curves", row);
    n.roundabout = floatColumn(s, 7, "roundabout", row);
    if (!std::isfinite(n.roundabout) || n.roundabout < 0.0f) row.fail("roundabout is not a finite radius >= 0");
    return n;
}

std::string nodeColumns(SqliteDb& db) {
    // Files written before roundabouts have no roundabout column: their nodes have none.
    const bool hasRoundabout =
        db.queryInteger("SELECT COUNT(*) FROM pragma_table_info('lacet_nodes') WHERE name = 'roundabout'") != 0;
    return std::string("layer, id, x, y, alive, curves, exact, ") + (hasRoundabout ? "roundabout" : "0.0");
}

void readNodes(SqliteDb& db, Scene& scene) {
    auto s = db.prepare("SELECT " + nodeColumns(db) + " FROM lacet_nodes ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_nodes"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::nodes, row);
        layer.nodes.push_back(decodeNode(s, row));
    }
}

std::vector<Vertex> verticesColumn(const SqliteStatement& s, int col, const Row& row) {
    const auto b = blobColumn(s, col, "vertices", row);
    if (b.size() % 17 != 0)
        row.fail("vertices blob of " + std::to_string(b.size()) + " bytes, not a multiple of 17 (16 + 1 per vertex)");
    std::vector<Vertex> v(b.size() / 17);
    ByteReader r(b);
    for (Vertex& x : v) {
        r.f64(x.p.x);
        r.f64(x.p.y);
    }
    for (std::size_t k = 0; k < v.size(); ++k) {
        std::uint8_t f = 0;
        r.u8(f);
        if ((f & ~(kOnCurveBit | kClosingBit)) != 0) row.fail("vertex " + std::to_string(k) + " has unknown flag bits");
        v[k].onCurve = (f & kOnCurveBit) != 0;
        v[k].closing = (f & kClosingBit) != 0;
    }
    return v;
}

constexpr const char* kCurveColumns = "layer, id, start, \"end\", w, wf, cls, flags, alive, vertices, areas, exact";

Curve decodeCurve(const SqliteStatement& s, const Row& row) {
    Curve c;
    c.start = ElementId(integerColumn(s, 2, 0, kMaxId, "start", row));
    c.end = ElementId(integerColumn(s, 3, 0, kMaxId, "end", row));
    if (const auto exact = exactColumn(s, 11, 8, row); !exact.empty()) {
        ByteReader r(exact);
        r.f32(c.w);
        r.f32(c.wf);
    } else {
        c.w = floatColumn(s, 4, "w", row);
        c.wf = floatColumn(s, 5, "wf", row);
    }
    c.cls = std::uint16_t(integerColumn(s, 6, 0, 0xffff, "cls", row));
    c.flags = std::uint16_t(integerColumn(s, 7, 0, 0xffff, "flags", row));
    c.alive = boolColumn(s, 8, "alive", row);
    c.vertices = verticesColumn(s, 9, row);
    c.areas = idListColumn(s, 10, "areas", row);
    return c;
}

void readCurves(SqliteDb& db, Scene& scene) {
    auto s = db.prepare(std::string("SELECT ") + kCurveColumns + " FROM lacet_curves ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_curves"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::curves, row);
        layer.curves.push_back(decodeCurve(s, row));
    }
}

std::vector<std::vector<AreaEdge>> loopsColumn(const SqliteStatement& s, int col, const Row& row) {
    ByteReader r(blobColumn(s, col, "loops", row));
    auto truncated = [&] { row.fail("loops blob is truncated"); };
    std::uint32_t nLoops = 0;
    if (!r.u32(nLoops)) truncated();
    if (nLoops > r.remaining() / 4) truncated();  // each loop takes at least 4 bytes
    std::vector<std::vector<AreaEdge>> loops(nLoops);
    for (auto& loop : loops) {
        std::uint32_t nEdges = 0;
        if (!r.u32(nEdges) || nEdges > r.remaining() / 5) truncated();
        loop.resize(nEdges);
        for (AreaEdge& e : loop) {
            std::uint8_t reversed = 0;
            r.u32(e.curve);
            r.u8(reversed);
            if (reversed > 1) row.fail("loops blob holds a reversed flag other than 0 or 1");
            e.reversed = reversed != 0;
        }
    }
    if (r.remaining() != 0) row.fail("loops blob has " + std::to_string(r.remaining()) + " bytes left over");
    return loops;
}

constexpr const char* kAreaColumns = "layer, id, wf, cls, axial, alive, loops, exact";

Area decodeArea(const SqliteStatement& s, const Row& row) {
    Area a;
    if (const auto exact = exactColumn(s, 7, 4, row); !exact.empty()) {
        ByteReader r(exact);
        r.f32(a.wf);
    } else {
        a.wf = floatColumn(s, 2, "wf", row);
    }
    a.cls = std::uint16_t(integerColumn(s, 3, 0, 0xffff, "cls", row));
    a.axial = ElementId(integerColumn(s, 4, 0, kMaxId, "axial", row));
    a.alive = boolColumn(s, 5, "alive", row);
    a.loops = loopsColumn(s, 6, row);
    return a;
}

void readAreas(SqliteDb& db, Scene& scene) {
    auto s = db.prepare(std::string("SELECT ") + kAreaColumns + " FROM lacet_areas ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_areas"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::areas, row);
        layer.areas.push_back(decodeArea(s, row));
    }
}

}  // namespace

namespace {
// An insert statement of the writer, as it is or as INSERT OR REPLACE (rows replaced by (layer, id)).
std::string insertSql(const char* sql, bool replace) {
    return replace ? "INSERT OR REPLACE" + std::string(sql).substr(std::string_view("INSERT").size()) : std::string(sql);
}
}  // namespace

ElementTablesWriter::ElementTablesWriter(SqliteDb& db, bool replace)
    : db_(db),
      node_(db.prepareKept(insertSql(kInsertNode, replace))),
      curve_(db.prepareKept(insertSql(kInsertCurve, replace))),
      area_(db.prepareKept(insertSql(kInsertArea, replace))) {}

ElementTablesWriter::~ElementTablesWriter() = default;

void ElementTablesWriter::layers(const Scene& scene) { writeLayers(db_, scene); }

void ElementTablesWriter::elements(LayerId layer, const Layer& part, const ElementOffsets& o) {
    writeNodes(*node_, layer, part, o.nodes);
    writeCurves(*curve_, layer, part, o.curves);
    writeAreas(*area_, layer, part, o.areas);
}

void ElementTablesWriter::attributes(const SceneDocument& doc) { writeAttributes(db_, doc); }

void readElementTables(SqliteDb& db, SceneDocument& doc) {
    readLayers(db, doc.scene);
    readNodes(db, doc.scene);
    readCurves(db, doc.scene);
    readAreas(db, doc.scene);
    readAttributesOf(
        db, doc,
        [&](LayerId layer, ElementKind kind) {
            const Layer& l = doc.scene.layers[layer];
            return kind == ElementKind::Node ? l.nodes.size() : kind == ElementKind::Curve ? l.curves.size() : l.areas.size();
        },
        [](const ElementAttribute& a) { return a.id; });
}

ElementRows::ElementRows(SqliteDb& db)
    : node_(db.prepareKept("SELECT " + nodeColumns(db) + " FROM lacet_nodes WHERE layer = ? AND id = ?")),
      curve_(db.prepareKept(std::string("SELECT ") + kCurveColumns + " FROM lacet_curves WHERE layer = ? AND id = ?")),
      area_(db.prepareKept(std::string("SELECT ") + kAreaColumns + " FROM lacet_areas WHERE layer = ? AND id = ?")) {}

ElementRows::~ElementRows() = default;

namespace {
template <class Element, class Decode>
Element readOne(SqliteStatement& s, const char* table, LayerId layer, ElementId id, Decode decode) {
    s.reset();
    s.bind(1, std::int64_t(layer));
    s.bind(2, std::int64_t(id));
    Row row{table, std::int64_t(layer), std::int64_t(id)};
    if (!s.step()) row.fail("missing");
    Element e = decode(s, row);
    s.reset();
    return e;
}
}  // namespace

Node ElementRows::node(LayerId layer, ElementId id) { return readOne<Node>(*node_, "lacet_nodes", layer, id, decodeNode); }
Curve ElementRows::curve(LayerId layer, ElementId id) {
    return readOne<Curve>(*curve_, "lacet_curves", layer, id, decodeCurve);
}
Area ElementRows::area(LayerId layer, ElementId id) { return readOne<Area>(*area_, "lacet_areas", layer, id, decodeArea); }

void readLayerTable(SqliteDb& db, Scene& scene) { readLayers(db, scene); }

void readAttributesOf(SqliteDb& db, SceneDocument& doc, const std::function<std::size_t(LayerId, ElementKind)>& slots,
                      const std::function<ElementId(const ElementAttribute&)>& idIn) {
    auto s = db.prepare("SELECT layer, kind, id, key, value FROM lacet_attributes ORDER BY fid");
    while (s.step()) {
        Row row{"lacet_attributes"};
        ElementAttribute a;
        const std::int64_t layer = integerColumn(s, 0, 0, std::int64_t(doc.scene.layers.size()) - 1, "layer", row);
        row.layer = layer;
        a.layer = LayerId(layer);
        a.kind = ElementKind(integerColumn(s, 1, 0, 2, "kind", row));
        const std::size_t count = slots(a.layer, a.kind);
        if (count == 0) row.fail("names an element of an empty kind");
        a.id = ElementId(integerColumn(s, 2, 0, std::int64_t(count) - 1, "id", row));
        if (s.type(3) != SQLITE_TEXT || s.type(4) != SQLITE_TEXT) row.fail("key and value must be text");
        a.id = idIn(a);
        if (a.id == kNoElement) continue;
        a.key = s.text(3);
        a.value = s.text(4);
        doc.attributes.push_back(std::move(a));
    }
}

bool readPartAttributes(SqliteDb& db, SceneDocument& doc) {
    if (db.queryInteger("SELECT count(*) FROM sqlite_master WHERE type = 'index' AND name = 'lacet_attributes_element'") == 0)
        return false;
    if (db.queryInteger("SELECT EXISTS (SELECT 1 FROM lacet_attributes)") == 0) return true;  // none: no lookups
    auto s = db.prepare("SELECT fid, key, value FROM lacet_attributes WHERE layer = ? AND kind = ? AND id = ?");
    std::vector<std::pair<std::int64_t, ElementAttribute>> read;  // with their fid, for the table's order
    for (LayerId l = 0; l < doc.scene.layers.size(); ++l) {
        const Layer::SceneIds& ids = doc.scene.layers[l].sceneIds;
        const auto kindIds = [&](ElementKind kind) -> const std::vector<ElementId>& {
            return kind == ElementKind::Node ? ids.nodes : kind == ElementKind::Curve ? ids.curves : ids.areas;
        };
        for (ElementKind kind : {ElementKind::Node, ElementKind::Curve, ElementKind::Area}) {
            const std::vector<ElementId>& of = kindIds(kind);
            for (std::size_t i = 0; i < of.size(); ++i) {
                s.reset();
                s.bind(1, std::int64_t(l));
                s.bind(2, std::int64_t(kind));
                s.bind(3, std::int64_t(of[i]));
                while (s.step()) {
                    Row row{"lacet_attributes"};
                    row.layer = std::int64_t(l);
                    row.id = std::int64_t(of[i]);
                    if (s.type(1) != SQLITE_TEXT || s.type(2) != SQLITE_TEXT) row.fail("key and value must be text");
                    read.push_back({s.integer(0), ElementAttribute{l, kind, ElementId(i), s.text(1), s.text(2)}});
                }
            }
        }
    }
    std::sort(read.begin(), read.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [fid, a] : read) doc.attributes.push_back(std::move(a));
    return true;
}

namespace {
template <class Element, class Decode>
void forEachRow(SqliteDb& db, const std::string& columns, const char* table, LayerId layer,
                const std::function<void(std::size_t)>& counted, const std::function<void(const Element&)>& each,
                Decode decode) {
    auto n = db.prepare(std::string("SELECT count(*) FROM ") + table + " WHERE layer = ?");
    n.bind(1, std::int64_t(layer));
    n.step();
    const std::int64_t count = n.integer(0);
    counted(std::size_t(count));
    auto s = db.prepare("SELECT " + columns + " FROM " + table + " WHERE layer = ? ORDER BY id");
    s.bind(1, std::int64_t(layer));
    std::int64_t expected = 0;
    while (s.step()) {
        Row row{table, std::int64_t(layer), integerColumn(s, 1, 0, kMaxId, "id", Row{table, std::int64_t(layer)})};
        if (row.id != expected) row.fail("ids are not 0, 1, 2... in their layer (id " + std::to_string(expected) + " expected)");
        ++expected;
        each(decode(s, row));
    }
    if (expected != count) Row{table, std::int64_t(layer)}.fail("rows changed while read");
}
}  // namespace

void forEachNodeRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t)>& counted,
                    const std::function<void(const Node&)>& each) {
    forEachRow<Node>(db, nodeColumns(db), "lacet_nodes", layer, counted, each, decodeNode);
}

void forEachCurveRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t)>& counted,
                     const std::function<void(const Curve&)>& each) {
    forEachRow<Curve>(db, kCurveColumns, "lacet_curves", layer, counted, each, decodeCurve);
}

void forEachAreaRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t)>& counted,
                    const std::function<void(const Area&)>& each) {
    forEachRow<Area>(db, kAreaColumns, "lacet_areas", layer, counted, each, decodeArea);
}

}  // namespace lacet::scene_format
