// The small reads of a scene file kept open or by path (io/scene_region.h): an element's box, the
// features a box meets, the extent, the outline.
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "io/scene_features.h"
#include "io/scene_format.h"
#include "io/scene_region.h"

namespace lacet {

using namespace scene_format;

Box loadSceneElementBox(const std::string& path, const ElementRef& ref, const SceneOverlay* overlay) {
    SceneFileConnection connection(path);
    return loadSceneElementBox(connection, ref, overlay);
}

Box loadSceneElementBox(SceneFileConnection& connection, const ElementRef& ref, const SceneOverlay* overlay) {
    SceneDocument doc;
    Box box;
    loadSceneParts(
        connection, doc,
        [&](SqliteDb& db, SceneDocument& d) {
            readLayerTable(db, d.scene);
            const std::string what = std::string(ref.kind == ElementKind::Node ? "node " : ref.kind == ElementKind::Curve ? "curve " : "area ") +
                                     std::to_string(ref.id) + " of layer " + std::to_string(ref.layer);
            if (ref.layer >= d.scene.layers.size()) throw FormatError(what + ": the file has no such layer");
            ElementRows rows(db);
            const auto value = [&](ElementKind kind, ElementId id) -> OverlayElement {
                if (overlay)
                    if (const OverlayElement* e = overlay->find({ref.layer, kind, id})) return *e;
                if (kind == ElementKind::Node) return {rows.node(ref.layer, id), {}};
                if (kind == ElementKind::Curve) return {rows.curve(ref.layer, id), {}};
                return {rows.area(ref.layer, id), {}};
            };
            const OverlayElement e = value(ref.kind, ref.id);
            if (const Node* n = std::get_if<Node>(&e.value)) {
                box = {n->p, n->p};
            } else if (const Curve* c = std::get_if<Curve>(&e.value)) {
                box = hullBox(*c);
            } else {
                box = {Vec2(std::numeric_limits<double>::infinity()), Vec2(-std::numeric_limits<double>::infinity())};
                for (const auto& loop : std::get<Area>(e.value).loops)
                    for (const AreaEdge& edge : loop) {
                        const Box b = hullBox(std::get<Curve>(value(ElementKind::Curve, edge.curve).value));
                        box = {glm::min(box.min, b.min), glm::max(box.max, b.max)};
                    }
            }
            if (!(box.min.x <= box.max.x && box.min.y <= box.max.y)) throw FormatError(what + " has no vertex");
        },
        /*readDem=*/false, /*wholeFileCheck=*/false);
    return box;
}

std::vector<ElementRef> loadSceneFeaturesIn(SceneFileConnection& connection, const Box& box, LayerKind kind,
                                            const SceneOverlay* overlay) {
    SceneDocument doc;
    std::vector<ElementRef> found;
    loadSceneParts(
        connection, doc,
        [&](SqliteDb& db, SceneDocument& d) {
            if (!db.hasTable(kFeatureIndexTable)) throw FormatError("the file has no feature index: save it again");
            const ReadTransaction transaction(db);
            readLayerTable(db, d.scene);
            const std::size_t n = d.scene.layers.size();
            FeatureIndex index = readFeatureIndex(db, d.scene);
            if (overlay) addOverlayTables(index.tables, *overlay, n);
            const std::vector<std::size_t> curves = fileIdCounts(db, "lacet_curves", n), areas = fileIdCounts(db, "lacet_areas", n);
            for (const FeatureTableRef& t : index.tables) {
                if (d.scene.layers[t.layer].kind != kind) continue;
                const ElementKind k = t.polygons ? ElementKind::Area : ElementKind::Curve;
                std::size_t count = (t.polygons ? areas : curves)[t.layer];
                if (overlay) overlay->forEach(t.layer, k, [&](ElementId id, const OverlayElement&) { count = std::max(count, std::size_t(id) + 1); });
                for (ElementId id : featuresIn(db, t, box, count, overlay)) found.push_back({t.layer, k, id});
            }
        },
        /*readDem=*/false, /*wholeFileCheck=*/false);
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
}

std::vector<std::size_t> loadSceneIdCounts(SceneFileConnection& connection, ElementKind kind) {
    SceneDocument doc;
    std::vector<std::size_t> counts;
    loadSceneParts(
        connection, doc,
        [&](SqliteDb& db, SceneDocument& d) {
            readLayerTable(db, d.scene);
            counts = fileIdCounts(db, kind == ElementKind::Node ? "lacet_nodes" : kind == ElementKind::Curve ? "lacet_curves" : "lacet_areas",
                                  d.scene.layers.size());
        },
        /*readDem=*/false, /*wholeFileCheck=*/false);
    return counts;
}

Box loadSceneExtent(const std::string& path) {
    SceneDocument doc;
    loadSceneParts(path, doc, [](SqliteDb&, SceneDocument&) {}, /*readDem=*/false, /*wholeFileCheck=*/false);
    return doc.scene.extent;
}

SceneOutline loadSceneOutline(const std::string& path) {
    SceneDocument doc;
    SceneOutline o;
    o.checksum = loadSceneParts(
        path, doc,
        [&](SqliteDb& db, SceneDocument& d) {
            readLayerTable(db, d.scene);
            for (const char* table : {"lacet_curves", "lacet_areas"})
                for (std::size_t count : fileIdCounts(db, table, d.scene.layers.size())) o.elements += count;
        },
        /*readDem=*/false, /*wholeFileCheck=*/false);
    o.extent = doc.scene.extent;
    return o;
}

}  // namespace lacet
