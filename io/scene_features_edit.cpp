// The feature tables of a scene file edited in place (io/scene_features.h: FeatureTablesEditor).
#include <sqlite3.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "io/scene_features.h"
#include "io/scene_features_internal.h"

namespace lacet {
namespace {

using namespace feature_tables;

// ---- the ST_* functions of the GeoPackage R-tree triggers (GPKG 1.2 Annex F.3) ----

// A GeoPackage geometry blob's envelope: from its header, else from its WKB (2D points, lines and
// polygons); `empty` from the header's flag.
struct BlobEnvelope {
    bool empty = false;
    Envelope e;
};

std::optional<BlobEnvelope> readBlobEnvelope(const std::uint8_t* b, std::size_t n) {
    if (n < 8 || b[0] != 'G' || b[1] != 'P') return std::nullopt;
    const std::uint8_t flags = b[3];
    const bool littleEndian = (flags & 1u) != 0;
    const int indicator = (flags >> 1) & 7;
    BlobEnvelope out;
    out.empty = (flags & (1u << 4)) != 0;
    static constexpr std::size_t kEnvelopeBytes[] = {0, 32, 48, 48, 64};
    if (indicator > 4) return std::nullopt;
    const std::size_t header = 8 + kEnvelopeBytes[indicator];
    if (n < header) return std::nullopt;
    const auto real = [](const std::uint8_t* p, bool le) {
        std::uint64_t w = 0;
        for (int k = 0; k < 8; ++k) w |= std::uint64_t(p[le ? k : 7 - k]) << (8 * k);
        return std::bit_cast<double>(w);
    };
    if (indicator > 0) {
        out.e.minX = real(b + 8, littleEndian);
        out.e.maxX = real(b + 16, littleEndian);
        out.e.minY = real(b + 24, littleEndian);
        out.e.maxY = real(b + 32, littleEndian);
        return out;
    }
    if (out.empty) return out;
    // No envelope in the header: the WKB's points (2D Point, LineString, Polygon).
    const std::uint8_t* p = b + header;
    const std::uint8_t* end = b + n;
    if (end - p < 5) return std::nullopt;
    const bool le = p[0] == 1;
    const auto u32 = [&](const std::uint8_t* q) {
        std::uint32_t w = 0;
        for (int k = 0; k < 4; ++k) w |= std::uint32_t(q[le ? k : 3 - k]) << (8 * k);
        return w;
    };
    const std::uint32_t type = u32(p + 1);
    p += 5;
    const auto points = [&](std::uint32_t count) {
        if (std::size_t(end - p) / 16 < count) return false;
        for (std::uint32_t k = 0; k < count; ++k, p += 16) out.e.add(Vec2(real(p, le), real(p + 8, le)));
        return true;
    };
    const auto counted = [&]() -> std::optional<std::uint32_t> {
        if (end - p < 4) return std::nullopt;
        const std::uint32_t c = u32(p);
        p += 4;
        return c;
    };
    if (type == 1) return points(1) ? std::optional(out) : std::nullopt;
    if (type == 2) {
        const auto c = counted();
        return c && points(*c) ? std::optional(out) : std::nullopt;
    }
    if (type == 3) {
        const auto rings = counted();
        if (!rings) return std::nullopt;
        for (std::uint32_t r = 0; r < *rings; ++r) {
            const auto c = counted();
            if (!c || !points(*c)) return std::nullopt;
        }
        return out;
    }
    return std::nullopt;
}

// Which value an ST_* function gives: 0..3 minx, maxx, miny, maxy; 4 whether empty.
void stFunction(sqlite3_context* ctx, int, sqlite3_value** argv) {
    const auto which = reinterpret_cast<std::intptr_t>(sqlite3_user_data(ctx));
    if (sqlite3_value_type(argv[0]) != SQLITE_BLOB) {
        sqlite3_result_null(ctx);
        return;
    }
    const auto* b = static_cast<const std::uint8_t*>(sqlite3_value_blob(argv[0]));
    const auto e = readBlobEnvelope(b, std::size_t(sqlite3_value_bytes(argv[0])));
    if (!e) {
        sqlite3_result_null(ctx);
        return;
    }
    if (which == 4) {
        sqlite3_result_int(ctx, e->empty || e->e.empty() ? 1 : 0);
        return;
    }
    if (e->e.empty()) {
        sqlite3_result_null(ctx);
        return;
    }
    const double v[] = {e->e.minX, e->e.maxX, e->e.minY, e->e.maxY};
    sqlite3_result_double(ctx, v[which]);
}

void registerStFunctions(SqliteDb& db) {
    const char* names[] = {"ST_MinX", "ST_MaxX", "ST_MinY", "ST_MaxY", "ST_IsEmpty"};
    for (std::intptr_t k = 0; k < 5; ++k)
        if (sqlite3_create_function(db.handle(), names[k], 1, SQLITE_UTF8 | SQLITE_DETERMINISTIC | SQLITE_INNOCUOUS, reinterpret_cast<void*>(k), stFunction,
                                    nullptr, nullptr) != SQLITE_OK)
            throw SqliteError(std::string("cannot register ") + names[k] + ": " + sqlite3_errmsg(db.handle()));
}

std::string lowercase(std::string s) {
    for (char& ch : s) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    return s;
}

// A box's margin for the R-tree search of a feature's old row: its points lie in the control
// points' hull up to the rounding of the halvings.
Box searchBox(const Box& b) {
    const double m = 1e-6 * (1.0 + std::max({std::abs(b.min.x), std::abs(b.min.y), std::abs(b.max.x), std::abs(b.max.y)}));
    return b.dilated(m);
}

}  // namespace

struct FeatureTablesEditor::Table {
    std::string name;
    LayerId layer = 0;
    bool polygons = false;
    double tolerance = 0.1;
    std::int64_t srsId = kUndefinedCartesianSrsId;
    std::set<std::string> columns;  // lowercase
    Envelope added;
    double curveWf = 0.0, areaWf = 0.0;
    bool touched = false;
    std::unique_ptr<SqliteStatement> find, update, remove;
};

FeatureTablesEditor::FeatureTablesEditor(SqliteDb& db, const SceneDocument& head) : db_(db), head_(head) {
    if (!db.hasTable(kFeatureIndexTable))
        throw std::invalid_argument(std::string("the file has no feature index (") + kFeatureIndexTable + "): save it whole");
    registerStFunctions(db);
    auto s = db.prepare(std::string("SELECT table_name, layer, polygons, tolerance FROM ") + kFeatureIndexTable + " ORDER BY table_name");
    while (s.step()) {
        auto t = std::make_unique<Table>();
        t->name = s.text(0);
        t->layer = LayerId(s.integer(1));
        t->polygons = s.integer(2) != 0;
        t->tolerance = s.real(3);
        tables_.push_back(std::move(t));
    }
    for (auto& t : tables_) {
        auto g = db.prepare("SELECT srs_id FROM gpkg_geometry_columns WHERE table_name = ?");
        g.bindText(1, t->name);
        if (g.step()) t->srsId = g.integer(0);
        auto c = db.prepare("SELECT name FROM pragma_table_info(?)");
        c.bindText(1, t->name);
        while (c.step()) t->columns.insert(lowercase(c.text(0)));
    }
}

FeatureTablesEditor::~FeatureTablesEditor() = default;

FeatureTablesEditor::Table& FeatureTablesEditor::table(LayerId layer, bool polygons) {
    for (auto& t : tables_)
        if (t->layer == layer && t->polygons == polygons) return *t;
    // Its layer has no table of this kind: the second of planFeatureTables', named as it names it.
    const Layer& l = head_.scene.layers.at(layer);
    std::set<std::string> taken;
    {
        auto s = db_.prepare("SELECT lower(name) FROM sqlite_master");
        while (s.step()) taken.insert(s.text(0));
    }
    const std::string base = tableBaseName(l.name);
    const bool second = isLayerOfLines(l.kind) == polygons;
    auto t = std::make_unique<Table>();
    t->name = uniqueName(second ? base + (polygons ? "_areas" : "_lines") : base, taken);
    t->layer = layer;
    t->polygons = polygons;
    t->tolerance = tables_.empty() ? FeatureTableParams{}.tolerance : tables_.front()->tolerance;
    t->srsId = tables_.empty() ? featureSrsId(db_, head_) : tables_.front()->srsId;
    const FeatureTable plan{.name = t->name, .layer = layer, .polygons = polygons, .elements = {}};
    createTable(db_, plan, {});
    createRtree(db_, plan);
    registerTable(db_, l, plan, Envelope{}, t->srsId, t->tolerance);
    createRtreeTriggers(db_, plan);
    if (db_.hasTable("gpkg_ogr_contents")) recordFeatureCount(db_, plan);
    auto s = db_.prepare(std::string("INSERT INTO ") + kFeatureIndexTable + " VALUES (?, ?, ?, ?, 0, 0)");
    s.bindText(1, t->name);
    s.bind(2, std::int64_t(layer));
    s.bind(3, std::int64_t(polygons));
    s.bind(4, t->tolerance);
    s.step();
    for (const std::string& c : fixedColumnNames()) t->columns.insert(c);
    ++counts_.tablesMade;
    tables_.push_back(std::move(t));
    return *tables_.back();
}

void FeatureTablesEditor::set(const ElementRef& ref, const std::optional<Box>& before, const Layer& local, ElementId id) {
    const bool polygons = ref.kind == ElementKind::Area;
    if (ref.kind == ElementKind::Node) throw std::invalid_argument("FeatureTablesEditor::set: a node has no feature");
    Table* t = nullptr;
    for (auto& candidate : tables_)
        if (candidate->layer == ref.layer && candidate->polygons == polygons) t = candidate.get();
    const bool has = polygons ? local.areas.at(id).alive : isLineFeature(local, local.curves.at(id));
    if (!polygons) {
        // Its largest wf, in the table of the areas it borders too (a region read's reach).
        const Curve& c = local.curves[id];
        if (c.alive && !has)
            for (auto& other : tables_)
                if (other->layer == ref.layer && other->polygons) {
                    other->curveWf = std::max(other->curveWf, double(c.wf));
                    other->touched = true;
                }
    }
    if (has && !t) t = &table(ref.layer, polygons);
    if (!t) return;
    t->touched = true;
    std::int64_t fid = 0;
    if (before) {
        if (!t->find)
            t->find = db_.prepareKept("SELECT fid FROM " + quoted(t->name) + " WHERE lacet_id = ? AND fid IN (SELECT id FROM " +
                                      quoted(featureRtreeName(t->name)) + " WHERE minx <= ? AND maxx >= ? AND miny <= ? AND maxy >= ?)");
        const Box b = searchBox(*before);
        SqliteStatement& f = *t->find;
        f.reset();
        f.bind(1, std::int64_t(ref.id));
        f.bind(2, b.max.x);
        f.bind(3, b.min.x);
        f.bind(4, b.max.y);
        f.bind(5, b.min.y);
        if (f.step()) fid = f.integer(0);
        f.reset();
    }
    if (!has) {
        if (fid == 0) return;
        if (!t->remove) t->remove = db_.prepareKept("DELETE FROM " + quoted(t->name) + " WHERE fid = ?");
        t->remove->reset();
        t->remove->bind(1, fid);
        t->remove->step();
        t->remove->reset();
        ++counts_.deleted;
        return;
    }
    if (fid == 0) {
        insert(*t, ref);
        fid = db_.queryInteger("SELECT last_insert_rowid()");
        ++counts_.inserted;
    } else {
        ++counts_.updated;
    }
    // The geometry and fixed columns now.
    ByteWriter blob;
    Envelope e;
    if (!t->update)
        t->update = db_.prepareKept(polygons ? "UPDATE " + quoted(t->name) + " SET geom = ?, class = ?, wf = ? WHERE fid = ?"
                                             : "UPDATE " + quoted(t->name) +
                                                   " SET geom = ?, class = ?, w = ?, wf = ?, bridge = ?, tunnel = ? WHERE fid = ?");
    SqliteStatement& u = *t->update;
    u.reset();
    if (polygons) {
        const Area& a = local.areas[id];
        e = polygonBlob(blob, polygonRings(local, a, t->tolerance), t->srsId);
        u.bindBlob(1, blob.bytes());
        u.bind(2, std::int64_t(a.cls));
        u.bind(3, double(a.wf));
        u.bind(4, fid);
        t->areaWf = std::max(t->areaWf, double(a.wf));
        for (const Curve& c : local.curves) t->curveWf = std::max(t->curveWf, double(c.wf));  // its loops and axial curve
    } else {
        const Curve& c = local.curves[id];
        e = lineStringBlob(blob, flattenSpline(c.vertices, t->tolerance), t->srsId);
        u.bindBlob(1, blob.bytes());
        u.bind(2, std::int64_t(c.cls));
        u.bind(3, double(c.w));
        u.bind(4, double(c.wf));
        u.bind(5, std::int64_t((c.flags & kBridge) != 0));
        u.bind(6, std::int64_t((c.flags & kTunnel) != 0));
        u.bind(7, fid);
        t->curveWf = std::max(t->curveWf, double(c.wf));
    }
    u.step();
    u.reset();
    t->added.add(e);
}

void FeatureTablesEditor::insert(Table& t, const ElementRef& ref) {
    // Its attributes, the first value of each key, each in its column (added when missing).
    std::map<std::string, std::string> values;
    {
        auto s = db_.prepare("SELECT key, value FROM lacet_attributes WHERE layer = ? AND kind = ? AND id = ? ORDER BY fid");
        s.bind(1, std::int64_t(ref.layer));
        s.bind(2, std::int64_t(ref.kind));
        s.bind(3, std::int64_t(ref.id));
        while (s.step()) values.emplace(s.text(0), s.text(1));
    }
    std::string columns = "lacet_id, class", params = "?, 0";
    if (!t.polygons) {
        columns += ", w, wf, bridge, tunnel";
        params += ", 0, 0, 0, 0";
    } else {
        columns += ", wf";
        params += ", 0";
    }
    std::vector<const std::string*> bound;
    std::set<std::string> boundColumns;
    const std::set<std::string> fixed = fixedColumnNames();
    for (const auto& [key, value] : values) {
        std::string name = attributeColumnBase(key, fixed);
        if (boundColumns.contains(name)) continue;  // a key of the same column name before it
        boundColumns.insert(name);
        if (!t.columns.contains(name)) {
            std::set<std::string> taken = t.columns;
            name = uniqueName(name, taken);
            db_.exec("ALTER TABLE " + quoted(t.name) + " ADD COLUMN " + quoted(name) + " TEXT");
            t.columns.insert(name);
        }
        columns += ", " + quoted(name);
        params += ", ?";
        bound.push_back(&value);
    }
    auto s = db_.prepare("INSERT INTO " + quoted(t.name) + " (" + columns + ") VALUES (" + params + ")");
    s.bind(1, std::int64_t(ref.id));
    for (std::size_t k = 0; k < bound.size(); ++k) s.bindText(int(k) + 2, *bound[k]);
    s.step();
}

FeatureTablesEditor::Counts FeatureTablesEditor::finish() {
    for (auto& t : tables_) {
        t->find.reset();
        t->update.reset();
        t->remove.reset();
        if (!t->touched) continue;
        if (!t->added.empty()) {
            auto s = db_.prepare(
                "UPDATE gpkg_contents SET last_change = strftime('%Y-%m-%dT%H:%M:%fZ', 'now'), "
                "min_x = CASE WHEN min_x IS NULL THEN ?1 ELSE min(min_x, ?1) END, min_y = CASE WHEN min_y IS NULL THEN ?2 ELSE min(min_y, ?2) END, "
                "max_x = CASE WHEN max_x IS NULL THEN ?3 ELSE max(max_x, ?3) END, max_y = CASE WHEN max_y IS NULL THEN ?4 ELSE max(max_y, ?4) END "
                "WHERE table_name = ?5");
            s.bind(1, t->added.minX);
            s.bind(2, t->added.minY);
            s.bind(3, t->added.maxX);
            s.bind(4, t->added.maxY);
            s.bindText(5, t->name);
            s.step();
        } else {
            auto s = db_.prepare("UPDATE gpkg_contents SET last_change = strftime('%Y-%m-%dT%H:%M:%fZ', 'now') WHERE table_name = ?");
            s.bindText(1, t->name);
            s.step();
        }
        auto s = db_.prepare(std::string("UPDATE ") + kFeatureIndexTable +
                             " SET max_curve_wf = max(max_curve_wf, ?), max_area_wf = max(max_area_wf, ?) WHERE table_name = ?");
        s.bind(1, t->curveWf);
        s.bind(2, t->areaWf);
        s.bindText(3, t->name);
        s.step();
    }
    return counts_;
}

}  // namespace lacet
