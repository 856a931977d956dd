#include "synth/random_edits.h"

#include "model/edits.h"

namespace lacet {
namespace {

std::size_t pick(std::mt19937_64& rng, std::size_t n) { return std::size_t(uniform01(rng) * double(n)) % n; }

Vec2 jitter(std::mt19937_64& rng, Vec2 p, double reach) {
    return p + Vec2((uniform01(rng) * 2.0 - 1.0) * reach, (uniform01(rng) * 2.0 - 1.0) * reach);
}

template <class T>
ElementId pickAlive(std::mt19937_64& rng, const std::vector<T>& v) {
    if (v.empty()) return kNoElement;
    for (int tries = 0; tries < 64; ++tries) {
        const auto id = ElementId(pick(rng, v.size()));
        if (v[id].alive) return id;
    }
    return kNoElement;
}

// A curve from node a to node b: a line, a quadratic or a cubic piece.
Curve makeCurve(std::mt19937_64& rng, const Layer& layer, ElementId a, ElementId b, double reach) {
    Curve c;
    c.start = a;
    c.end = b;
    const Vec2 pa = layer.nodes[a].p, pb = layer.nodes[b].p;
    c.vertices.push_back({pa});
    const int controls = int(pick(rng, 3));
    for (int k = 1; k <= controls; ++k)
        c.vertices.push_back({jitter(rng, pa + (pb - pa) * (double(k) / double(controls + 1)), reach * 0.3), false});
    c.vertices.push_back({pb});
    c.w = float(2.0 + uniform01(rng) * 8.0);
    c.wf = c.w + float(uniform01(rng) * 10.0);
    c.cls = std::uint16_t(pick(rng, 3));
    return c;
}

Changeset addSquareArea(Scene& s, LayerId l, std::mt19937_64& rng, double reach) {
    const Layer& layer = s.layers[l];
    Vec2 centre = s.extent.center();
    if (const ElementId n = pickAlive(rng, layer.nodes); n != kNoElement) centre = layer.nodes[n].p;
    centre = jitter(rng, centre, reach);
    const double r = reach * (0.1 + uniform01(rng) * 0.4);
    Changeset cs;
    ElementId nodes[4];
    const Vec2 corners[4] = {{-r, -r}, {r, -r}, {r, r}, {-r, r}};
    for (int k = 0; k < 4; ++k) cs.append(addNode(s, l, centre + corners[k], &nodes[k]));
    Area a;
    a.loops.emplace_back();
    for (int k = 0; k < 4; ++k) {
        ElementId id;
        cs.append(addCurve(s, l, makeCurve(rng, s.layers[l], nodes[k], nodes[(k + 1) % 4], r), &id));
        a.loops[0].push_back({id, false});
    }
    a.wf = float(uniform01(rng) * 10.0);
    a.cls = std::uint16_t(pick(rng, 4));
    cs.append(addArea(s, l, a));
    return cs;
}

Changeset tryEdit(Scene& s, EditKind kind, LayerId l, std::mt19937_64& rng, double reach) {
    Layer& layer = s.layers[l];
    const ElementId c = pickAlive(rng, layer.curves);
    switch (kind) {
        case EditKind::MoveVertex:
            if (c == kNoElement || layer.curves[c].vertices.size() < 3) return {};
            {
                const auto i = 1 + pick(rng, layer.curves[c].vertices.size() - 2);
                return moveVertex(s, l, c, i, jitter(rng, layer.curves[c].vertices[i].p, reach));
            }
        case EditKind::InsertVertex:
            if (c == kNoElement) return {};
            {
                const auto& v = layer.curves[c].vertices;
                const auto i = 1 + pick(rng, v.size() - 1);
                const Vertex x{jitter(rng, (v[i - 1].p + v[i].p) * 0.5, reach * 0.3), uniform01(rng) < 0.5};
                try {
                    return insertVertex(s, l, c, i, x);
                } catch (const EditError&) {
                    return insertVertex(s, l, c, i, Vertex{x.p, true});
                }
            }
        case EditKind::DeleteVertex:
            if (c == kNoElement || layer.curves[c].vertices.size() < 3) return {};
            try {
                return deleteVertex(s, l, c, 1 + pick(rng, layer.curves[c].vertices.size() - 2));
            } catch (const EditError&) {
                return {};
            }
        case EditKind::MoveNode:
            if (const ElementId n = pickAlive(rng, layer.nodes); n != kNoElement)
                return moveNode(s, l, n, jitter(rng, layer.nodes[n].p, reach));
            return {};
        case EditKind::AddNode: return addNode(s, l, jitter(rng, s.extent.center(), s.extent.size().x * 0.5));
        case EditKind::DeleteNode:
            for (int tries = 0; tries < 16; ++tries)
                if (const ElementId n = pickAlive(rng, layer.nodes); n != kNoElement && layer.nodes[n].curves.empty())
                    return deleteNode(s, l, n);
            return {};
        case EditKind::AddCurve: {
            const ElementId a = pickAlive(rng, layer.nodes);
            if (a == kNoElement) return {};
            ElementId b;
            Changeset cs = addNode(s, l, jitter(rng, layer.nodes[a].p, reach), &b);
            cs.append(addCurve(s, l, makeCurve(rng, s.layers[l], a, b, reach)));
            return cs;
        }
        case EditKind::DeleteCurve:
            if (c == kNoElement || !layer.curves[c].areas.empty()) return {};
            return deleteCurve(s, l, c);
        case EditKind::AddArea: return addSquareArea(s, l, rng, reach);
        case EditKind::DeleteArea:
            if (const ElementId a = pickAlive(rng, layer.areas); a != kNoElement) return deleteArea(s, l, a);
            return {};
        case EditKind::SetCurveWidth:
            if (c == kNoElement) return {};
            {
                const float w = float(uniform01(rng) * 12.0);
                return setCurveWidth(s, l, c, w, w + float(uniform01(rng) * 20.0));
            }
        case EditKind::SetCurveClass:
            if (c == kNoElement) return {};
            return setCurveClass(s, l, c, std::uint16_t(pick(rng, 4)));
        case EditKind::SetAreaClass:
            if (const ElementId a = pickAlive(rng, layer.areas); a != kNoElement)
                return setAreaClass(s, l, a, std::uint16_t(pick(rng, 6)));
            return {};
        case EditKind::SetAreaFootprint:
            if (const ElementId a = pickAlive(rng, layer.areas); a != kNoElement)
                return setAreaFootprint(s, l, a, float(uniform01(rng) * 30.0));
            return {};
        case EditKind::SetRoundabout: {
            if (layer.kind != LayerKind::Roads) return {};
            const ElementId n = pickAlive(rng, layer.nodes);
            if (n == kNoElement || layer.nodes[n].curves.empty()) return {};
            const float radius = layer.nodes[n].roundabout > 0.0f ? 0.0f : float(5.0 + uniform01(rng) * 25.0);
            try {
                return setNodeRoundabout(s, l, n, radius);
            } catch (const EditError&) {
                return {};  // does not fit: refused, nothing changed
            }
        }
        case EditKind::SetCurveFlags: {
            if (c == kNoElement || layer.kind != LayerKind::Roads) return {};
            static constexpr std::uint16_t choices[] = {0, kBridge, kTunnel, kNoBridge};
            return setCurveFlags(s, l, c, choices[pick(rng, 4)]);
        }
        case EditKind::Count: break;
    }
    return {};
}

}  // namespace

std::string_view toString(EditKind kind) {
    static constexpr std::string_view names[] = {
        "move_vertex", "insert_vertex", "delete_vertex", "move_node", "add_node", "delete_node", "add_curve",
        "delete_curve", "add_area", "delete_area", "set_curve_width", "set_curve_class", "set_area_class",
        "set_area_footprint", "set_roundabout", "set_curve_flags"};
    return names[std::size_t(kind)];
}

double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }

RandomEdit applyRandomEdit(Scene& scene, std::mt19937_64& rng, double reach) {
    RandomEdit e;
    if (scene.layers.empty()) return e;
    e.kind = EditKind(pick(rng, std::size_t(EditKind::Count)));
    const auto layer = LayerId(pick(rng, scene.layers.size()));
    e.changeset = tryEdit(scene, e.kind, layer, rng, reach);
    return e;
}

}  // namespace lacet
