// The feature tables as reads of parts of the scene file find them (io/scene_format.h): their
// list, the features a box meets through their R-trees with the edits, the file's id counts.
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/scene_features.h"
#include "io/scene_format.h"
#include "io/scene_overlay.h"

namespace lacet::scene_format {

// Each of `layers` layers' ids in the element table `table`: its largest id + 1, through the
// (layer, id) index, not a scan of the table.
std::vector<std::size_t> fileIdCounts(SqliteDb& db, const char* table, std::size_t layers) {
    std::vector<std::size_t> counts(layers, 0);
    auto s = db.prepare(std::string("SELECT max(id) + 1 FROM ") + table + " WHERE layer = ?");
    for (std::size_t layer = 0; layer < layers; ++layer) {
        s.reset();
        s.bind(1, std::int64_t(layer));
        const std::int64_t count = s.step() && s.type(0) != SQLITE_NULL ? s.integer(0) : 0;
        if (count < 0 || count > kMaxId + 1) throw FormatError(std::string(table) + ": layer " + std::to_string(layer) + ": ids out of range");
        counts[layer] = std::size_t(count);
    }
    return counts;
}

FeatureIndex readFeatureIndex(SqliteDb& db, const Scene& scene) {
    FeatureIndex index;
    auto s = db.prepare(std::string("SELECT table_name, layer, polygons, tolerance, max_curve_wf, max_area_wf FROM ") + kFeatureIndexTable +
                        " ORDER BY table_name");
    while (s.step()) {
        const std::int64_t layer = s.integer(1);
        if (layer < 0 || std::size_t(layer) >= scene.layers.size() || !db.hasTable(s.text(0)) || !db.hasTable(featureRtreeName(s.text(0))))
            throw FormatError(std::string(kFeatureIndexTable) + ": table '" + s.text(0) + "' has no layer, no table or no R-tree");
        const double tol = s.real(3), cw = s.real(4), aw = s.real(5);
        if (!(tol >= 0.0) || !(cw >= 0.0) || !(aw >= 0.0) || !std::isfinite(tol + cw + aw))
            throw FormatError(std::string(kFeatureIndexTable) + ": table '" + s.text(0) + "' has a bad tolerance or wf");
        index.tables.push_back({s.text(0), LayerId(layer), s.integer(2) != 0});
        index.tolerance = std::max(index.tolerance, tol);
        index.curveWf = std::max(index.curveWf, cw);
        index.areaWf = std::max(index.areaWf, aw);
    }
    return index;
}

// The tables of the layers' features the file has none for and the edits add (name empty): found
// in the overlay alone. Throws FormatError for an edit of a layer the file has not.
void addOverlayTables(std::vector<FeatureTableRef>& tables, const SceneOverlay& overlay, std::size_t layers) {
    for (const auto& [ref, e] : overlay.elements) {
        if (ref.layer >= layers) throw FormatError("the edits name layer " + std::to_string(ref.layer) + ", which the file has not");
        if (ref.kind == ElementKind::Node) continue;
        const bool polygons = ref.kind == ElementKind::Area;
        const LayerId layer = ref.layer;  // a structured binding is not captured by clang 14
        if (std::none_of(tables.begin(), tables.end(), [&](const FeatureTableRef& t) { return t.layer == layer && t.polygons == polygons; }))
            tables.push_back({std::string(), layer, polygons});
    }
}

// The features of table `t` whose boxes meet `box` (their ids, below `count`): the file's R-tree's,
// except those `overlay` (nullptr: none) changed, found by their boxes now.
std::vector<ElementId> featuresIn(SqliteDb& db, const FeatureTableRef& t, const Box& box, std::size_t count, const SceneOverlay* overlay) {
    const ElementKind kind = t.polygons ? ElementKind::Area : ElementKind::Curve;
    std::vector<ElementId> ids;
    if (!t.name.empty()) {
        auto s = db.prepare("SELECT lacet_id FROM \"" + t.name + "\" WHERE fid IN (SELECT id FROM \"" + featureRtreeName(t.name) +
                            "\" WHERE minx <= ? AND maxx >= ? AND miny <= ? AND maxy >= ?)");
        s.bind(1, box.max.x);
        s.bind(2, box.min.x);
        s.bind(3, box.max.y);
        s.bind(4, box.min.y);
        while (s.step()) {
            const std::int64_t id = s.integer(0);
            if (id < 0 || std::size_t(id) >= count)
                throw FormatError("feature table '" + t.name + "': lacet_id " + std::to_string(id) + " names no element");
            ids.push_back(ElementId(id));
        }
    }
    if (overlay) {
        std::erase_if(ids, [&](ElementId id) { return overlay->find({t.layer, kind, id}) != nullptr; });
        overlay->forEach(t.layer, kind, [&](ElementId id, const OverlayElement& e) {
            if (e.box && e.box->intersects(box)) ids.push_back(id);
        });
    }
    return ids;
}

}  // namespace lacet::scene_format
