#include "io/scene_save_edits.h"

#include <sys/stat.h>

#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <variant>

#include "io/dem_lod.h"
#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/scene_format.h"
#include "model/work_clock.h"

namespace lacet {
namespace {

using namespace scene_format;

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
// element at 0; a curve's areas, an area's loop curves and axial curve after it. An element whose
// row was deleted (`gone`): a dead one.
Layer featureLayer(ElementRows& rows, const ElementRef& r, bool gone) {
    Layer local;
    if (gone) {
        if (r.kind == ElementKind::Curve) local.curves.emplace_back().alive = false;
        else local.areas.emplace_back().alive = false;
        return local;
    }
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

// Each layer's count of ids of each kind (its largest id + 1, through the (layer, id) index).
struct IdCounts {
    std::vector<std::size_t> byKind[3];  // by ElementKind, then layer
    std::size_t of(const ElementRef& r) const { return byKind[std::size_t(r.kind)].at(r.layer); }
    static const char* table(ElementKind k) {
        return k == ElementKind::Node ? "lacet_nodes" : k == ElementKind::Curve ? "lacet_curves" : "lacet_areas";
    }
};

IdCounts idCounts(SqliteDb& db, std::size_t layers) {
    IdCounts c;
    for (ElementKind k : {ElementKind::Node, ElementKind::Curve, ElementKind::Area}) c.byKind[std::size_t(k)] = fileIdCounts(db, IdCounts::table(k), layers);
    return c;
}

// Format 2's head digest of `head` (its layers, attributes, georeference and DEM) with the counts
// `counts`: what SceneChecksum sums beside the elements' digests.
std::uint64_t headDigestOf(const SceneDocument& head, const IdCounts& counts) {
    SceneChecksum sum(head.scene);
    for (LayerId l = 0; l < head.scene.layers.size(); ++l) {
        sum.layerHead(head.scene.layers[l]);
        for (ElementKind k : {ElementKind::Node, ElementKind::Curve, ElementKind::Area}) sum.count(counts.of({l, k, 0}));
    }
    return sum.finish(head).head;
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
    // format-1 file, or stored parts that do not give it) or its head is (elements added or taken
    // away), also what the head sums beside the counts (attributes, DEM).
    SceneDocument head;
    int version = 0;
    StoredChecksum parts;
    IdCounts counts;
    bool streamedDem = false;  // a DEM LOD tree: the head sums its layout and stored digest, no sample
    std::string stored = loadSceneParts(
        path, head,
        [&](SqliteDb& db, SceneDocument& doc) {
            readLayerTable(db, doc.scene);
            parts = storedChecksum(db);
            counts = idCounts(db, doc.scene.layers.size());
            streamedDem = db.queryText("SELECT value FROM lacet_meta WHERE key = 'dem'") == kDemLodTable;
        },
        /*readDem=*/false, /*wholeFileCheck=*/false, &version);
    if (stored != expected) throw changed(stored);
    const bool summedWhole = version < 2 || !parts.giveChecksum();
    // Elements added or taken away change the head's counts: its digest is summed again.
    bool countsChange = false;
    for (const auto& [ref, e] : overlay.elements) {
        if (ref.layer >= head.scene.layers.size())
            throw SceneFileError(path + ": not saved: the edits name layer " + std::to_string(ref.layer) + ", which the file has not");
        countsChange = countsChange || (e.absent ? ref.id < counts.of(ref) : ref.id >= counts.of(ref));  // a row goes or comes
    }
    if (summedWhole || countsChange) {
        head = SceneDocument();
        // A streamed DEM's tree opened alone (its layout and digest), not a level of it read.
        const bool readDem = summedWhole || !streamedDem;
        stored = loadSceneParts(
            path, head,
            [](SqliteDb& db, SceneDocument& doc) {
                readLayerTable(db, doc.scene);
                const std::size_t layers = doc.scene.layers.size();
                const IdCounts ids = idCounts(db, layers);
                readAttributesOf(
                    db, doc, [&](LayerId l, ElementKind k) { return ids.of({l, k, 0}); },
                    [](const ElementAttribute& a) { return a.id; });
            },
            readDem, /*wholeFileCheck=*/false);
        if (stored != expected) throw changed(stored);
        try {
            if (!readDem) head.demLod = std::make_shared<const DemLodFile>(path);
        } catch (const DemLodError& e) {
            throw SceneFileError(std::string("not saved: ") + e.what());
        }
    }
    try {
        struct stat opened {};
        if (::stat(path.c_str(), &opened) != 0) throw SceneFileError(path + ": not saved: " + std::strerror(errno));
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);  // waits for readers: SqliteDb::kDefaultBusyTimeoutMs
        db.exec("BEGIN IMMEDIATE");
        // A whole save (saveSceneOver) may have renamed a new file over the path while this waited
        // for the old one's lock: writing into the old one would lose the edits.
        struct stat locked {};
        if (::stat(path.c_str(), &locked) != 0 || locked.st_dev != opened.st_dev || locked.st_ino != opened.st_ino)
            throw SceneFileError(path + ": not saved: another program saved a new file over it since its edits began; it is left as it is");
        const StoredChecksum sum = storedChecksum(db);
        if (sum.text != expected || sum.giveChecksum() != parts.giveChecksum()) throw changed(sum.text);
        counts = idCounts(db, head.scene.layers.size());  // as read in this transaction
        // Each layer and kind's ids after the save: the file's, those added, less those taken away.
        std::map<std::pair<LayerId, ElementKind>, std::int64_t> idsAfter;
        for (const auto& [ref, e] : overlay.elements) {
            const bool row = ref.id < counts.of(ref);
            std::int64_t& n = idsAfter.try_emplace({ref.layer, ref.kind}, std::int64_t(counts.of(ref))).first->second;
            n += e.absent ? -std::int64_t(row) : std::int64_t(!row);
        }
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
                // The row before (none: an element added) leaves the sum; the value now enters it,
                // unless the element is absent.
                const bool row = ref.id < counts.of(ref);
                if (e.absent && !row) continue;  // taken back before it was saved: nothing to do
                const auto moved = [&, &r = ref, &absent = e.absent](const auto& now, const auto* before) {
                    if (!elements) return;
                    if (!absent) *elements += SceneChecksum::elementDigest(r.layer, r.id, now);
                    if (before) *elements -= SceneChecksum::elementDigest(r.layer, r.id, *before);
                };
                if (const Node* n = std::get_if<Node>(&e.value)) {
                    const std::optional<Node> before = row ? std::optional(rows.node(ref.layer, ref.id)) : std::nullopt;
                    moved(*n, before ? &*before : nullptr);
                } else if (const Curve* c = std::get_if<Curve>(&e.value)) {
                    const std::optional<Curve> before = row ? std::optional(rows.curve(ref.layer, ref.id)) : std::nullopt;
                    moved(*c, before ? &*before : nullptr);
                    features[ref] = before ? featureSearchBox(*before) : std::nullopt;
                } else {
                    const Area& now = std::get<Area>(e.value);
                    const std::optional<Area> before = row ? std::optional(rows.area(ref.layer, ref.id)) : std::nullopt;
                    moved(now, before ? &*before : nullptr);
                    features[ref] = before ? featureSearchBox(rows, ref.layer, *before) : std::nullopt;
                    if (before) addLoops(ref.layer, *before);
                    if (!e.absent) addLoops(ref.layer, now);
                }
            }
            if (db.queryInteger("SELECT COUNT(*) FROM pragma_table_info('lacet_nodes') WHERE name = 'roundabout'") == 0)
                db.exec("ALTER TABLE lacet_nodes ADD COLUMN roundabout REAL NOT NULL DEFAULT 0");
            {
                ElementTablesWriter writer(db, /*replace=*/true);
                std::unique_ptr<SqliteStatement> remove[3];
                for (const auto& [ref, e] : overlay.elements) {
                    if (e.absent) {
                        if (ref.id >= counts.of(ref)) continue;
                        std::unique_ptr<SqliteStatement>& d = remove[std::size_t(ref.kind)];
                        if (!d) d = db.prepareKept(std::string("DELETE FROM ") + IdCounts::table(ref.kind) + " WHERE layer = ? AND id = ?");
                        d->reset();
                        d->bind(1, std::int64_t(ref.layer));
                        d->bind(2, std::int64_t(ref.id));
                        d->step();
                        d->reset();
                        ++out.removed;
                        continue;
                    }
                    out.added += ref.id >= counts.of(ref);
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
            for (const auto& [ref, box] : features) {
                const OverlayElement* e = overlay.find(ref);
                editor.set(ref, box, featureLayer(rows, ref, e && e->absent), 0);
            }
            out.features = editor.finish();
        }
        // The ids of each layer and kind are still 0, 1, 2... (loadScene refuses a file with a hole).
        const IdCounts now = idCounts(db, head.scene.layers.size());
        for (const auto& [key, n] : idsAfter)
            if (std::int64_t(now.of({key.first, key.second, 0})) != n)
                throw SceneFileError(path + ": not saved (the file is as it was): the edits would leave a gap in the ids of the " +
                                     IdCounts::table(key.second) + " of layer " + std::to_string(key.first));
        out.writeMs = msSince(t0);
        const auto t1 = std::chrono::steady_clock::now();
        SceneChecksumParts sums;
        if (elements) {
            std::uint64_t headDigest = *sum.head;
            if (countsChange) {
                headDigest = headDigestOf(head, now);
                out.headSummed = true;
            }
            sums = {SceneChecksum::combine(headDigest, *elements), headDigest, *elements};
        } else {
            sums = checksumOfRows(db, head, [](LayerId) { return true; });
            db.exec("UPDATE lacet_meta SET value = '" + std::to_string(kSceneFormatVersion) + "' WHERE key = 'format_version'");
            out.summedWhole = true;
        }
        writeChecksum(db, sums);
        out.checksum = sums.text;
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
