#include "model/roundabouts.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include <glm/geometric.hpp>

namespace lacet {
namespace {

// Depth of the halving search for the first exit from the circle: sub-pieces of 2^-16 of a piece
// whose control polygon crosses the circle are decided by their end point (an excursion out of
// the circle and back within one of them is not seen).
constexpr int kExitSearchDepth = 16;
// Largest angle of one cubic piece of a ring arc (radians): the k = 4/3 tan(θ/4) cubic is within
// 2.7e-4 r of the circle at 90 degrees.
constexpr double kMaxArcPieceAngle = std::numbers::pi / 2.0;

// One end of a road at a ring: where it crosses the circle first, coming from the node.
struct Entry {
    ElementId curve = kNoElement;
    bool atStart = true;   // the road's start (true) or end (false) is at the node
    double s = 0.0;        // root parameter of the crossing (on-curve vertex k at s = k)
    Vec2 p{0.0};           // the crossing: the trimmed road's end and the arcs' end there
    double angle = 0.0;    // of p around the node, radians in (-pi, pi]
};

// The curve's pieces (global coordinates), in order.
std::vector<BezierPiece> piecesOf(const Curve& c) {
    std::vector<BezierPiece> out;
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) { out.push_back(b); });
    return out;
}

bool insideLocal(Vec2 q, double r2) { return glm::dot(q, q) < r2; }

// The first t of `local` (the piece translated so that the node is the origin, t0..t1 of the
// original piece) where it reaches the circle of squared radius r2, given that its start is
// inside. Halving with the convex hull: a sub-piece whose controls are all inside is inside.
std::optional<std::pair<double, double>> firstExitBracket(const BezierPiece& local, double r2, double t0, double t1,
                                                          int depth) {
    bool allInside = true;
    for (int i = 0; i <= local.degree; ++i) allInside = allInside && insideLocal(local.p[i], r2);
    if (allInside) return std::nullopt;
    if (depth >= kExitSearchDepth) {
        if (insideLocal(local.end(), r2)) return std::nullopt;
        return std::pair{t0, t1};
    }
    const auto [l, r] = splitHalf(local);
    const double tm = 0.5 * (t0 + t1);
    if (auto b = firstExitBracket(l, r2, t0, tm, depth + 1)) return b;
    return firstExitBracket(r, r2, tm, t1, depth + 1);
}

// Bisection of [lo, hi] (lo inside, hi outside or on the circle) until the bracket cannot shrink
// in double precision; returns hi, the first parameter found at or outside the circle.
double bisectExit(const BezierPiece& local, double r2, double lo, double hi) {
    for (;;) {
        const double mid = 0.5 * (lo + hi);
        if (!(mid > lo && mid < hi)) return hi;
        if (insideLocal(evaluate(local, mid), r2)) lo = mid;
        else hi = mid;
    }
}

BezierPiece translated(const BezierPiece& b, Vec2 origin) {
    BezierPiece out = b;
    for (int i = 0; i <= b.degree; ++i) out.p[i] = b.p[i] - origin;
    return out;
}

// Where curve `c` first crosses the circle of `radius` around `centre`, walking from its start
// (atStart) or from its end; nullopt when it never leaves the circle.
std::optional<Entry> firstCrossing(const Curve& c, ElementId id, bool atStart, Vec2 centre, double radius) {
    const std::vector<BezierPiece> pieces = piecesOf(c);
    const double r2 = radius * radius;
    const std::size_t n = pieces.size();
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = atStart ? i : n - 1 - i;
        // Walking from the end, the piece is searched reversed: t' = 1 - t.
        const BezierPiece walked = atStart ? pieces[k] : pieces[k].reversed();
        const BezierPiece local = translated(walked, centre);
        const auto bracket = firstExitBracket(local, r2, 0.0, 1.0, 0);
        if (!bracket) continue;
        const double tw = bisectExit(local, r2, bracket->first, bracket->second);
        Entry e;
        e.curve = id;
        e.atStart = atStart;
        e.s = double(k) + (atStart ? tw : 1.0 - tw);
        // The point at the parameter as the trimmed road's sub-spline will see it (t = s - k), in
        // global coordinates, so that the road and the arc end at the same point.
        const double t = std::min(1.0, std::max(0.0, e.s - double(k)));
        e.p = evaluate(pieces[k], t);
        const Vec2 d = e.p - centre;
        e.angle = std::atan2(d.y, d.x);
        return e;
    }
    return std::nullopt;
}

// The curve ends at `node`, each once (a closed curve at the node gives two), in node.curves order.
std::vector<std::pair<ElementId, bool>> endsAt(const Layer& layer, ElementId node) {
    std::vector<std::pair<ElementId, bool>> ends;
    for (ElementId id : layer.nodes[node].curves) {
        if (id >= layer.curves.size() || !layer.curves[id].alive) continue;
        if (std::find_if(ends.begin(), ends.end(), [&](const auto& e) { return e.first == id; }) != ends.end()) continue;
        const Curve& c = layer.curves[id];
        if (c.start == node) ends.push_back({id, true});
        if (c.end == node) ends.push_back({id, false});
    }
    return ends;
}

std::string metres(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v << " m";
    return s.str();
}

// The entries of every road at `node` for a ring of `radius`, sorted counter-clockwise by angle
// (ties by curve id, start before end: deterministic); or the reason the ring does not fit.
struct RingLayout {
    std::vector<Entry> entries;
    std::optional<std::string> refusal;
};

RingLayout layoutRing(const Scene& scene, LayerId layerId, ElementId node, double radius,
                      const RoundaboutParams& params) {
    RingLayout out;
    const Layer& layer = scene.layers[layerId];
    const Vec2 centre = layer.nodes[node].p;
    const auto ends = endsAt(layer, node);
    if (ends.empty()) {
        std::ostringstream s;
        s << "node " << node << " of layer " << layerId << " has no road to carry a roundabout ring";
        out.refusal = s.str();
        return out;
    }
    for (const auto& [id, atStart] : ends) {
        const Curve& c = layer.curves[id];
        auto e = firstCrossing(c, id, atStart, centre, radius);
        if (!e) {
            std::ostringstream s;
            s << "road " << id << " does not leave the circle of radius " << metres(radius) << " around node "
              << node << " (the roundabout is larger than the road)";
            out.refusal = s.str();
            return out;
        }
        // The road's other end may be a ring too (its current radius): the two trims must leave
        // some road between them.
        const ElementId other = atStart ? c.end : c.start;
        if (other != node && layer.aliveNode(other) && layer.nodes[other].roundabout > 0.0f) {
            const auto o = firstCrossing(c, id, !atStart, layer.nodes[other].p, double(layer.nodes[other].roundabout));
            if (!o || (atStart ? !(e->s < o->s) : !(o->s < e->s))) {
                std::ostringstream s;
                s << "road " << id << " has nothing left between the roundabout of radius " << metres(radius)
                  << " at node " << node << " and the one of radius "
                  << metres(double(layer.nodes[other].roundabout)) << " at node " << other;
                out.refusal = s.str();
                return out;
            }
        }
        out.entries.push_back(*e);
    }
    std::sort(out.entries.begin(), out.entries.end(), [](const Entry& a, const Entry& b) {
        if (a.angle != b.angle) return a.angle < b.angle;
        if (a.curve != b.curve) return a.curve < b.curve;
        return a.atStart && !b.atStart;
    });
    const std::size_t n = out.entries.size();
    if (n >= 2) {
        for (std::size_t i = 0; i < n; ++i) {
            const Entry& a = out.entries[i];
            const Entry& b = out.entries[(i + 1) % n];
            double gap = b.angle - a.angle;
            if (i + 1 == n) gap += 2.0 * std::numbers::pi;
            const double along = gap * radius;
            if (along < params.minEntrySeparation) {
                std::ostringstream s;
                s << "roads " << a.curve << " and " << b.curve << " enter the roundabout of radius " << metres(radius)
                  << " at node " << node << " " << metres(along) << " apart along the ring, less than "
                  << metres(params.minEntrySeparation);
                out.refusal = s.str();
                return out;
            }
        }
    }
    return out;
}

// The ring arc from entry `a` counter-clockwise to entry `b` (the same entry: the full circle),
// as cubic pieces of at most kMaxArcPieceAngle; its first and last vertices are exactly a.p, b.p.
std::vector<Vertex> ringArc(Vec2 centre, double radius, const Entry& a, const Entry& b, bool fullCircle) {
    double sweep = b.angle - a.angle;
    if (fullCircle) sweep = 2.0 * std::numbers::pi;
    else if (sweep <= 0.0) sweep += 2.0 * std::numbers::pi;
    const int n = std::max(1, int(std::ceil(sweep / kMaxArcPieceAngle)));
    const double step = sweep / double(n);
    const double k = 4.0 / 3.0 * std::tan(step / 4.0);
    auto onCircle = [&](double angle) { return Vec2(std::cos(angle), std::sin(angle)) * radius; };
    auto tangent = [&](double angle) { return Vec2(-std::sin(angle), std::cos(angle)) * (k * radius); };
    std::vector<Vertex> v;
    v.reserve(std::size_t(3 * n + 1));
    v.push_back({a.p, true});
    for (int i = 0; i < n; ++i) {
        const double from = a.angle + step * double(i);
        const double to = a.angle + step * double(i + 1);
        const Vec2 start = v.back().p - centre;
        const Vec2 end = i + 1 == n ? b.p - centre : onCircle(to);
        v.push_back({centre + (start + tangent(from)), false});
        v.push_back({centre + (end - tangent(to)), false});
        v.push_back({i + 1 == n ? b.p : centre + end, true});
    }
    return v;
}

// Whether `node` is a roundabout of `layer` that fits; fills its layout.
bool fittingRing(const Scene& scene, LayerId layerId, ElementId node, const RoundaboutParams& params,
                 RingLayout& layout) {
    const Layer& layer = scene.layers[layerId];
    if (!layer.aliveNode(node)) return false;
    const float radius = layer.nodes[node].roundabout;
    // The checks of roundaboutRefusal(), the layout computed once.
    if (!(radius > 0.0f) || !std::isfinite(radius) || double(radius) > params.maxRadius) return false;
    layout = layoutRing(scene, layerId, node, double(radius), params);
    return !layout.refusal;
}

}  // namespace

std::optional<RoundaboutCut> roundaboutCut(const Scene& scene, LayerId layerId, ElementId curve,
                                           const RoundaboutParams& params) {
    if (layerId >= scene.layers.size()) return std::nullopt;
    const Layer& layer = scene.layers[layerId];
    if (layer.kind != LayerKind::Roads || curve >= layer.curves.size() || !layer.curves[curve].alive)
        return std::nullopt;
    const Curve& c = layer.curves[curve];
    RoundaboutCut cut;
    cut.s0 = 0.0;
    std::size_t onCurve = 0;
    for (const Vertex& v : c.vertices) onCurve += v.onCurve ? 1 : 0;
    cut.s1 = onCurve > 0 ? double(onCurve - 1) : 0.0;

    for (const bool atStart : {true, false}) {
        const ElementId node = atStart ? c.start : c.end;
        RingLayout layout;
        if (!fittingRing(scene, layerId, node, params, layout)) continue;
        const auto& entries = layout.entries;
        const auto self = std::find_if(entries.begin(), entries.end(),
                                       [&](const Entry& e) { return e.curve == curve && e.atStart == atStart; });
        if (self == entries.end()) continue;  // not reached: every end at the node has an entry
        const std::size_t i = std::size_t(self - entries.begin());
        const Entry& next = entries[(i + 1) % entries.size()];
        if (atStart) cut.s0 = self->s, cut.trimmedStart = true;
        else cut.s1 = self->s, cut.trimmedEnd = true;

        // The ring takes the attributes of the widest road at the node (first in node.curves on a tie).
        const Curve* widest = nullptr;
        for (const Entry& e : entries)
            if (!widest || layer.curves[e.curve].w > widest->w) widest = &layer.curves[e.curve];
        ProceduralCurve arc;
        const Vec2 centre = layer.nodes[node].p;
        arc.curve.vertices = ringArc(centre, double(layer.nodes[node].roundabout), *self, next, entries.size() == 1);
        arc.curve.start = arc.curve.end = kNoElement;
        arc.curve.w = widest->w;
        arc.curve.wf = widest->wf;
        arc.curve.cls = widest->cls;
        arc.curve.flags = kRoundabout;
        arc.ringAtStart = arc.ringAtEnd = node;
        cut.arcs.push_back(std::move(arc));
    }
    if (!cut.trimmedStart && !cut.trimmedEnd) return std::nullopt;
    return cut;
}

float roundaboutRingWidth(const Layer& layer, ElementId node) {
    if (!layer.aliveNode(node)) return 0.0f;
    float w = 0.0f;
    for (ElementId id : layer.nodes[node].curves)
        if (id < layer.curves.size() && layer.curves[id].alive) w = std::max(w, layer.curves[id].w);
    return w;
}

std::optional<std::string> roundaboutRefusal(const Scene& scene, LayerId layerId, ElementId node, float radius,
                                             const RoundaboutParams& params) {
    std::ostringstream s;
    if (!std::isfinite(radius) || radius < 0.0f) {
        s << "the roundabout radius of node " << node << " must be a finite number of metres >= 0, not " << radius;
        return s.str();
    }
    if (layerId >= scene.layers.size()) {
        s << "layer " << layerId << " does not exist";
        return s.str();
    }
    const Layer& layer = scene.layers[layerId];
    if (!layer.aliveNode(node)) {
        s << "node " << node << " of layer " << layerId << " does not exist";
        return s.str();
    }
    if (layer.kind != LayerKind::Roads) {
        s << "node " << node << " is in layer '" << layer.name << "' (" << toString(layer.kind)
          << "): roundabouts are made in Roads layers only";
        return s.str();
    }
    if (radius == 0.0f) return std::nullopt;
    if (double(radius) > params.maxRadius) {
        s << "a roundabout of radius " << metres(double(radius)) << " at node " << node
          << " is larger than the largest allowed, " << metres(params.maxRadius);
        return s.str();
    }
    return layoutRing(scene, layerId, node, double(radius), params).refusal;
}

}  // namespace lacet
