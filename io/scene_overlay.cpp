#include "io/scene_overlay.h"

#include "io/scene_features.h"

namespace lacet {

ElementRef fileRef(const Layer& layer, LayerId l, ElementKind kind, ElementId id) {
    const ElementId file = kind == ElementKind::Node    ? layer.sceneNodeId(id)
                           : kind == ElementKind::Curve ? layer.sceneCurveId(id)
                                                        : layer.sceneAreaId(id);
    return {l, kind, file};
}

OverlayElement overlayElement(const Layer& layer, ElementKind kind, ElementId id, double tolerance) {
    OverlayElement e;
    switch (kind) {
    case ElementKind::Node: {
        Node n = layer.nodes.at(id);
        for (ElementId& c : n.curves) c = layer.sceneCurveId(c);
        e.value = std::move(n);
        break;
    }
    case ElementKind::Curve: {
        const Curve& local = layer.curves.at(id);
        e.box = featureBox(layer, local, tolerance);
        Curve c = local;
        if (c.start != kNoElement) c.start = layer.sceneNodeId(c.start);
        if (c.end != kNoElement) c.end = layer.sceneNodeId(c.end);
        for (ElementId& a : c.areas) a = layer.sceneAreaId(a);
        e.value = std::move(c);
        break;
    }
    case ElementKind::Area: {
        const Area& local = layer.areas.at(id);
        e.box = featureBox(layer, local, tolerance);
        Area a = local;
        for (auto& loop : a.loops)
            for (AreaEdge& edge : loop) edge.curve = layer.sceneCurveId(edge.curve);
        if (a.axial != kNoElement) a.axial = layer.sceneCurveId(a.axial);
        e.value = std::move(a);
        break;
    }
    }
    return e;
}

}  // namespace lacet
