#include "io/scene_region.h"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <limits>
#include <stdexcept>
#include <vector>

#include "io/scene_checksum.h"
#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_format.h"
#include "raster/elevation_producer.h"

namespace lacet {

using namespace scene_format;

namespace {

struct FeatureTableRef {
    std::string name;
    LayerId layer = 0;
    bool polygons = false;
};

// One element to load, and whether it lies within the region's reach (its nodes' curves are loaded).
struct Pending {
    LayerId layer = 0;
    ElementId id = 0;
    bool near = false;
};

class RegionLoader {
public:
    RegionLoader(SqliteDb& db, SceneDocument& doc, std::vector<FeatureTableRef> tables, double tolerance, SceneRegionOptions filter)
        : db_(db), doc_(doc), rows_(db), tables_(std::move(tables)), tolerance_(tolerance), filter_(filter) {
        const std::size_t n = doc.scene.layers.size();
        nodeLoaded_.resize(n);
        curveLoaded_.resize(n);
        curveNear_.resize(n);
        upstreamChecked_.resize(n);
        areaLoaded_.resize(n);
        // Each layer's slots: its largest id + 1, through the (layer, id) index, not a scan of the
        // table (a region reads a small part of it). A row missing below it is found when read.
        for (const char* table : {"lacet_nodes", "lacet_curves", "lacet_areas"}) {
            auto s = db.prepare(std::string("SELECT max(id) + 1 FROM ") + table + " WHERE layer = ?");
            for (std::size_t layer = 0; layer < n; ++layer) {
                s.reset();
                s.bind(1, std::int64_t(layer));
                const std::int64_t count = s.step() && s.type(0) != SQLITE_NULL ? s.integer(0) : 0;
                if (count < 0 || count > kMaxId + 1)
                    throw FormatError(std::string(table) + ": layer " + std::to_string(layer) + ": ids out of range");
                Layer& l = doc.scene.layers[layer];
                if (table[6] == 'n') l.nodes.resize(std::size_t(count));
                else if (table[6] == 'c') l.curves.resize(std::size_t(count));
                else l.areas.resize(std::size_t(count));
            }
        }
        for (std::size_t l = 0; l < n; ++l) {
            Layer& layer = doc.scene.layers[l];
            for (Node& x : layer.nodes) x.alive = false;  // slots not loaded: dead and empty
            for (Curve& x : layer.curves) x.alive = false;
            for (Area& x : layer.areas) x.alive = false;
            nodeLoaded_[l].assign(layer.nodes.size(), false);
            curveLoaded_[l].assign(layer.curves.size(), false);
            curveNear_[l].assign(layer.curves.size(), false);
            upstreamChecked_[l].assign(layer.curves.size(), false);
            areaLoaded_[l].assign(layer.areas.size(), false);
        }
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
                if (t.polygons) addArea(t.layer, id, true);
                else if (filter_.elevationOnly) addElevationCurve(t.layer, id);
                else addCurve(t.layer, id, true);
            }
        }
        return found;
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
                    if (!areaLoaded_[l][a] || layer.areas[a].axial == kNoElement) continue;
                    const std::size_t before = nodes + curves + areas;
                    const AxialRiver walk = axialRiver(layer, layer.areas[a]);
                    for (ElementId n : walk.nodes) {
                        addNode(l, n);
                        for (ElementId c : layer.nodes[n].curves) {
                            addCurve(l, c, false);
                            for (ElementId border : layer.curves[c].areas) addArea(l, border, false);
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
            for (std::size_t n = 0; n < layer.nodes.size(); ++n)
                if (nodeLoaded_[l][n])
                    std::erase_if(layer.nodes[n].curves, [&](ElementId c) { return c >= layer.curves.size() || !curveLoaded_[l][c]; });
            for (std::size_t c = 0; c < layer.curves.size(); ++c)
                if (curveLoaded_[l][c])
                    std::erase_if(layer.curves[c].areas, [&](ElementId a) { return a >= layer.areas.size() || !areaLoaded_[l][a]; });
        }
    }

    bool loaded(const ElementAttribute& a) const {
        const auto& flags = a.kind == ElementKind::Node ? nodeLoaded_ : a.kind == ElementKind::Curve ? curveLoaded_ : areaLoaded_;
        return a.layer < flags.size() && a.id < flags[a.layer].size() && flags[a.layer][a.id];
    }

    std::size_t nodes = 0, curves = 0, areas = 0;

private:
    std::vector<ElementId> query(const FeatureTableRef& t, const Box& box) {
        auto s = db_.prepare("SELECT lacet_id FROM \"" + t.name + "\" WHERE fid IN (SELECT id FROM \"" +
                             featureRtreeName(t.name) + "\" WHERE minx <= ? AND maxx >= ? AND miny <= ? AND maxy >= ?)");
        s.bind(1, box.max.x);
        s.bind(2, box.min.x);
        s.bind(3, box.max.y);
        s.bind(4, box.min.y);
        std::vector<ElementId> ids;
        const Layer& layer = doc_.scene.layers[t.layer];
        const std::size_t count = t.polygons ? layer.areas.size() : layer.curves.size();
        while (s.step()) {
            const std::int64_t id = s.integer(0);
            if (id < 0 || std::size_t(id) >= count)
                throw FormatError("feature table '" + t.name + "': lacet_id " + std::to_string(id) + " names no element");
            ids.push_back(ElementId(id));
        }
        return ids;
    }

    void addNode(LayerId l, ElementId id) {
        if (id >= nodeLoaded_[l].size()) throw FormatError("a curve names node " + std::to_string(id) + ", which is not in lacet_nodes");
        if (nodeLoaded_[l][id]) return;
        nodeLoaded_[l][id] = true;
        doc_.scene.layers[l].nodes[id] = rows_.node(l, id);
        ++nodes;
    }

    // `row`: the curve's row when the caller has read it already.
    void addCurve(LayerId l, ElementId id, bool near, std::optional<Curve> row = std::nullopt) {
        if (id >= curveLoaded_[l].size()) throw FormatError("curve " + std::to_string(id) + " is not in lacet_curves");
        if (curveLoaded_[l][id] && (!near || curveNear_[l][id])) return;
        if (!curveLoaded_[l][id]) {
            curveLoaded_[l][id] = true;
            doc_.scene.layers[l].curves[id] = row ? std::move(*row) : rows_.curve(l, id);
            ++curves;
        }
        curveNear_[l][id] = curveNear_[l][id] || near;
        pending_.push_back({l, id, near});
    }

    // A curve found with SceneRegionOptions::elevationOnly: kept when the elevation producer draws
    // it (its row read once to see).
    void addElevationCurve(LayerId l, ElementId id) {
        if (id >= curveLoaded_[l].size() || curveLoaded_[l][id]) return addCurve(l, id, true);
        Curve c = rows_.curve(l, id);
        if (c.alive && !(c.flags & (kBridge | kTunnel)) && double(c.w) >= filter_.minCurveWidth) addCurve(l, id, true, std::move(c));
    }

    void addArea(LayerId l, ElementId id, bool near) {
        if (id >= areaLoaded_[l].size()) throw FormatError("area " + std::to_string(id) + " is not in lacet_areas");
        if (areaLoaded_[l][id]) return;
        areaLoaded_[l][id] = true;
        Area& a = doc_.scene.layers[l].areas[id];
        a = rows_.area(l, id);
        ++areas;
        for (const auto& loop : a.loops)
            for (const AreaEdge& e : loop) addCurve(l, e.curve, near);
        if (a.axial != kNoElement) addCurve(l, a.axial, near);
    }

    static Box hullBox(const Curve& c) {
        Box b{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
              {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
        for (const Vertex& v : c.vertices) {
            b.min = glm::min(b.min, v.p);
            b.max = glm::max(b.max, v.p);
        }
        return b;
    }

    void closeCurve(const Pending& p) {
        const Layer& layer = doc_.scene.layers[p.layer];
        // The layers' vectors were sized once (constructor): loading others never moves this one.
        const Curve& c = layer.curves[p.id];
        if (!c.alive) return;
        for (ElementId n : {c.start, c.end}) addNode(p.layer, n);
        if (p.near)
            for (ElementId n : {c.start, c.end})
                for (ElementId other : layer.nodes[n].curves) addCurve(p.layer, other, false);
        if (layer.kind == LayerKind::Roads && !c.vertices.empty()) {
            const Box box = hullBox(c).dilated(tolerance_);  // a feature's box may lie within the tolerance of its spline
            for (const FeatureTableRef& t : tables_) {
                const LayerKind kind = doc_.scene.layers[t.layer].kind;
                if (kind != LayerKind::Rivers && !(kind == LayerKind::Roads && (c.flags & kBridge))) continue;
                for (ElementId id : query(t, box)) {
                    if (t.polygons) addArea(t.layer, id, false);
                    else addCurve(t.layer, id, false);
                }
            }
        }
        if (layer.kind == LayerKind::Rivers)
            for (ElementId n : {c.start, c.end})
                for (ElementId other : layer.nodes[n].curves) {
                    if (other >= curveLoaded_[p.layer].size()) continue;
                    if (curveLoaded_[p.layer][other] || upstreamChecked_[p.layer][other]) continue;
                    upstreamChecked_[p.layer][other] = true;  // each curve's row read once for this test
                    if (rows_.curve(p.layer, other).end == n) addCurve(p.layer, other, false);  // flows into n
                }
    }

    SqliteDb& db_;
    SceneDocument& doc_;
    ElementRows rows_;
    std::vector<FeatureTableRef> tables_;
    double tolerance_ = 0.0;
    SceneRegionOptions filter_;
    std::vector<std::vector<bool>> nodeLoaded_, curveLoaded_, curveNear_, areaLoaded_, upstreamChecked_;
    std::deque<Pending> pending_;
};

}  // namespace

SceneDocument loadSceneRegion(const std::string& path, const Box& region, const RefineParams& params, int level,
                              SceneRegionStats* stats, const SceneRegionOptions& filter) {
    if (level < 0 || level > 30) throw std::invalid_argument("loadSceneRegion: level " + std::to_string(level) + " is not in 0..30");
    if (!(region.min.x <= region.max.x && region.min.y <= region.max.y))
        throw std::invalid_argument("loadSceneRegion: the region is empty");
    if (!(filter.minCurveWidth >= 0.0) || !std::isfinite(filter.minCurveWidth))
        throw std::invalid_argument("loadSceneRegion: SceneRegionOptions::minCurveWidth must be finite and >= 0");
    SceneRegionStats local;
    SceneRegionStats& st = stats ? *stats : local;
    st = {};
    bool indexed = false;
    SceneDocument doc;
    const auto readRegion = [&](SqliteDb& db, SceneDocument& d) {
        indexed = db.hasTable(kFeatureIndexTable);
        if (!indexed) {
            readElementTables(db, d);
            return;
        }
        // One read transaction: the file's shared lock taken once, not at each of the many
        // single-row statements below (per statement, SQLite locks and checks for a hot journal:
        // most of a small region's time). A read changes nothing: the end is a plain COMMIT.
        db.exec("BEGIN");
        struct End {
            SqliteDb& db;
            ~End() {
                try {
                    db.exec("COMMIT");
                } catch (...) {
                }
            }
        } end{db};
        readLayerTable(db, d.scene);
        std::vector<FeatureTableRef> tables;
        double curveWf = 0.0, areaWf = 0.0, tolerance = 0.0;
        {
            auto s = db.prepare(std::string("SELECT table_name, layer, polygons, tolerance, max_curve_wf, max_area_wf FROM ") +
                                kFeatureIndexTable + " ORDER BY table_name");
            while (s.step()) {
                const std::int64_t layer = s.integer(1);
                if (layer < 0 || std::size_t(layer) >= d.scene.layers.size() || !db.hasTable(s.text(0)) ||
                    !db.hasTable(featureRtreeName(s.text(0))))
                    throw FormatError(std::string(kFeatureIndexTable) + ": table '" + s.text(0) +
                                      "' has no layer, no table or no R-tree");
                const double tol = s.real(3), cw = s.real(4), aw = s.real(5);
                if (!(tol >= 0.0) || !(cw >= 0.0) || !(aw >= 0.0) || !std::isfinite(tol + cw + aw))
                    throw FormatError(std::string(kFeatureIndexTable) + ": table '" + s.text(0) + "' has a bad tolerance or wf");
                tables.push_back({s.text(0), LayerId(layer), s.integer(2) != 0});
                tolerance = std::max(tolerance, tol);
                curveWf = std::max(curveWf, cw);
                areaWf = std::max(areaWf, aw);
            }
        }
        const Vec2 extent = d.scene.extent.size();
        const double quadSize = std::max(extent.x, extent.y) / double(std::int64_t(1) << level);
        // The largest margin of any element at this quad size (a curve's delta is never above the
        // level's), plus the features' distance from their splines, plus a float's rounding.
        st.reach = std::max(params.curveMargin(std::numeric_limits<double>::max(), curveWf, quadSize),
                            params.areaMargin(areaWf, quadSize)) +
                   tolerance;
        // A roundabout's ring reaches its radius beyond the roads at its node.
        {
            auto s = db.prepare("SELECT max(roundabout) FROM lacet_nodes WHERE alive");
            const double radius = s.step() ? s.real(0) : 0.0;
            if (!(radius >= 0.0) || !std::isfinite(radius)) throw FormatError("lacet_nodes: a roundabout radius is not finite and >= 0");
            st.reach += radius;
        }
        st.reach += 1e-6 * std::max({1.0, std::fabs(region.min.x), std::fabs(region.max.x), std::fabs(region.min.y),
                                     std::fabs(region.max.y)});
        RegionLoader loader(db, d, std::move(tables), tolerance, filter);
        // The quads of the level that meet the region (closed boxes: a quad touching its border
        // counts), on the root's grid, then the reach around them.
        const double cells = double(std::int64_t(1) << level);
        const auto cell = [&](double v, double origin) { return std::clamp(std::floor((v - origin) / quadSize), 0.0, cells - 1.0); };
        const Vec2 origin = d.scene.extent.min;
        const Box quads{origin + Vec2(cell(region.min.x, origin.x), cell(region.min.y, origin.y)) * quadSize,
                        origin + (Vec2(cell(region.max.x, origin.x), cell(region.max.y, origin.y)) + 1.0) * quadSize};
        st.found = loader.findIn(quads.dilated(st.reach));
        loader.close();
        loader.closeAxialRivers();
        loader.trimLists();
        readAttributesOf(db, d, [&](const ElementAttribute& a) { return loader.loaded(a); });
        st.nodes = loader.nodes;
        st.curves = loader.curves;
        st.areas = loader.areas;
    };
    const std::string checksum = loadSceneParts(path, doc, readRegion, filter.dem, filter.wholeFileCheck);
    st.checksum = checksum;
    // Read whole: checked whole, as loadScene checks it.
    if (!indexed && filter.dem && sceneChecksumText(doc) != checksum)
        throw SceneFileError(path + ": corrupt file (its contents do not match their checksum)");
    st.wholeScene = !indexed;
    for (const Layer& l : doc.scene.layers) {
        st.sceneNodes += l.nodes.size();
        st.sceneCurves += l.curves.size();
        st.sceneAreas += l.areas.size();
        if (!indexed) {
            st.nodes += l.nodes.size();
            st.curves += l.curves.size();
            st.areas += l.areas.size();
        }
    }
    return doc;
}

Box loadSceneExtent(const std::string& path) {
    SceneDocument doc;
    loadSceneParts(path, doc, [](SqliteDb&, SceneDocument&) {}, /*readDem=*/false, /*wholeFileCheck=*/false);
    return doc.scene.extent;
}

}  // namespace lacet
