#include "io/scene_region.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <iomanip>
#include <optional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_format.h"
#include "raster/elevation_producer.h"

namespace lacet {

using namespace scene_format;

namespace {

// One curve to close (by its id in the document), and whether it lies within the region's reach
// (its nodes' curves are loaded).
struct Pending {
    LayerId layer = 0;
    ElementId id = 0;
    bool near = false;
};

// The elements of one kind of a layer read so far, by their ids in the document: each id of the
// file that a loaded element names gets a slot (dead and empty until it is loaded itself), so that
// the walks below see what they see over the whole scene; compact() keeps the loaded ones, in file
// order.
struct KindSlots {
    std::size_t fileCount = 0;                          // the file's ids: max(id) + 1
    std::unordered_map<ElementId, ElementId> byFile;    // file id -> document id
    std::vector<ElementId> file;                        // document id -> file id
    std::vector<bool> loaded;                           // by document id

    // The document id of file id `id`, given a dead and empty slot in `elements` when new.
    template <class Element>
    ElementId slot(std::vector<Element>& elements, ElementId id, const char* what) {
        if (id >= fileCount) throw FormatError(std::string(what) + " " + std::to_string(id) + " is named but not in the file");
        const auto [it, added] = byFile.try_emplace(id, ElementId(elements.size()));
        if (added) {
            file.push_back(id);
            elements.emplace_back().alive = false;
            loaded.push_back(false);
        }
        return it->second;
    }

    // The loaded slots in file order: their file ids (Layer::sceneIds) and each document id's new
    // id (kNoElement: not loaded), with the document ids they come from.
    struct Order {
        std::vector<ElementId> fileIds, from, renumber;
    };
    Order order() const {
        Order o;
        for (ElementId d = 0; d < file.size(); ++d)
            if (loaded[d]) o.from.push_back(d);
        std::sort(o.from.begin(), o.from.end(), [&](ElementId a, ElementId b) { return file[a] < file[b]; });
        o.renumber.assign(file.size(), kNoElement);
        o.fileIds.resize(o.from.size());
        for (std::size_t k = 0; k < o.from.size(); ++k) {
            o.fileIds[k] = file[o.from[k]];
            o.renumber[o.from[k]] = ElementId(k);
        }
        return o;
    }
};

// A layer's slots.
struct LayerSlots {
    KindSlots nodes, curves, areas;
    std::vector<bool> curveNear;                    // by document id: the curve lies within the reach
    std::unordered_set<ElementId> upstreamChecked;  // file ids of river curves whose flow was read

    KindSlots& of(ElementKind kind) { return kind == ElementKind::Node ? nodes : kind == ElementKind::Curve ? curves : areas; }
    const KindSlots& of(ElementKind kind) const {
        return kind == ElementKind::Node ? nodes : kind == ElementKind::Curve ? curves : areas;
    }
};

class RegionLoader {
public:
    RegionLoader(const std::string& path, SqliteDb& db, SceneDocument& doc, std::vector<FeatureTableRef> tables,
                 double tolerance, SceneRegionOptions filter)
        : path_(path), db_(db), doc_(doc), rows_(db), tables_(std::move(tables)), tolerance_(tolerance), filter_(filter) {
        const std::size_t n = doc.scene.layers.size();
        slots_.resize(n);
        // Each layer's file ids: its largest id + 1, through the (layer, id) index, not a scan of the
        // table (a region reads a small part of it). A row missing below it is found when read.
        for (const char* table : {"lacet_nodes", "lacet_curves", "lacet_areas"}) {
            const std::vector<std::size_t> counts = fileIdCounts(db, table, n);
            for (std::size_t layer = 0; layer < n; ++layer)
                slots_[layer].of(table[6] == 'n' ? ElementKind::Node : table[6] == 'c' ? ElementKind::Curve : ElementKind::Area).fileCount =
                    counts[layer];
        }
        if (const SceneOverlay* o = filter_.overlay) {
            // Elements added by the edits have ids past the file's; a layer's features the file has
            // no table for are found in the overlay alone.
            addOverlayTables(tables_, *o, n);
            for (const auto& [ref, e] : o->elements) {
                KindSlots& k = slots_[ref.layer].of(ref.kind);
                k.fileCount = std::max(k.fileCount, std::size_t(ref.id) + 1);
            }
        }
        charge(memoryBytes(doc.scene));  // the layers, without elements yet
    }

    // Everything whose feature box meets `box`.
    std::size_t findIn(const Box& box) {
        std::size_t found = 0;
        for (const FeatureTableRef& t : tables_) {
            const LayerKind kind = doc_.scene.layers[t.layer].kind;
            if (filter_.elevationOnly && (t.polygons ? kind != LayerKind::Lakes && kind != LayerKind::Rivers
                                                     : kind != LayerKind::Roads && kind != LayerKind::Rivers))
                continue;
            for (ElementId id : query(t, box)) {
                ++found;
                if (t.polygons) loadArea(t.layer, areaSlot(t.layer, id), true);
                else if (filter_.elevationOnly) addElevationCurve(t.layer, id);
                else loadCurve(t.layer, curveSlot(t.layer, id), true);
            }
        }
        return found;
    }

    // Node `ref` (its id in the file) and every curve at it, as a curve found brings them.
    void loadNamedNode(const ElementRef& ref) {
        if (ref.kind != ElementKind::Node || ref.layer >= doc_.scene.layers.size())
            throw FormatError("node " + std::to_string(ref.id) + " of layer " + std::to_string(ref.layer) + " is named but not in the file");
        const ElementId n = nodeSlot(ref.layer, ref.id);
        loadNode(ref.layer, n);
        const std::vector<ElementId> at = doc_.scene.layers[ref.layer].nodes[n].curves;  // loading grows the layer's vectors
        for (ElementId c : at) loadCurve(ref.layer, c, true);
    }

    // Loads what the loaded elements depend on, until nothing is added.
    void close() {
        while (!pending_.empty()) {
            const Pending p = pending_.front();
            pending_.pop_front();
            closeCurve(p);
        }
    }

    // A river area's water follows its river on through the area (raster/elevation_producer.h:
    // axialRiver), whatever quad its tile is in: every curve at the nodes the walk looks at, and
    // the areas those curves border (so that the walk over the part read, whose lists trimLists()
    // keeps to what was read, sees what it sees over the whole scene), until no walk finds more.
    void closeAxialRivers() {
        for (bool changed = true; changed;) {
            changed = false;
            for (LayerId l = 0; l < doc_.scene.layers.size(); ++l) {
                Layer& layer = doc_.scene.layers[l];
                if (layer.kind != LayerKind::Rivers) continue;
                for (ElementId a = 0; a < layer.areas.size(); ++a) {
                    if (!slots_[l].areas.loaded[a] || layer.areas[a].axial == kNoElement) continue;
                    const std::size_t before = nodes + curves + areas;
                    const AxialRiver walk = axialRiver(layer, layer.areas[a]);
                    for (ElementId n : walk.nodes) {
                        loadNode(l, n);
                        const std::vector<ElementId> at = layer.nodes[n].curves;  // loading grows the layer's vectors
                        for (ElementId c : at) {
                            loadCurve(l, c, false);
                            const std::vector<ElementId> borders = layer.curves[c].areas;
                            for (ElementId border : borders) loadArea(l, border, false);
                        }
                    }
                    close();
                    changed = changed || nodes + curves + areas != before;
                }
            }
        }
    }

    // Node lists of curves and curve lists of areas keep what was loaded.
    void trimLists() {
        for (std::size_t l = 0; l < doc_.scene.layers.size(); ++l) {
            Layer& layer = doc_.scene.layers[l];
            const LayerSlots& s = slots_[l];
            for (std::size_t n = 0; n < layer.nodes.size(); ++n)
                if (s.nodes.loaded[n]) std::erase_if(layer.nodes[n].curves, [&](ElementId c) { return !s.curves.loaded[c]; });
            for (std::size_t c = 0; c < layer.curves.size(); ++c)
                if (s.curves.loaded[c]) std::erase_if(layer.curves[c].areas, [&](ElementId a) { return !s.areas.loaded[a]; });
        }
    }

    // Keeps the loaded elements only, in the file's order, and records their file ids
    // (Layer::sceneIds). After trimLists(): a loaded element names loaded ones only.
    void compact() {
        for (std::size_t l = 0; l < doc_.scene.layers.size(); ++l) {
            Layer& layer = doc_.scene.layers[l];
            const LayerSlots& s = slots_[l];
            const KindSlots::Order nodeOrder = s.nodes.order(), curveOrder = s.curves.order(), areaOrder = s.areas.order();
            const auto to = [&](const KindSlots::Order& o, ElementId id) {
                if (id == kNoElement) return id;
                if (o.renumber[id] == kNoElement) throw FormatError("layer '" + layer.name + "': a loaded element names one not loaded");
                return o.renumber[id];
            };
            std::vector<Node> ns(nodeOrder.from.size());
            for (std::size_t k = 0; k < ns.size(); ++k) {
                ns[k] = std::move(layer.nodes[nodeOrder.from[k]]);
                for (ElementId& c : ns[k].curves) c = to(curveOrder, c);
            }
            std::vector<Curve> cs(curveOrder.from.size());
            for (std::size_t k = 0; k < cs.size(); ++k) {
                cs[k] = std::move(layer.curves[curveOrder.from[k]]);
                cs[k].start = to(nodeOrder, cs[k].start);
                cs[k].end = to(nodeOrder, cs[k].end);
                for (ElementId& a : cs[k].areas) a = to(areaOrder, a);
            }
            std::vector<Area> as(areaOrder.from.size());
            for (std::size_t k = 0; k < as.size(); ++k) {
                as[k] = std::move(layer.areas[areaOrder.from[k]]);
                for (auto& loop : as[k].loops)
                    for (AreaEdge& e : loop) e.curve = to(curveOrder, e.curve);
                as[k].axial = to(curveOrder, as[k].axial);
            }
            layer.nodes = std::move(ns);
            layer.curves = std::move(cs);
            layer.areas = std::move(as);
            layer.sceneIds = {true, nodeOrder.fileIds, curveOrder.fileIds, areaOrder.fileIds};
        }
    }

    // The file's count of ids of `kind` in `layer`.
    std::size_t fileSlots(LayerId layer, ElementKind kind) const { return slots_[layer].of(kind).fileCount; }

    std::size_t nodes = 0, curves = 0, areas = 0;
    std::size_t bytes = 0;  // held so far (charge())

private:
    std::vector<ElementId> query(const FeatureTableRef& t, const Box& box) {
        return featuresIn(db_, t, box, fileSlots(t.layer, t.polygons ? ElementKind::Area : ElementKind::Curve), filter_.overlay);
    }

    // An element's row, or its value in the edits.
    template <class T>
    const T* edited(LayerId l, ElementKind kind, ElementId id) const {
        if (!filter_.overlay) return nullptr;
        const OverlayElement* e = filter_.overlay->find({l, kind, id});
        return e ? &std::get<T>(e->value) : nullptr;
    }
    Node nodeRow(LayerId l, ElementId id) {
        const Node* e = edited<Node>(l, ElementKind::Node, id);
        return e ? *e : rows_.node(l, id);
    }
    Curve curveRow(LayerId l, ElementId id) {
        const Curve* e = edited<Curve>(l, ElementKind::Curve, id);
        return e ? *e : rows_.curve(l, id);
    }
    Area areaRow(LayerId l, ElementId id) {
        const Area* e = edited<Area>(l, ElementKind::Area, id);
        return e ? *e : rows_.area(l, id);
    }

    // Counts `n` more bytes of elements held; refuses the read when they pass the budget.
    void charge(std::size_t n) {
        bytes += n;
        if (toMiB(bytes) > filter_.budgetMiB) {
            std::ostringstream m;
            m << std::fixed << std::setprecision(2) << "the vector data of the region passes the budget of "
              << filter_.budgetMiB << " MiB after reading " << nodes << " nodes, " << curves << " curves and " << areas
              << " areas";
            throw SceneBudgetError(path_ + ": " + m.str());
        }
    }
    ElementId nodeSlot(LayerId l, ElementId id) { return slots_[l].nodes.slot(doc_.scene.layers[l].nodes, id, "node"); }
    ElementId curveSlot(LayerId l, ElementId id) {
        LayerSlots& s = slots_[l];
        const ElementId d = s.curves.slot(doc_.scene.layers[l].curves, id, "curve");
        if (d >= s.curveNear.size()) s.curveNear.resize(d + 1, false);
        return d;
    }
    ElementId areaSlot(LayerId l, ElementId id) { return slots_[l].areas.slot(doc_.scene.layers[l].areas, id, "area"); }

    // Rows name file ids; the loaded element names document ids (slots). A dead row names nothing.
    void loadNode(LayerId l, ElementId id) {
        LayerSlots& s = slots_[l];
        if (s.nodes.loaded[id]) return;
        s.nodes.loaded[id] = true;
        Node n = nodeRow(l, s.nodes.file[id]);
        if (n.alive)
            for (ElementId& c : n.curves) c = curveSlot(l, c);
        else {
            n = Node{};
            n.alive = false;
        }
        charge(memoryBytes(n) + sizeof(ElementId));  // and its file id (Layer::sceneIds)
        doc_.scene.layers[l].nodes[id] = std::move(n);
        ++nodes;
    }

    // `row`: the curve's row when the caller has read it already.
    void loadCurve(LayerId l, ElementId id, bool near, std::optional<Curve> row = std::nullopt) {
        LayerSlots& s = slots_[l];
        if (s.curves.loaded[id] && (!near || s.curveNear[id])) return;
        if (!s.curves.loaded[id]) {
            s.curves.loaded[id] = true;
            Curve c = row ? std::move(*row) : curveRow(l, s.curves.file[id]);
            if (c.alive) {
                c.start = nodeSlot(l, c.start);
                c.end = nodeSlot(l, c.end);
                for (ElementId& a : c.areas) a = areaSlot(l, a);
            } else {
                c = Curve{};
                c.alive = false;
            }
            charge(memoryBytes(c) + sizeof(ElementId));
            doc_.scene.layers[l].curves[id] = std::move(c);
            ++curves;
        }
        s.curveNear[id] = s.curveNear[id] || near;
        pending_.push_back({l, id, near});
    }

    // A curve found with SceneRegionOptions::elevationOnly: kept when the elevation producer draws
    // it (its row read once to see).
    void addElevationCurve(LayerId l, ElementId fileId) {
        const KindSlots& kind = slots_[l].curves;
        if (const auto it = kind.byFile.find(fileId); it != kind.byFile.end() && kind.loaded[it->second])
            return loadCurve(l, it->second, true);
        Curve c = curveRow(l, fileId);
        if (c.alive && !(c.flags & (kBridge | kTunnel)) && double(c.w) >= filter_.minCurveWidth)
            loadCurve(l, curveSlot(l, fileId), true, std::move(c));
    }

    void loadArea(LayerId l, ElementId id, bool near) {
        LayerSlots& s = slots_[l];
        if (s.areas.loaded[id]) return;
        s.areas.loaded[id] = true;
        Area a = areaRow(l, s.areas.file[id]);
        if (a.alive) {
            for (auto& loop : a.loops)
                for (AreaEdge& e : loop) e.curve = curveSlot(l, e.curve);
            if (a.axial != kNoElement) a.axial = curveSlot(l, a.axial);
        } else {
            a = Area{};
            a.alive = false;
        }
        doc_.scene.layers[l].areas[id] = a;  // a copy: the curve loads below may move the areas
        charge(memoryBytes(doc_.scene.layers[l].areas[id]) + sizeof(ElementId));
        ++areas;
        for (const auto& loop : a.loops)
            for (const AreaEdge& e : loop) loadCurve(l, e.curve, near);
        if (a.axial != kNoElement) loadCurve(l, a.axial, near);
    }

    void closeCurve(const Pending& p) {
        Layer& layer = doc_.scene.layers[p.layer];
        // Loading grows the layer's vectors: what is read of this curve is copied first.
        const Curve& c = layer.curves[p.id];
        if (!c.alive) return;
        const ElementId ends[2] = {c.start, c.end};
        const std::uint16_t flags = c.flags;
        const bool bridgesSought = layer.kind == LayerKind::Roads && !c.vertices.empty();
        const Box hull = bridgesSought ? hullBox(c) : Box{};
        for (ElementId n : ends) loadNode(p.layer, n);
        if (p.near)
            for (ElementId n : ends) {
                const std::vector<ElementId> at = layer.nodes[n].curves;
                for (ElementId other : at) loadCurve(p.layer, other, false);
            }
        if (bridgesSought) {
            const Box box = hull.dilated(tolerance_);  // a feature's box may lie within the tolerance of its spline
            for (const FeatureTableRef& t : tables_) {
                const LayerKind kind = doc_.scene.layers[t.layer].kind;
                if (kind != LayerKind::Rivers && !(kind == LayerKind::Roads && (flags & kBridge))) continue;
                for (ElementId id : query(t, box)) {
                    if (t.polygons) loadArea(t.layer, areaSlot(t.layer, id), false);
                    else loadCurve(t.layer, curveSlot(t.layer, id), false);
                }
            }
        }
        if (layer.kind == LayerKind::Rivers) {
            LayerSlots& s = slots_[p.layer];
            for (ElementId n : ends) {
                const std::vector<ElementId> at = layer.nodes[n].curves;
                for (ElementId other : at) {
                    if (s.curves.loaded[other]) continue;
                    const ElementId file = s.curves.file[other];
                    if (!s.upstreamChecked.insert(file).second) continue;  // each curve's row read once for this test
                    const Curve row = curveRow(p.layer, file);
                    if (row.alive && row.end == s.nodes.file[n]) loadCurve(p.layer, other, false);  // flows into n
                }
            }
        }
    }

    const std::string& path_;
    SqliteDb& db_;
    SceneDocument& doc_;
    ElementRows rows_;
    std::vector<FeatureTableRef> tables_;
    double tolerance_ = 0.0;
    SceneRegionOptions filter_;
    std::vector<LayerSlots> slots_;
    std::deque<Pending> pending_;
};

}  // namespace

SceneDocument loadSceneRegion(const std::string& path, const Box& region, const RefineParams& params, int level,
                              SceneRegionStats* stats, const SceneRegionOptions& filter) {
    SceneFileConnection connection(path);
    return loadSceneRegion(connection, region, params, level, stats, filter);
}

SceneDocument loadSceneRegion(SceneFileConnection& connection, const Box& region, const RefineParams& params, int level,
                              SceneRegionStats* stats, const SceneRegionOptions& filter) {
    const std::string& path = connection.path();
    if (level < 0 || level > 30) throw std::invalid_argument("loadSceneRegion: level " + std::to_string(level) + " is not in 0..30");
    if (!(region.min.x <= region.max.x && region.min.y <= region.max.y))
        throw std::invalid_argument("loadSceneRegion: the region is empty");
    if (!(filter.minCurveWidth >= 0.0) || !std::isfinite(filter.minCurveWidth))
        throw std::invalid_argument("loadSceneRegion: SceneRegionOptions::minCurveWidth must be finite and >= 0");
    if (!(filter.budgetMiB > 0.0)) throw std::invalid_argument("loadSceneRegion: SceneRegionOptions::budgetMiB must be > 0");
    SceneRegionStats local;
    SceneRegionStats& st = stats ? *stats : local;
    st = {};
    bool indexed = false;
    SceneDocument doc;
    const auto readRegion = [&](SqliteDb& db, SceneDocument& d) {
        indexed = db.hasTable(kFeatureIndexTable);
        if (!indexed) {
            if (filter.overlay && !filter.overlay->empty())
                throw SceneFileError(path + ": the file has no feature index, which reading it with edits not saved needs: save it again");
            readElementTables(db, d);
            return;
        }
        const ReadTransaction transaction(db);
        readLayerTable(db, d.scene);
        FeatureIndex index = readFeatureIndex(db, d.scene);
        double curveWf = index.curveWf, areaWf = index.areaWf;
        const double tolerance = index.tolerance;
        // The edits' widths and rings: what the file would say of them saved.
        double editedRadius = 0.0;
        if (filter.overlay)
            for (const auto& [ref, e] : filter.overlay->elements) {
                if (const Curve* c = std::get_if<Curve>(&e.value); c && c->alive) curveWf = std::max(curveWf, double(c->wf));
                if (const Area* a = std::get_if<Area>(&e.value); a && a->alive) areaWf = std::max(areaWf, double(a->wf));
                if (const Node* n = std::get_if<Node>(&e.value); n && n->alive) editedRadius = std::max(editedRadius, double(n->roundabout));
            }
        st.tolerance = tolerance;
        const Vec2 extent = d.scene.extent.size();
        const double quadSize = std::max(extent.x, extent.y) / double(std::int64_t(1) << level);
        // The largest margin of any element at this quad size (a curve's delta is never above the
        // level's), plus the features' distance from their splines, plus a float's rounding.
        st.reach = std::max(params.curveMargin(std::numeric_limits<double>::max(), curveWf, quadSize),
                            params.areaMargin(areaWf, quadSize)) +
                   tolerance;
        // A roundabout's ring reaches its radius beyond the roads at its node.
        {
            // lacet_nodes_roundabout, a partial index of the nodes with a ring, makes this a
            // look at those nodes (a scan of the table in a file written before it).
            auto s = db.prepare("SELECT max(roundabout) FROM lacet_nodes WHERE alive AND roundabout > 0");
            const double radius = s.step() ? s.real(0) : 0.0;
            if (!(radius >= 0.0) || !std::isfinite(radius)) throw FormatError("lacet_nodes: a roundabout radius is not finite and >= 0");
            st.reach += std::max(radius, editedRadius);
        }
        st.reach += 1e-6 * std::max({1.0, std::fabs(region.min.x), std::fabs(region.max.x), std::fabs(region.min.y),
                                     std::fabs(region.max.y)});
        RegionLoader loader(path, db, d, std::move(index.tables), tolerance, filter);
        // The quads of the level that meet the region (closed boxes: a quad touching its border
        // counts), on the root's grid, then the reach around them.
        const double cells = double(std::int64_t(1) << level);
        const auto cell = [&](double v, double origin) { return std::clamp(std::floor((v - origin) / quadSize), 0.0, cells - 1.0); };
        const Vec2 origin = d.scene.extent.min;
        const Box quads{origin + Vec2(cell(region.min.x, origin.x), cell(region.min.y, origin.y)) * quadSize,
                        origin + (Vec2(cell(region.max.x, origin.x), cell(region.max.y, origin.y)) + 1.0) * quadSize};
        st.found = loader.findIn(quads.dilated(st.reach));
        for (const ElementRef& node : filter.nodes) loader.loadNamedNode(node);
        loader.close();
        loader.closeAxialRivers();
        loader.trimLists();
        loader.compact();
        // Through lacet_attributes' index, a lookup per element read; a file written before the
        // index is scanned whole.
        if (!readPartAttributes(db, d))
            readAttributesOf(
                db, d, [&](LayerId layer, ElementKind kind) { return loader.fileSlots(layer, kind); },
                [&](const ElementAttribute& a) {  // the id it has in the part read, if read
                    const Layer::SceneIds& ids = d.scene.layers[a.layer].sceneIds;
                    const auto& of = a.kind == ElementKind::Node ? ids.nodes : a.kind == ElementKind::Curve ? ids.curves : ids.areas;
                    const auto it = std::lower_bound(of.begin(), of.end(), a.id);
                    return it != of.end() && *it == a.id ? ElementId(it - of.begin()) : kNoElement;
                });
        st.sceneNodes = st.sceneCurves = st.sceneAreas = 0;
        for (LayerId l = 0; l < d.scene.layers.size(); ++l) {
            st.sceneNodes += loader.fileSlots(l, ElementKind::Node);
            st.sceneCurves += loader.fileSlots(l, ElementKind::Curve);
            st.sceneAreas += loader.fileSlots(l, ElementKind::Area);
        }
        st.nodes = loader.nodes;
        st.curves = loader.curves;
        st.areas = loader.areas;
        st.bytes = loader.bytes;  // what was counted while reading (the test checks it is what is held)
    };
    int version = 0;
    const std::string checksum = loadSceneParts(connection, doc, readRegion, filter.dem, filter.wholeFileCheck, &version);
    st.checksum = checksum;
    // Read whole: checked whole, as loadScene checks it.
    if (!indexed && filter.dem && sceneChecksumText(doc, version) != checksum)
        throw SceneFileError(path + ": corrupt file (its contents do not match their checksum)");
    st.wholeScene = !indexed;
    if (!indexed) st.bytes = memoryBytes(doc.scene);
    if (!indexed && toMiB(st.bytes) > filter.budgetMiB)  // read whole: refused once read
        throw SceneBudgetError(path + ": the vector data of the scene (read whole: the file has no feature index) holds " +
                               std::to_string(toMiB(st.bytes)) + " MiB, over the budget of " +
                               std::to_string(filter.budgetMiB) + " MiB");
    if (!indexed)
        for (const Layer& l : doc.scene.layers) {
            st.sceneNodes += l.nodes.size();
            st.sceneCurves += l.curves.size();
            st.sceneAreas += l.areas.size();
            st.nodes += l.nodes.size();
            st.curves += l.curves.size();
            st.areas += l.areas.size();
        }
    return doc;
}

}  // namespace lacet
