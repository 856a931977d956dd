#include "io/scene_save_edits.h"

#include <charconv>
#include <chrono>
#include <map>
#include <optional>
#include <variant>

#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/scene_format.h"

namespace lacet {
namespace {

using namespace scene_format;

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::optional<Box> unite(const std::optional<Box>& a, const Box& b) {
    if (!(b.min.x <= b.max.x)) return a;
    return a ? Box{glm::min(a->min, b.min), glm::max(a->max, b.max)} : b;
}

// A box the feature of curve `c` or area `a` (of `layer`, as the file holds them now) meets (none:
// it has none): the hull of a curve's control points, or of an area's loop curves'.
std::optional<Box> featureSearchBox(const Curve& c) { return c.alive ? unite(std::nullopt, hullBox(c)) : std::nullopt; }
std::optional<Box> featureSearchBox(ElementRows& rows, LayerId layer, const Area& a) {
    if (!a.alive) return std::nullopt;
    std::optional<Box> box;
    for (const auto& loop : a.loops)
        for (const AreaEdge& e : loop) box = unite(box, hullBox(rows.curve(layer, e.curve)));
    return box;
}

// What the feature of `r` needs, read as the file holds it now, in ids of the layer returned: the
// element at 0; a curve's areas, an area's loop curves and axial curve after it.
Layer featureLayer(ElementRows& rows, const ElementRef& r) {
    Layer local;
    if (r.kind == ElementKind::Curve) {
        Curve c = rows.curve(r.layer, r.id);
        for (ElementId& a : c.areas) {
            local.areas.push_back(rows.area(r.layer, a));
            a = ElementId(local.areas.size() - 1);
        }
        local.curves.push_back(std::move(c));
        return local;
    }
    Area a = rows.area(r.layer, r.id);
    std::map<ElementId, ElementId> ids;
    const auto localOf = [&](ElementId file) {
        const auto [it, added] = ids.emplace(file, ElementId(local.curves.size()));
        if (added) local.curves.push_back(rows.curve(r.layer, file));
        return it->second;
    };
    for (auto& loop : a.loops)
        for (AreaEdge& e : loop) e.curve = localOf(e.curve);
    if (a.axial != kNoElement) a.axial = localOf(a.axial);
    local.areas.push_back(std::move(a));
    return local;
}

// lacet_meta's checksum and, from format 2, its parts (none where missing or not 16 hex digits).
struct StoredChecksum {
    std::string text;
    std::optional<std::uint64_t> head, elements;
    bool giveChecksum() const { return head && elements && SceneChecksum::combine(*head, *elements) == text; }
};

std::optional<std::uint64_t> hexValue(const std::string& s) {
    std::uint64_t v = 0;
    if (s.size() != 16) return std::nullopt;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v, 16);
    return r.ec == std::errc() && r.ptr == s.data() + s.size() ? std::optional(v) : std::nullopt;
}

StoredChecksum storedChecksum(SqliteDb& db) {
    StoredChecksum out;
    auto s = db.prepare("SELECT key, value FROM lacet_meta WHERE key IN ('checksum', 'checksum_head', 'checksum_elements')");
    while (s.step()) {
        const std::string key = s.text(0), value = s.text(1);
        if (key == "checksum") out.text = value;
        else if (key == "checksum_head") out.head = hexValue(value);
        else out.elements = hexValue(value);
    }
    return out;
}

}  // namespace

SceneEditsSaved saveSceneEdits(const std::string& path, const SceneOverlay& overlay, const std::string& expected) {
    const auto t0 = std::chrono::steady_clock::now();
    SceneEditsSaved out;
    out.checksum = expected;
    if (overlay.empty()) return out;
    const auto changed = [&](const std::string& now) {
        return SceneFileError(path + ": not saved: the file changed since its edits began (its stored checksum is " + now + ", was " +
                              expected + "); it is left as it is");
    };
    // The document but its elements: its layers; where the checksum is summed again whole (a
    // format-1 file, or stored parts that do not give it), also what it sums beside the rows
    // (attributes, DEM).
    SceneDocument head;
    int version = 0;
    StoredChecksum parts;
    std::string stored = loadSceneParts(
        path, head,
        [&](SqliteDb& db, SceneDocument& doc) {
            readLayerTable(db, doc.scene);
            parts = storedChecksum(db);
        },
        /*readDem=*/false, /*wholeFileCheck=*/false, &version);
    if (stored != expected) throw changed(stored);
    const bool summedWhole = version < 2 || !parts.giveChecksum();
    if (summedWhole) {
        head = SceneDocument();
        stored = loadSceneParts(
            path, head,
            [](SqliteDb& db, SceneDocument& doc) {
                readLayerTable(db, doc.scene);
                const std::size_t layers = doc.scene.layers.size();
                const std::vector<std::size_t> counts[] = {fileIdCounts(db, "lacet_nodes", layers), fileIdCounts(db, "lacet_curves", layers),
                                                           fileIdCounts(db, "lacet_areas", layers)};
                readAttributesOf(
                    db, doc, [&](LayerId l, ElementKind k) { return counts[std::size_t(k)][l]; },
                    [](const ElementAttribute& a) { return a.id; });
            },
            /*readDem=*/true, /*wholeFileCheck=*/false);
        if (stored != expected) throw changed(stored);
    }
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);  // waits for readers: SqliteDb::kDefaultBusyTimeoutMs
        db.exec("BEGIN IMMEDIATE");
        const StoredChecksum sum = storedChecksum(db);
        if (sum.text != expected || sum.giveChecksum() != parts.giveChecksum()) throw changed(sum.text);
        // Format 2 with parts that give the checksum: updated by the elements' digests (their
        // rows' before, the overlay's after); else summed again whole below, with the whole head.
        std::optional<std::uint64_t> elements;
        if (!summedWhole) elements = sum.elements;
        {
            ElementRows rows(db);
            // Each changed element's row before the edits, read once: its digest leaves the sum,
            // the overlay's value's enters it; and the features to set, with the boxes their rows
            // meet before the edits: the curves and areas changed, and the curves of the loops of
            // an area changed, before and after.
            std::map<ElementRef, std::optional<Box>> features;
            const auto addLoops = [&](LayerId layer, const Area& a) {
                for (const auto& loop : a.loops)
                    for (const AreaEdge& edge : loop)
                        if (const ElementRef r{layer, ElementKind::Curve, edge.curve}; !features.contains(r))
                            features.emplace(r, featureSearchBox(rows.curve(layer, edge.curve)));
            };
            for (const auto& [ref, e] : overlay.elements) {
                const auto moved = [&, &r = ref](const auto& now, const auto& before) {
                    if (elements) *elements += SceneChecksum::elementDigest(r.layer, r.id, now) - SceneChecksum::elementDigest(r.layer, r.id, before);
                };
                if (const Node* n = std::get_if<Node>(&e.value)) {
                    moved(*n, rows.node(ref.layer, ref.id));
                } else if (const Curve* c = std::get_if<Curve>(&e.value)) {
                    const Curve before = rows.curve(ref.layer, ref.id);
                    moved(*c, before);
                    features[ref] = featureSearchBox(before);
                } else {
                    const Area& now = std::get<Area>(e.value);
                    const Area before = rows.area(ref.layer, ref.id);
                    moved(now, before);
                    features[ref] = featureSearchBox(rows, ref.layer, before);
                    addLoops(ref.layer, before);
                    addLoops(ref.layer, now);
                }
            }
            if (db.queryInteger("SELECT COUNT(*) FROM pragma_table_info('lacet_nodes') WHERE name = 'roundabout'") == 0)
                db.exec("ALTER TABLE lacet_nodes ADD COLUMN roundabout REAL NOT NULL DEFAULT 0");
            {
                ElementTablesWriter writer(db, /*replace=*/true);
                for (const auto& [ref, e] : overlay.elements) {
                    Layer one;
                    ElementOffsets at;
                    if (const Node* n = std::get_if<Node>(&e.value)) {
                        one.nodes.push_back(*n);
                        at.nodes = ref.id;
                        ++out.nodes;
                    } else if (const Curve* c = std::get_if<Curve>(&e.value)) {
                        one.curves.push_back(*c);
                        at.curves = ref.id;
                        ++out.curves;
                    } else {
                        one.areas.push_back(std::get<Area>(e.value));
                        at.areas = ref.id;
                        ++out.areas;
                    }
                    writer.elements(ref.layer, one, at);
                }
            }
            FeatureTablesEditor editor(db, head);
            for (const auto& [ref, box] : features) editor.set(ref, box, featureLayer(rows, ref), 0);
            out.features = editor.finish();
        }
        out.writeMs = msSince(t0);
        const auto t1 = std::chrono::steady_clock::now();
        SceneChecksumParts now;
        if (elements) {
            now = {SceneChecksum::combine(*sum.head, *elements), *sum.head, *elements};
        } else {
            now = checksumOfRows(db, head, [](LayerId) { return true; });
            db.exec("UPDATE lacet_meta SET value = '" + std::to_string(kSceneFormatVersion) + "' WHERE key = 'format_version'");
            out.summedWhole = true;
        }
        writeChecksum(db, now);
        out.checksum = now.text;
        out.checksumMs = msSince(t1);
        db.exec("COMMIT");
        try {
            db.close();  // saved already: a failure to close is no failure of the save
        } catch (const std::exception&) {
        }
    } catch (const SceneFileError&) {
        throw;
    } catch (const std::exception& e) {
        throw SceneFileError(path + ": the edits were not saved (the file is as it was): " + e.what());
    }
    out.totalMs = msSince(t0);
    return out;
}

}  // namespace lacet
