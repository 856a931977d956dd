#include "io/scene_overlay.h"

#include <algorithm>
#include <variant>

#include "io/scene_features.h"

namespace lacet {

ElementRef fileRef(const Layer& layer, LayerId l, ElementKind kind, ElementId id) {
    const ElementId file = kind == ElementKind::Node    ? layer.sceneNodeId(id)
                           : kind == ElementKind::Curve ? layer.sceneCurveId(id)
                                                        : layer.sceneAreaId(id);
    return {l, kind, file};
}

ElementId localIdOf(const Layer& layer, ElementKind kind, ElementId file) {
    const std::size_t count = kind == ElementKind::Node ? layer.nodes.size() : kind == ElementKind::Curve ? layer.curves.size() : layer.areas.size();
    if (!layer.isPart()) return file < count ? file : kNoElement;
    const Layer::SceneIds& ids = layer.sceneIds;
    const std::vector<ElementId>& of = kind == ElementKind::Node ? ids.nodes : kind == ElementKind::Curve ? ids.curves : ids.areas;
    const auto it = std::lower_bound(of.begin(), of.end(), file);
    return it != of.end() && *it == file ? ElementId(it - of.begin()) : kNoElement;
}

OverlayElement overlayValue(const Layer& layer, Node n) {
    for (ElementId& c : n.curves) c = layer.sceneCurveId(c);
    return {std::move(n), std::nullopt};
}

OverlayElement overlayValue(const Layer& layer, Curve c, double tolerance) {
    std::optional<Box> box = featureBox(layer, c, tolerance);
    if (c.start != kNoElement) c.start = layer.sceneNodeId(c.start);
    if (c.end != kNoElement) c.end = layer.sceneNodeId(c.end);
    for (ElementId& a : c.areas) a = layer.sceneAreaId(a);
    return {std::move(c), box};
}

OverlayElement overlayValue(const Layer& layer, Area a, double tolerance) {
    std::optional<Box> box = featureBox(layer, a, tolerance);
    for (auto& loop : a.loops)
        for (AreaEdge& edge : loop) edge.curve = layer.sceneCurveId(edge.curve);
    if (a.axial != kNoElement) a.axial = layer.sceneCurveId(a.axial);
    return {std::move(a), box};
}

OverlayElement absentElement(ElementKind kind) {
    OverlayElement e{Node{}, std::nullopt, true};
    if (kind == ElementKind::Curve) e.value = Curve{};
    if (kind == ElementKind::Area) e.value = Area{};
    std::visit([](auto& v) { v.alive = false; }, e.value);
    return e;
}

OverlayElement overlayElement(const Layer& layer, ElementKind kind, ElementId id, double tolerance) {
    switch (kind) {
    case ElementKind::Node:
        return overlayValue(layer, layer.nodes.at(id));
    case ElementKind::Curve:
        return overlayValue(layer, layer.curves.at(id), tolerance);
    case ElementKind::Area:
        break;
    }
    return overlayValue(layer, layer.areas.at(id), tolerance);
}

}  // namespace lacet
