#include "model/edits.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "model/roundabouts.h"
#include "model/validate.h"

namespace lacet {
namespace {

std::string name(const Scene& s, LayerId layer, const char* kind, ElementId id) {
    return "layer '" + s.layers[layer].name + "' " + kind + " " + std::to_string(id);
}

Layer& layerOf(Scene& s, LayerId layer) {
    if (layer >= s.layers.size()) throw EditError("no layer " + std::to_string(layer));
    return s.layers[layer];
}

Node& liveNode(Scene& s, LayerId layer, ElementId id) {
    Layer& l = layerOf(s, layer);
    if (id >= l.nodes.size() || !l.nodes[id].alive) throw EditError(name(s, layer, "node", id) + ": no such node");
    return l.nodes[id];
}

Curve& liveCurve(Scene& s, LayerId layer, ElementId id) {
    Layer& l = layerOf(s, layer);
    if (id >= l.curves.size() || !l.curves[id].alive) throw EditError(name(s, layer, "curve", id) + ": no such curve");
    return l.curves[id];
}

Area& liveArea(Scene& s, LayerId layer, ElementId id) {
    Layer& l = layerOf(s, layer);
    if (id >= l.areas.size() || !l.areas[id].alive) throw EditError(name(s, layer, "area", id) + ": no such area");
    return l.areas[id];
}

void requireFinite(const Scene& s, LayerId layer, const char* kind, ElementId id, Vec2 p) {
    if (!isFinite(p)) throw EditError(name(s, layer, kind, id) + ": position is not finite or beyond 1e9 m");
}

// The curve's geometry changed: the curve and the areas using it.
void curveChanged(Changeset& cs, const Curve& c, LayerId layer, ElementId id) {
    cs.modify({layer, ElementKind::Curve, id});
    for (ElementId a : c.areas) cs.modify({layer, ElementKind::Area, a});
}

// The curves of an area's loops, whose `areas` an added or deleted area changes: a river curve
// that becomes or stops being an area's border is bridged otherwise (model/graph_step.h), and drawn
// otherwise (a border, not a river).
void loopCurvesChanged(Changeset& cs, const Area& a, LayerId layer) {
    for (const auto& loop : a.loops)
        for (const auto& e : loop) cs.modify({layer, ElementKind::Curve, e.curve});
}

void endNodesChanged(Changeset& cs, const Curve& c, LayerId layer) {
    cs.modify({layer, ElementKind::Node, c.start});
    if (c.end != c.start) cs.modify({layer, ElementKind::Node, c.end});
}

Changeset done(Changeset cs) {
    cs.normalize();
    return cs;
}

void checkLoops(const Scene& s, LayerId layer, const Area& a) {
    const Layer& l = s.layers[layer];
    if (a.loops.empty()) throw EditError("layer '" + l.name + "' new area: no outer loop");
    if (!std::isfinite(a.wf) || a.wf < 0.0f) throw EditError("layer '" + l.name + "' new area: footprint width must be finite and >= 0");
    for (std::size_t li = 0; li < a.loops.size(); ++li) {
        const auto& loop = a.loops[li];
        if (loop.empty()) throw EditError("layer '" + l.name + "' new area: loop " + std::to_string(li) + " is empty");
        for (const auto& e : loop)
            if (e.curve >= l.curves.size() || !l.curves[e.curve].alive)
                throw EditError("layer '" + l.name + "' new area: loop " + std::to_string(li) + " refers to missing curve " +
                                std::to_string(e.curve));
        for (std::size_t k = 0; k < loop.size(); ++k) {
            const auto& e = loop[k];
            const auto& n = loop[(k + 1) % loop.size()];
            const Curve& c = l.curves[e.curve];
            const Curve& d = l.curves[n.curve];
            if ((e.reversed ? c.start : c.end) != (n.reversed ? d.end : d.start))
                throw EditError("layer '" + l.name + "' new area: loop " + std::to_string(li) + " is open after curve " +
                                std::to_string(e.curve));
        }
    }
}

}  // namespace

void Changeset::normalize() {
    for (auto* v : {&removed, &added}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
}

void Changeset::append(const Changeset& other) {
    removed.insert(removed.end(), other.removed.begin(), other.removed.end());
    added.insert(added.end(), other.added.begin(), other.added.end());
    normalize();
}

Changeset moveVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index, Vec2 p) {
    Curve& c = liveCurve(s, layer, curve);
    requireFinite(s, layer, "curve", curve, p);
    if (index == 0 || index + 1 >= c.vertices.size())
        throw EditError(name(s, layer, "curve", curve) + ": vertex " + std::to_string(index) +
                        " is an end vertex or out of range; move its node instead");
    c.vertices[index].p = p;
    Changeset cs;
    curveChanged(cs, c, layer, curve);
    return done(cs);
}

Changeset insertVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index, Vertex v) {
    Curve& c = liveCurve(s, layer, curve);
    requireFinite(s, layer, "curve", curve, v.p);
    if (index == 0 || index >= c.vertices.size())
        throw EditError(name(s, layer, "curve", curve) + ": cannot insert before vertex " + std::to_string(index));
    auto vertices = c.vertices;
    v.closing = false;
    vertices.insert(vertices.begin() + std::ptrdiff_t(index), v);
    if (auto reason = splineProblem(vertices); !reason.empty())
        throw EditError(name(s, layer, "curve", curve) + ": inserting vertex " + std::to_string(index) + " " + reason);
    c.vertices = std::move(vertices);
    Changeset cs;
    curveChanged(cs, c, layer, curve);
    return done(cs);
}

Changeset deleteVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index) {
    Curve& c = liveCurve(s, layer, curve);
    if (index == 0 || index + 1 >= c.vertices.size())
        throw EditError(name(s, layer, "curve", curve) + ": vertex " + std::to_string(index) +
                        " is an end vertex or out of range");
    auto vertices = c.vertices;
    vertices.erase(vertices.begin() + std::ptrdiff_t(index));
    if (auto reason = splineProblem(vertices); !reason.empty())
        throw EditError(name(s, layer, "curve", curve) + ": deleting vertex " + std::to_string(index) + " " + reason);
    c.vertices = std::move(vertices);
    Changeset cs;
    curveChanged(cs, c, layer, curve);
    return done(cs);
}

Changeset moveNode(Scene& s, LayerId layer, ElementId node, Vec2 p) {
    Node& n = liveNode(s, layer, node);
    requireFinite(s, layer, "node", node, p);
    n.p = p;
    Changeset cs;
    cs.modify({layer, ElementKind::Node, node});
    for (ElementId id : n.curves) {
        Curve& c = s.layers[layer].curves[id];
        if (c.start == node) c.vertices.front().p = p;
        if (c.end == node) c.vertices.back().p = p;
        curveChanged(cs, c, layer, id);
    }
    return done(cs);
}

Changeset addNode(Scene& s, LayerId layer, Vec2 p, ElementId* id) {
    Layer& l = layerOf(s, layer);
    requireFinite(s, layer, "node", ElementId(l.nodes.size()), p);
    const ElementId nid = l.addNode(p);
    if (id) *id = nid;
    Changeset cs;
    cs.added.push_back({layer, ElementKind::Node, nid});
    return cs;
}

Changeset deleteNode(Scene& s, LayerId layer, ElementId node) {
    Node& n = liveNode(s, layer, node);
    if (!n.curves.empty())
        throw EditError(name(s, layer, "node", node) + ": still has " + std::to_string(n.curves.size()) + " curve(s)");
    n.alive = false;
    Changeset cs;
    cs.removed.push_back({layer, ElementKind::Node, node});
    return cs;
}

Changeset addCurve(Scene& s, LayerId layer, Curve c, ElementId* id) {
    Layer& l = layerOf(s, layer);
    const auto nid = ElementId(l.curves.size());
    if (auto reason = splineProblem(c.vertices); !reason.empty()) throw EditError(name(s, layer, "curve", nid) + ": " + reason);
    if (!std::isfinite(c.w) || !std::isfinite(c.wf) || c.w < 0.0f || c.wf < c.w)
        throw EditError(name(s, layer, "curve", nid) + ": widths must be finite with 0 <= w <= wf");
    const Node& a = liveNode(s, layer, c.start);
    const Node& b = liveNode(s, layer, c.end);
    if (c.vertices.front().p != a.p || c.vertices.back().p != b.p)
        throw EditError(name(s, layer, "curve", nid) + ": end vertices must lie on the start and end nodes");
    for (auto& v : c.vertices) v.closing = false;
    c.areas.clear();
    c.alive = true;
    const ElementId cid = l.addCurve(std::move(c));
    if (id) *id = cid;
    Changeset cs;
    cs.added.push_back({layer, ElementKind::Curve, cid});
    endNodesChanged(cs, l.curves[cid], layer);
    return done(cs);
}

Changeset deleteCurve(Scene& s, LayerId layer, ElementId curve) {
    Curve& c = liveCurve(s, layer, curve);
    if (!c.areas.empty())
        throw EditError(name(s, layer, "curve", curve) + ": used by area " + std::to_string(c.areas.front()) +
                        "; delete the area first");
    Layer& l = s.layers[layer];
    for (std::size_t a = 0; a < l.areas.size(); ++a)
        if (l.areas[a].alive && l.areas[a].axial == curve)
            throw EditError(name(s, layer, "curve", curve) + ": axial curve of area " + std::to_string(a) +
                            "; delete the area first");
    for (ElementId n : {c.start, c.end}) {
        auto& list = l.nodes[n].curves;
        if (auto it = std::find(list.begin(), list.end(), curve); it != list.end()) list.erase(it);
    }
    c.alive = false;
    Changeset cs;
    cs.removed.push_back({layer, ElementKind::Curve, curve});
    endNodesChanged(cs, c, layer);
    return done(cs);
}

Changeset addArea(Scene& s, LayerId layer, Area a, ElementId* id) {
    Layer& l = layerOf(s, layer);
    checkLoops(s, layer, a);
    if (a.axial != kNoElement && (a.axial >= l.curves.size() || !l.curves[a.axial].alive))
        throw EditError("layer '" + l.name + "' new area: axial curve " + std::to_string(a.axial) + " does not exist");
    a.alive = true;
    const ElementId aid = l.addArea(std::move(a));
    if (id) *id = aid;
    Changeset cs;
    cs.added.push_back({layer, ElementKind::Area, aid});
    loopCurvesChanged(cs, l.areas[aid], layer);
    return done(cs);
}

Changeset deleteArea(Scene& s, LayerId layer, ElementId area) {
    Area& a = liveArea(s, layer, area);
    Layer& l = s.layers[layer];
    for (const auto& loop : a.loops)
        for (const auto& e : loop) {
            auto& list = l.curves[e.curve].areas;
            list.erase(std::remove(list.begin(), list.end(), area), list.end());
        }
    a.alive = false;
    Changeset cs;
    cs.removed.push_back({layer, ElementKind::Area, area});
    loopCurvesChanged(cs, a, layer);
    return done(cs);
}

Changeset setCurveWidth(Scene& s, LayerId layer, ElementId curve, float w, float wf) {
    Curve& c = liveCurve(s, layer, curve);
    if (!std::isfinite(w) || !std::isfinite(wf) || w < 0.0f || wf < w)
        throw EditError(name(s, layer, "curve", curve) + ": widths must be finite with 0 <= w <= wf");
    c.w = w;
    c.wf = wf;
    Changeset cs;
    curveChanged(cs, c, layer, curve);
    endNodesChanged(cs, c, layer);
    return done(cs);
}

Changeset setCurveClass(Scene& s, LayerId layer, ElementId curve, std::uint16_t cls) {
    Curve& c = liveCurve(s, layer, curve);
    c.cls = cls;
    Changeset cs;
    cs.modify({layer, ElementKind::Curve, curve});
    endNodesChanged(cs, c, layer);
    return done(cs);
}

Changeset setCurveFlags(Scene& s, LayerId layer, ElementId curve, std::uint16_t flags) {
    Curve& c = liveCurve(s, layer, curve);
    c.flags = flags;
    Changeset cs;
    cs.modify({layer, ElementKind::Curve, curve});
    return done(cs);
}

Changeset setAreaClass(Scene& s, LayerId layer, ElementId area, std::uint16_t cls) {
    liveArea(s, layer, area).cls = cls;
    Changeset cs;
    cs.modify({layer, ElementKind::Area, area});
    return cs;
}

Changeset setAreaFootprint(Scene& s, LayerId layer, ElementId area, float wf) {
    Area& a = liveArea(s, layer, area);
    if (!std::isfinite(wf) || wf < 0.0f) throw EditError(name(s, layer, "area", area) + ": footprint width must be finite and >= 0");
    a.wf = wf;
    Changeset cs;
    cs.modify({layer, ElementKind::Area, area});
    return cs;
}

Changeset setNodeRoundabout(Scene& s, LayerId layer, ElementId node, float radius) {
    Node& n = liveNode(s, layer, node);
    if (auto reason = roundaboutRefusal(s, layer, node, radius)) throw EditError(name(s, layer, "node", node) + ": " + *reason);
    n.roundabout = radius == 0.0f ? 0.0f : radius;  // -0 as 0, as the scene file keeps it
    Changeset cs;
    cs.modify({layer, ElementKind::Node, node});
    for (ElementId id : n.curves) cs.modify({layer, ElementKind::Curve, id});
    return done(cs);
}

}  // namespace lacet
