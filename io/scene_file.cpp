#include "io/scene_file.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <span>
#include <vector>

#include "io/gpkg_dem.h"
#include "io/le_bytes.h"
#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/sqlite_db.h"
#include "model/validate.h"

namespace lacet {
namespace {

constexpr const char* kFormatName = "lacet-scene";
constexpr std::int64_t kGpkgApplicationId = 0x47504B47;  // 'GPKG'
constexpr std::size_t kMaxLayers = 65536;                // LayerId is 16 bits
constexpr std::int64_t kMaxId = 0xffffffffLL;            // ElementId is 32 bits
constexpr std::uint8_t kOnCurveBit = 1u, kClosingBit = 2u;

// A problem with the file's contents (reason only); loadScene adds the file name.
class FormatError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

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
  x REAL, y REAL, alive BOOLEAN NOT NULL, curves BLOB NOT NULL, exact BLOB, UNIQUE (layer, id));
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
)sql";

struct TableInfo {
    const char* name;
    const char* description;
};
constexpr TableInfo kTables[] = {
    {"lacet_meta", "Lacet scene: format, extent, georeference, DEM grid (key/value)"},
    {"lacet_layers", "Lacet scene: layers"},
    {"lacet_nodes", "Lacet scene: nodes of the spline networks (scene CRS metres)"},
    {"lacet_curves", "Lacet scene: Bezier curves (vertices: little-endian f64 x, y then flag bytes)"},
    {"lacet_areas", "Lacet scene: areas (loops of curves)"},
    {"lacet_attributes", "Lacet scene: attributes kept from the source data (kind 0 node, 1 curve, 2 area)"},
};

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

void writeMeta(SqliteDb& db, const SceneDocument& doc) {
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
        {"dem", doc.dem ? kDemRasterTable : "none"},
        {"checksum", sceneChecksumText(doc)},
    };
    if (doc.dem) {
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

void writeNodes(SqliteDb& db, const Scene& scene) {
    auto s = db.prepare("INSERT INTO lacet_nodes (layer, id, x, y, alive, curves, exact) VALUES (?, ?, ?, ?, ?, ?, ?)");
    ByteWriter list, exact;
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        const auto& nodes = scene.layers[l].nodes;
        for (std::size_t id = 0; id < nodes.size(); ++id) {
            const Node& n = nodes[id];
            s.bind(1, std::int64_t(l));
            s.bind(2, std::int64_t(id));
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
            s.step();
            s.reset();
        }
    }
}

void writeCurves(SqliteDb& db, const Scene& scene) {
    auto s = db.prepare(
        "INSERT INTO lacet_curves (layer, id, start, \"end\", w, wf, cls, flags, alive, vertices, areas, exact) "
        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    ByteWriter vertices, list, exact;
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        const auto& curves = scene.layers[l].curves;
        for (std::size_t id = 0; id < curves.size(); ++id) {
            const Curve& c = curves[id];
            s.bind(1, std::int64_t(l));
            s.bind(2, std::int64_t(id));
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

void writeAreas(SqliteDb& db, const Scene& scene) {
    auto s = db.prepare(
        "INSERT INTO lacet_areas (layer, id, wf, cls, axial, alive, loops, exact) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
    ByteWriter loops, exact;
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        const auto& areas = scene.layers[l].areas;
        for (std::size_t id = 0; id < areas.size(); ++id) {
            const Area& a = areas[id];
            s.bind(1, std::int64_t(l));
            s.bind(2, std::int64_t(id));
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

// Adds the lacet_* tables to the GeoPackage at `path`, in one transaction.
void writeTables(const std::string& path, const SceneDocument& doc) {
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
    writeMeta(db, doc);
    writeLayers(db, doc.scene);
    writeNodes(db, doc.scene);
    writeCurves(db, doc.scene);
    writeAreas(db, doc.scene);
    writeAttributes(db, doc);
    writeFeatureTables(db, doc);
    // GDAL writes GPKG 1.2 as asked; set the header anyway, it is what makes the file a GeoPackage.
    db.exec("PRAGMA application_id = 1196444487; PRAGMA user_version = 10200");
    db.exec("COMMIT");
    db.close();
}

std::string systemError(const std::string& what) { return what + ": " + std::strerror(errno); }

// Removes `p` if it exists; throws if it exists and cannot be removed (e.g. a directory).
void removeStale(const std::string& p) {
    if (::unlink(p.c_str()) != 0 && errno != ENOENT)
        throw std::runtime_error(systemError("cannot remove the stale temporary file " + p));
}

void fsyncOrThrow(const std::string& p) {
    const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw std::runtime_error(systemError("cannot open " + p + " to flush it"));
    if (::fsync(fd) != 0) {
        const std::string reason = systemError("cannot flush " + p);
        ::close(fd);
        throw std::runtime_error(reason);
    }
    ::close(fd);
}

// Best effort: the rename is durable once the directory is flushed; failing that changes nothing
// about the file's contents, so errors are ignored.
void fsyncDirectoryOf(const std::string& p) {
    std::string dir = std::filesystem::path(p).parent_path().string();
    if (dir.empty()) dir = ".";
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
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

using Meta = std::map<std::string, std::string>;

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

void readNodes(SqliteDb& db, Scene& scene) {
    auto s = db.prepare("SELECT layer, id, x, y, alive, curves, exact FROM lacet_nodes ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_nodes"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::nodes, row);
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
        layer.nodes.push_back(std::move(n));
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

void readCurves(SqliteDb& db, Scene& scene) {
    auto s = db.prepare(
        "SELECT layer, id, start, \"end\", w, wf, cls, flags, alive, vertices, areas, exact FROM lacet_curves "
        "ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_curves"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::curves, row);
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
        layer.curves.push_back(std::move(c));
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

void readAreas(SqliteDb& db, Scene& scene) {
    auto s = db.prepare("SELECT layer, id, wf, cls, axial, alive, loops, exact FROM lacet_areas ORDER BY layer, id");
    while (s.step()) {
        Row row{"lacet_areas"};
        Layer& layer = rowLayer(s, scene.layers, &Layer::areas, row);
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
        layer.areas.push_back(std::move(a));
    }
}

// Attributes must name an existing element slot.
void readAttributes(SqliteDb& db, SceneDocument& doc) {
    auto s = db.prepare("SELECT layer, kind, id, key, value FROM lacet_attributes ORDER BY fid");
    while (s.step()) {
        Row row{"lacet_attributes"};
        ElementAttribute a;
        const std::int64_t layer = integerColumn(s, 0, 0, std::int64_t(doc.scene.layers.size()) - 1, "layer", row);
        row.layer = layer;
        a.layer = LayerId(layer);
        a.kind = ElementKind(integerColumn(s, 1, 0, 2, "kind", row));
        const Layer& l = doc.scene.layers[a.layer];
        const std::size_t count = a.kind == ElementKind::Node ? l.nodes.size() : a.kind == ElementKind::Curve ? l.curves.size() : l.areas.size();
        if (count == 0) row.fail("names an element of an empty kind");
        a.id = ElementId(integerColumn(s, 2, 0, std::int64_t(count) - 1, "id", row));
        if (s.type(3) != SQLITE_TEXT || s.type(4) != SQLITE_TEXT) row.fail("key and value must be text");
        a.key = s.text(3);
        a.value = s.text(4);
        doc.attributes.push_back(std::move(a));
    }
}

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

// Checks that `path` is an intact GeoPackage holding a Lacet scene of a known version; returns its meta.
Meta openScene(SqliteDb& db, std::int64_t fileSize) {
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
    const std::string check = db.queryText("PRAGMA quick_check(1)");
    if (check != "ok") throw FormatError("corrupt file (SQLite quick_check: " + check + ")");
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

}  // namespace

void saveScene(const std::string& path, const SceneDocument& doc) {
    if (auto problems = validate(doc.scene); !problems.empty())
        throw SceneFileError(path + ": cannot save an invalid scene: " + ValidationError(std::move(problems)).what());
    if (doc.scene.layers.size() > kMaxLayers)
        throw SceneFileError(path + ": cannot save more than " + std::to_string(kMaxLayers) + " layers");
    const std::string tmp = path + ".tmp";
    bool tmpIsOurs = false;
    try {
        // A crashed save may have left the temporary file and its journal: a journal left next to a
        // new file would be "rolled back" into it.
        for (const char* suffix : {"", "-journal", "-wal", "-shm"}) removeStale(tmp + suffix);
        tmpIsOurs = true;
        if (doc.dem)
            createGpkgWithDem(tmp, *doc.dem, doc.georeference.valid ? doc.georeference.crsWkt : std::string());
        else
            createEmptyGpkg(tmp);
        writeTables(tmp, doc);
        fsyncOrThrow(tmp);
        if (std::rename(tmp.c_str(), path.c_str()) != 0)
            throw std::runtime_error(systemError("cannot rename " + tmp + " to it"));
        tmpIsOurs = false;
        fsyncDirectoryOf(path);
    } catch (const std::exception& e) {
        if (tmpIsOurs) {
            ::unlink(tmp.c_str());
            ::unlink((tmp + "-journal").c_str());
        }
        throw SceneFileError(path + ": cannot save: " + e.what());
    }
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

SceneDocument loadScene(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw SceneFileError(systemError(path + ": cannot open"));
    if (S_ISDIR(st.st_mode)) throw SceneFileError(path + ": is a directory, not a Lacet scene");
    if (st.st_size == 0) throw SceneFileError(path + ": empty file, not a Lacet scene");
    SceneDocument doc;
    std::string checksum;
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        const Meta meta = openScene(db, std::int64_t(st.st_size));
        doc.scene.extent = metaBox(meta, "extent");
        doc.georeference.valid = metaInteger(meta, "georeference_valid", 0, 1) != 0;
        doc.georeference.lon0 = metaDouble(meta, "georeference_lon0");
        doc.georeference.lat0 = metaDouble(meta, "georeference_lat0");
        doc.georeference.originShift = {metaDouble(meta, "georeference_origin_shift_x"),
                                        metaDouble(meta, "georeference_origin_shift_y")};
        doc.georeference.crsWkt = metaValue(meta, "crs_wkt");
        checksum = metaValue(meta, "checksum");
        readLayers(db, doc.scene);
        readNodes(db, doc.scene);
        readCurves(db, doc.scene);
        readAreas(db, doc.scene);
        readAttributes(db, doc);
        const std::string& dem = metaValue(meta, "dem");
        std::int64_t demWidth = 0, demHeight = 0;
        if (dem == kDemRasterTable) {
            demWidth = metaInteger(meta, "dem_width", 1, INT32_MAX);
            demHeight = metaInteger(meta, "dem_height", 1, INT32_MAX);
            checkDemTiles(db, demWidth, demHeight);
        }
        db.close();
        if (dem == kDemRasterTable) {
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
    } catch (const SqliteError& e) {
        throw SceneFileError(path + ": not a GeoPackage, or corrupt: " + e.what());
    } catch (const std::bad_alloc&) {
        throw SceneFileError(path + ": out of memory while loading");
    } catch (const std::exception& e) {
        throw SceneFileError(path + ": cannot load: " + e.what());
    }
    if (auto problems = validate(doc.scene); !problems.empty())
        throw SceneFileError(path + ": invalid scene: " + ValidationError(std::move(problems)).what());
    if (const std::string sum = sceneChecksumText(doc); sum != checksum)
        throw SceneFileError(path + ": corrupt file (its contents do not match their checksum: " + sum + ", not " +
                             checksum + ")");
    return doc;
}

}  // namespace lacet
