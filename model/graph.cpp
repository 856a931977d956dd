#include "model/graph.h"

#include <iterator>
#include <limits>
#include <stdexcept>
#include <utility>

namespace lacet {

std::string_view toString(LayerKind kind) {
    switch (kind) {
        case LayerKind::Roads: return "roads";
        case LayerKind::Rivers: return "rivers";
        case LayerKind::Lakes: return "lakes";
        case LayerKind::Fields: return "fields";
        case LayerKind::Forests: return "forests";
        case LayerKind::Other: break;
    }
    return "other";
}

void Layer::refuseIfPart(const std::vector<ElementId>& fileIds, std::size_t count) const {
    if (isPart() && fileIds.size() != count + 1)
        throw std::logic_error("layer '" + name + "' is a part of a scene file's layer (a region read): it takes a new element only once its file id is named");
}

ElementId Layer::addNode(Vec2 p) {
    refuseIfPart(sceneIds.nodes, nodes.size());
    Node n;
    n.p = p;
    nodes.push_back(std::move(n));
    return ElementId(nodes.size() - 1);
}

ElementId Layer::addCurve(Curve c) {
    refuseIfPart(sceneIds.curves, curves.size());
    const auto id = ElementId(curves.size());
    nodes.at(c.start).curves.push_back(id);
    nodes.at(c.end).curves.push_back(id);
    curves.push_back(std::move(c));
    return id;
}

ElementId Layer::addArea(Area a) {
    refuseIfPart(sceneIds.areas, areas.size());
    const auto id = ElementId(areas.size());
    for (const auto& loop : a.loops)
        for (const auto& e : loop) {
            auto& list = curves.at(e.curve).areas;
            if (list.empty() || list.back() != id) list.push_back(id);
        }
    areas.push_back(std::move(a));
    return id;
}

void offsetElementIds(Layer& part, const ElementOffsets& o) {
    for (Node& n : part.nodes)
        for (ElementId& c : n.curves) c += o.curves;
    for (Curve& c : part.curves) {
        c.start += o.nodes;
        c.end += o.nodes;
        for (ElementId& a : c.areas) a += o.areas;
    }
    for (Area& a : part.areas) {
        for (auto& loop : a.loops)
            for (AreaEdge& e : loop) e.curve += o.curves;
        if (a.axial != kNoElement) a.axial += o.curves;
    }
}

void appendLayerPart(Layer& into, Layer&& part) {
    if (into.isPart() || part.isPart()) throw std::logic_error("appendLayerPart: a part of a scene file's layer (a region read) takes no new element");
    offsetElementIds(part, {ElementId(into.nodes.size()), ElementId(into.curves.size()), ElementId(into.areas.size())});
    const auto append = [](auto& to, auto& from) {
        if (to.empty()) {
            to = std::move(from);
            return;
        }
        to.insert(to.end(), std::make_move_iterator(from.begin()), std::make_move_iterator(from.end()));
    };
    append(into.nodes, part.nodes);
    append(into.curves, part.curves);
    append(into.areas, part.areas);
}

std::vector<Vertex> loopVertices(const Layer& layer, const std::vector<AreaEdge>& loop) {
    std::vector<Vertex> out;
    for (const auto& e : loop) {
        const auto& v = layer.curves[e.curve].vertices;
        const std::size_t n = v.size();
        for (std::size_t k = out.empty() ? 0 : 1; k < n; ++k) {
            Vertex x = v[e.reversed ? n - 1 - k : k];
            x.closing = false;
            out.push_back(x);
        }
    }
    return out;
}

SceneCounts count(const Scene& scene) {
    SceneCounts c;
    for (const auto& layer : scene.layers) {
        for (const auto& n : layer.nodes) c.nodes += n.alive;
        for (const auto& cv : layer.curves) {
            if (!cv.alive) continue;
            ++c.curves;
            c.vertices += cv.vertices.size();
            for (const auto& v : cv.vertices) c.controlPoints += !v.onCurve;
        }
        for (const auto& a : layer.areas) c.areas += a.alive;
    }
    return c;
}

namespace {
template <class T>
std::size_t heapBytes(const std::vector<T>& v) {
    return v.capacity() * sizeof(T);
}
}  // namespace

std::size_t memoryBytes(const Node& n) { return sizeof(Node) + heapBytes(n.curves); }
Box hullBox(const Curve& c) {
    Box b{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()},
          {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
    for (const Vertex& v : c.vertices) {
        b.min = glm::min(b.min, v.p);
        b.max = glm::max(b.max, v.p);
    }
    return b;
}

std::size_t memoryBytes(const Curve& c) { return sizeof(Curve) + heapBytes(c.vertices) + heapBytes(c.areas); }
std::size_t memoryBytes(const Area& a) {
    std::size_t b = sizeof(Area) + heapBytes(a.loops);
    for (const auto& loop : a.loops) b += heapBytes(loop);
    return b;
}

std::size_t memoryBytes(const Layer& layer) {
    std::size_t b = sizeof(Layer) + layer.name.capacity();
    for (const Node& n : layer.nodes) b += memoryBytes(n);
    for (const Curve& c : layer.curves) b += memoryBytes(c);
    for (const Area& a : layer.areas) b += memoryBytes(a);
    b += (layer.nodes.capacity() - layer.nodes.size()) * sizeof(Node) +
         (layer.curves.capacity() - layer.curves.size()) * sizeof(Curve) +
         (layer.areas.capacity() - layer.areas.size()) * sizeof(Area);
    const Layer::SceneIds& ids = layer.sceneIds;
    return b + heapBytes(ids.nodes) + heapBytes(ids.curves) + heapBytes(ids.areas);
}

std::size_t memoryBytes(const Scene& scene) {
    std::size_t b = sizeof(Scene) + (scene.layers.capacity() - scene.layers.size()) * sizeof(Layer);
    for (const Layer& l : scene.layers) b += memoryBytes(l);
    return b;
}

}  // namespace lacet
