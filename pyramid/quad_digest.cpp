#include "pyramid/quad_digest.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "io/digest.h"
#include "raster/elevation_producer.h"

namespace lacet {
namespace {

void vertices(Digest& d, const std::vector<Vertex>& vs) {
    d.word(vs.size());
    for (const Vertex& v : vs) d.real(v.p.x).real(v.p.y).word(std::uint64_t(v.onCurve) | std::uint64_t(v.closing) << 1);
}

template <class Map>
std::vector<typename Map::key_type> sortedKeys(const Map& m) {
    std::vector<typename Map::key_type> keys;
    keys.reserve(m.size());
    for (const auto& kv : m) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());
    return keys;
}

// Looks `key` up in `map`, computing it outside the lock when missing.
template <class Key, class Compute>
std::uint64_t cached(std::mutex& mutex, std::unordered_map<Key, std::uint64_t>& map, Key key, Compute&& compute) {
    {
        std::lock_guard lock(mutex);
        if (auto it = map.find(key); it != map.end()) return it->second;
    }
    const std::uint64_t v = compute();
    std::lock_guard lock(mutex);
    map.emplace(key, v);
    return v;
}

}  // namespace

QuadDigests::QuadDigests(const Quadtree& quadtree, const CurveDataCache& curveData)
    : qt_(quadtree),
      data_(curveData),
      curves_(quadtree.scene().layers.size()),
      areas_(quadtree.scene().layers.size()),
      nodes_(quadtree.scene().layers.size()) {}

std::uint64_t QuadDigests::curve(LayerId layer, AncestorId id) const {
    return cached(mutex_, curves_[layer], id, [&] { return computeCurve(layer, id); });
}
std::uint64_t QuadDigests::area(LayerId layer, ElementId id) const {
    return cached(mutex_, areas_[layer], AncestorId(id), [&] { return computeArea(layer, id); });
}
std::uint64_t QuadDigests::node(LayerId layer, ElementId id) const {
    return cached(mutex_, nodes_[layer], AncestorId(id), [&] { return computeNode(layer, id); });
}

std::uint64_t QuadDigests::computeNode(LayerId layer, ElementId id) const {
    const Layer& l = qt_.scene().layers[layer];
    Digest d;
    d.word(l.sceneNodeId(id));
    if (id == kNoElement || id >= l.nodes.size() || !l.nodes[id].alive) return d.word(0xDEAD).value();
    const Node& n = l.nodes[id];
    d.real(n.p.x).real(n.p.y).real(n.roundabout).word(n.curves.size());
    // Stop lines and junction radii (model/junctions.h) read every curve at the node: its width,
    // and where 3 meet the direction it leaves the node in, towards its first vertex that differs
    // from the node.
    const auto leaving = [&](const Curve& cv, bool atStart) {
        const std::size_t count = cv.vertices.size();
        const Vec2 origin = atStart ? cv.vertices.front().p : cv.vertices.back().p;
        for (std::size_t k = 1; k < count; ++k) {
            const Vec2 p = atStart ? cv.vertices[k].p : cv.vertices[count - 1 - k].p;
            if (p != origin) return glm::normalize(p - origin);  // as model/junctions.cpp
        }
        return Vec2(0.0);
    };
    for (ElementId c : n.curves) {
        d.word(l.sceneCurveId(c));
        if (c >= l.curves.size() || l.curves[c].vertices.empty()) continue;
        const Curve& cv = l.curves[c];
        d.word(l.sceneNodeId(cv.start)).word(l.sceneNodeId(cv.end)).real(cv.w).real(cv.wf).word(cv.cls).word(cv.flags);
        if (n.curves.size() != 3) continue;  // directions decide stop lines only where 3 curves meet
        const Vec2 a = leaving(cv, true), b = leaving(cv, false);
        d.real(a.x).real(a.y).real(b.x).real(b.y);
    }
    return d.value();
}

std::uint64_t QuadDigests::computeCurve(LayerId layer, AncestorId id) const {
    const Curve& c = qt_.ancestorCurve(layer, id);
    const Layer& l = qt_.scene().layers[layer];
    const LayerKind kind = l.kind;
    Digest d;  // ids as the scene file has them (a region read holds a part of it)
    d.word(sceneAncestorId(l, id)).word(l.sceneNodeId(c.start)).word(l.sceneNodeId(c.end));
    d.real(c.w).real(c.wf).word(c.cls).word(c.flags).word(c.areas.size());
    for (ElementId a : c.areas) d.word(l.sceneAreaId(a));
    vertices(d, c.vertices);
    if (const ProceduralCurve* pc = qt_.proceduralCurve(layer, id)) {
        d.real(pc->rootS0).real(pc->rootS1).word(l.sceneNodeId(pc->ringAtStart)).word(l.sceneNodeId(pc->ringAtEnd));
        d.word(pc->spans.size());
        for (const BridgeSpan& s : pc->spans)
            d.word(s.layer).word(sceneAncestorId(qt_.scene().layers[s.layer], s.over)).real(s.overS).real(s.u).real(s.halfLength);
        d.word(node(layer, pc->ringAtStart)).word(node(layer, pc->ringAtEnd));
    }
    d.word(node(layer, c.start)).word(node(layer, c.end));
    // The computed z-profile sums up what the curve's heights depend on beyond its own shape.
    if (kind == LayerKind::Roads || kind == LayerKind::Rivers) {
        const ZProfile& z = data_.zProfile(layer, id);
        d.real(z.length).real(z.spacing).reals(std::span<const double>(z.z));
    }
    return d.value();
}

std::uint64_t QuadDigests::computeArea(LayerId layer, ElementId id) const {
    const Layer& l = qt_.scene().layers[layer];
    const Area& a = l.areas[id];
    Digest d;
    d.word(l.sceneAreaId(id)).real(a.wf).word(a.cls).word(l.sceneCurveId(a.axial)).word(a.loops.size());
    for (const auto& loop : a.loops) {
        d.word(loop.size());
        for (const AreaEdge& e : loop) {
            d.word(l.sceneCurveId(e.curve)).word(e.reversed);
            if (e.curve < l.curves.size()) vertices(d, l.curves[e.curve].vertices);
        }
    }
    if (l.kind == LayerKind::Lakes || (l.kind == LayerKind::Rivers && a.axial == kNoElement)) d.real(data_.lakeLevel(layer, id));
    if (l.kind == LayerKind::Rivers && a.axial != kNoElement) {  // the river its water follows through it
        const AxialRiver river = axialRiver(l, a);
        d.word(river.curves.size());
        for (ElementId c : river.curves) d.word(l.sceneCurveId(c)).word(curve(layer, AncestorId(c)));
    }
    return d.value();
}

std::uint64_t QuadDigests::of(const Quad& quad, QuadDigestScope scope) const {
    const bool elevationOnly = scope == QuadDigestScope::Elevation;
    const double delta = quad.bounds.size().x / double(qt_.params().grid().elevationResolution);
    Digest d;
    d.word(std::uint64_t(quad.level)).word(quad.tx).word(quad.ty).word(quad.layers.size()).word(std::uint64_t(scope));
    for (LayerId l = 0; l < quad.layers.size(); ++l) {
        const QuadLayer& ql = quad.layers[l];
        const Layer& layer = qt_.scene().layers[l];
        const LayerKind kind = layer.kind;
        d.word(0xC0FFEE);
        std::vector<AncestorId> curves = sortedKeys(ql.curves);
        if (elevationOnly)  // as the elevation producer draws them: roads and rivers, not on structures, >= 2 samples wide
            std::erase_if(curves, [&](AncestorId a) {
                const Curve& c = qt_.ancestorCurve(l, a);
                return (kind != LayerKind::Roads && kind != LayerKind::Rivers) || (c.flags & (kBridge | kTunnel)) ||
                       double(c.w) < 2.0 * delta;
            });
        d.word(curves.size());
        for (AncestorId a : curves) {
            d.word(sceneAncestorId(layer, a)).word(curve(l, a));
            const auto& pieces = ql.curves.at(a);
            d.word(pieces.size());
            for (const ClippedCurve& p : pieces) {
                vertices(d, p.vertices);
                d.reals(std::span<const double>(p.s)).word(p.startsAtNode).word(p.endsAtNode);
            }
        }
        std::vector<ElementId> areas = sortedKeys(ql.areas);
        if (elevationOnly && kind != LayerKind::Lakes && kind != LayerKind::Rivers) areas.clear();
        d.word(areas.size());
        for (ElementId a : areas) {
            d.word(layer.sceneAreaId(a)).word(area(l, a));
            const auto& pieces = ql.areas.at(a);
            d.word(pieces.size());
            for (const ClippedArea& p : pieces) {
                d.word(p.coversQuad).word(p.loops.size());
                for (const ClippedLoop& loop : p.loops) {
                    d.word(loop.hole);
                    vertices(d, loop.vertices);
                }
            }
        }
        if (elevationOnly) continue;  // the elevation producer reads no node
        d.word(ql.nodes.size());
        for (ElementId n : sortedKeys(ql.nodes)) {
            const Vec2 p = ql.nodes.at(n);
            d.word(layer.sceneNodeId(n)).real(p.x).real(p.y).word(node(l, n));
        }
    }
    return d.value();
}

}  // namespace lacet
