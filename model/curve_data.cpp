#include "model/curve_data.h"

#include "model/graph_step.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>

#include <glm/geometric.hpp>

namespace lacet {
namespace {

// Node heights average the terrain over a disc: its centre and two rings of this many samples.
constexpr int kNodeRingSamples = 8;
// Flattening of a curve into a polyline to place z-profile samples: segments per piece, at least.
constexpr int kPolylineSegmentsPerPiece = 16;

}  // namespace

template <class T, class Compute>
const T& CurveDataCache::getOrCompute(Map<T>& map, const Key& key, std::atomic<std::size_t>& counter,
                                      Compute&& compute) const {
    {
        std::lock_guard lock(mutex_);
        if (auto it = map.find(key); it != map.end()) return *it->second;
    }
    auto value = compute();  // outside the lock: it may ask for other cached data
    std::lock_guard lock(mutex_);
    auto [it, inserted] = map.try_emplace(key, std::move(value));
    if (inserted) {
        ++counter;
        if (key.id & kProceduralBit) procedural_.insert(key);
    }
    return *it->second;
}

double ZProfile::at(double u) const {
    if (z.empty()) return 0.0;
    if (z.size() == 1 || spacing <= 0.0) return z.front();
    const double x = std::clamp(u / spacing, 0.0, double(z.size() - 1));
    const auto i = std::min(std::size_t(x), z.size() - 2);
    const double f = x - double(i);
    return z[i] + (z[i + 1] - z[i]) * f;
}

CurveDataCache::CurveDataCache(const Quadtree& quadtree, const HeightField& heights, ZProfileParams params)
    : quadtree_(quadtree), heights_(heights), params_(params) {
    if (const auto* step = dynamic_cast<const GraphStep*>(quadtree.procedural())) {
        deckClearance_ = step->params().clearance;
        deckThickness_ = step->params().deckThickness;
    }
    if (!(params_.sampleSpacing > 0.0) || !(params_.kernelRadius >= 0.0) || !(params_.arcLengthTolerance > 0.0))
        throw std::invalid_argument("CurveDataCache: sample spacing and arc-length tolerance must be > 0, kernel radius >= 0");
}

const CurveDataCache::Arc& CurveDataCache::arc(LayerId layer, AncestorId ancestor) const {
    return getOrCompute<Arc>(arcs_, Key{layer, ancestor}, counters_.arcLengthTables, [&] {
        auto a = std::make_unique<Arc>();
        a->start.push_back(0.0);
        forEachPiece(quadtree_.ancestorCurve(layer, ancestor).vertices, [&](const BezierPiece& b, std::size_t) {
            a->pieces.push_back(b);
            a->start.push_back(a->start.back() + arcLength(b, params_.arcLengthTolerance));
        });
        return a;
    });
}

double CurveDataCache::u(LayerId layer, AncestorId ancestor, double s) const {
    const Arc& a = arc(layer, ancestor);
    if (a.pieces.empty() || s <= 0.0) return 0.0;
    const auto k = std::min(std::size_t(s), a.pieces.size() - 1);
    const double t = std::min(s - double(k), 1.0);
    if (t <= 0.0) return a.start[k];
    if (t >= 1.0) return a.start[k + 1];
    return a.start[k] + arcLength(split(a.pieces[k], t).first, params_.arcLengthTolerance);
}

double CurveDataCache::length(LayerId layer, AncestorId ancestor) const { return arc(layer, ancestor).start.back(); }

double CurveDataCache::localNodeHeight(LayerId layer, ElementId node) const {
    const Layer& l = quadtree_.scene().layers[layer];
    const Vec2 c = l.nodes[node].p;
    if (l.kind == LayerKind::Rivers) {
        // A river lies on the valley floor and never rises: its node is as low as the lowest
        // terrain at it and along the river curves that flow into it (sampled every
        // sampleSpacing / 4 at most), so the profiles between their nodes, clamped to their end
        // nodes' heights, are never lifted above the terrain (a dip of the terrain upstream
        // holds the river down to its level further on). A mean over a disc counted the valley's
        // sides and lifted the river above its bed (and the downstream clamp carried that height
        // down the river); the curves flowing out are left out, being lower only because the
        // river descends (they would sink the node). So the height depends on the node and the
        // curves ending there, which is what invalidate() drops for a river edit (the node and
        // everything downstream of it).
        constexpr double kSamplesPerSpacing = 4.0;
        const double step = params_.sampleSpacing / kSamplesPerSpacing;
        double lowest = heights_.height(c);
        for (ElementId id : l.nodes[node].curves) {
            const Curve& cv = l.curves[id];
            if (!cv.alive || cv.end != node || !cv.areas.empty()) continue;  // an area's border is not a river
            forEachPiece(cv.vertices, [&](const BezierPiece& b, std::size_t) {
                const int n = std::max(1, int(std::ceil(arcLength(b, step) / step)));
                for (int i = 0; i < n; ++i) lowest = std::min(lowest, heights_.height(evaluate(b, double(i) / n)));
            });
        }
        return lowest;
    }
    double sum = heights_.height(c);
    int n = 1;
    for (double r : {0.5 * params_.kernelRadius, params_.kernelRadius}) {
        if (r <= 0.0) continue;
        for (int k = 0; k < kNodeRingSamples; ++k) {
            const double a = 2.0 * std::numbers::pi * k / kNodeRingSamples;
            sum += heights_.height(c + r * Vec2(std::cos(a), std::sin(a)));
            ++n;
        }
    }
    return sum / n;
}

double CurveDataCache::nodeHeight(LayerId layer, ElementId node) const {
    return getOrCompute<double>(nodeHeights_, Key{layer, node}, counters_.nodeHeights, [&] {
        const Layer& l = quadtree_.scene().layers[layer];
        double h = localNodeHeight(layer, node);
        if (l.kind == LayerKind::Rivers) {
            // No higher than any river node upstream (curves flow from start to end). A cycle in
            // a river network is broken where the walk first meets a node already on it.
            thread_local std::vector<Key> onPath;
            if (std::find(onPath.begin(), onPath.end(), Key{layer, node}) != onPath.end()) return std::make_unique<double>(h);
            onPath.push_back({layer, node});
            for (ElementId c : l.nodes[node].curves)
                if (l.curves[c].end == node && l.curves[c].start != node) h = std::min(h, nodeHeight(layer, l.curves[c].start));
            onPath.pop_back();
        }
        return std::make_unique<double>(h);
    });
}

std::unique_ptr<ZProfile> CurveDataCache::computeProfile(LayerId layer, AncestorId ancestor) const {
    if (const ProceduralCurve* pc = quadtree_.proceduralCurve(layer, ancestor)) return proceduralProfile(layer, ancestor, *pc);
    auto prof = terrainProfile(layer, ancestor);
    if (quadtree_.ancestorCurve(layer, ancestor).flags & kBridge) liftDeck(layer, ancestor, {}, *prof);
    return prof;
}

std::unique_ptr<ZProfile> CurveDataCache::proceduralProfile(LayerId layer, AncestorId ancestor, const ProceduralCurve& pc) const {
    const double len = length(layer, ancestor);
    auto prof = std::make_unique<ZProfile>();
    prof->length = len;
    const auto n = std::size_t(std::max(1.0, std::ceil(len / params_.sampleSpacing))) + 1;
    prof->spacing = len / double(n - 1);
    prof->z.resize(n);
    if (pc.followsRoot()) {
        // The part of the root curve's profile it follows, so that the pieces of a road meet at one
        // height (their arc lengths agree with the root's within the arc-length tolerance).
        const ElementId root = rootCurveOf(ancestor);
        const ZProfile& rp = zProfile(layer, root);
        const double u0 = u(layer, root, pc.rootS0), u1 = u(layer, root, pc.rootS1);
        for (std::size_t i = 0; i < n; ++i) prof->z[i] = rp.at(u0 + (u1 - u0) * double(i) / double(n - 1));
    } else {
        // A ring arc: level with its node.
        const ElementId node = pc.ringAtStart != kNoElement ? pc.ringAtStart : pc.ringAtEnd;
        std::fill(prof->z.begin(), prof->z.end(), node != kNoElement ? nodeHeight(layer, node) : 0.0);
    }
    // A road trimmed at a ring meets it at the ring's (its node's) height.
    const double reach = std::min(params_.kernelRadius, 0.5 * len);
    for (const auto& [node, atStart] : {std::pair{pc.ringAtStart, true}, std::pair{pc.ringAtEnd, false}}) {
        if (node == kNoElement || !pc.followsRoot() || reach <= 0.0) continue;
        const double d = nodeHeight(layer, node) - (atStart ? prof->z.front() : prof->z.back());
        for (std::size_t i = 0; i < n; ++i) {
            const double ui = prof->spacing * double(i);
            prof->z[i] += d * std::max(0.0, 1.0 - (atStart ? ui : len - ui) / reach);
        }
    }
    if (pc.curve.flags & kBridge) liftDeck(layer, ancestor, pc.spans, *prof);
    return prof;
}

double CurveDataCache::spanWater(const BridgeSpan& span) const {
    const ZProfile& over = zProfile(span.layer, span.over);
    const double ou = u(span.layer, span.over, span.overS);
    double water = -INFINITY;
    for (double d : {-params_.sampleSpacing, 0.0, params_.sampleSpacing}) water = std::max(water, over.at(ou + d));
    return water;
}

void CurveDataCache::liftDeck(LayerId layer, AncestorId ancestor, std::span<const BridgeSpan> spans, ZProfile& prof) const {
    // A deck runs straight between its ends (where it meets the road on the ground), never under
    // the terrain profile it replaces, and rises where it must to clear what it spans: over each
    // span's crossed footprint (u +- halfLength) its road surface stands `clearance` plus the deck's
    // thickness above the crossed curve's profile, easing back to the straight line at the ends.
    auto& z = prof.z;
    const std::size_t n = z.size();
    if (n < 2) return;
    const double len = prof.length;
    const std::vector<double> ground = z;
    for (std::size_t i = 0; i < n; ++i) z[i] = ground.front() + (ground.back() - ground.front()) * double(i) / double(n - 1);
    std::vector<double> lift(n, 0.0);
    const Scene& scene = quadtree_.scene();
    auto border = [&](const BridgeSpan& sp) {  // a river area's border: the water's edge, not a river
        return !(sp.over & kProceduralBit) && !scene.layers[sp.layer].curves[ElementId(sp.over)].areas.empty();
    };
    const bool overARiver = std::any_of(spans.begin(), spans.end(), [&](const BridgeSpan& sp) {
        return scene.layers[sp.layer].kind == LayerKind::Rivers && !border(sp);
    });
    for (const BridgeSpan& sp : spans) {
        const double overHalf = sp.halfLength;
        double water = -INFINITY;
        if (border(sp)) {
            // The profile of a border curve is the bank's, not the water's: the river inside the
            // area gives the water when the bridge spans it too, else the area's level.
            if (overARiver) continue;
            water = lakeLevel(sp.layer, scene.layers[sp.layer].curves[ElementId(sp.over)].areas.front());
        } else {
            water = spanWater(sp);
            std::lock_guard lock(mutex_);
            readers_[Key{sp.layer, sp.over}].insert(Key{layer, ancestor});
        }
        const double need = water + deckClearance_ + deckThickness_;
        const double a = std::max(0.0, sp.u - overHalf), b = std::min(len, sp.u + overHalf);
        for (std::size_t i = 0; i < n; ++i) {
            const double ui = prof.spacing * double(i);
            // 1 over [a, b], easing (cosine) to 0 at the deck's ends.
            double w = 1.0;
            if (ui < a) w = a > 0.0 ? 0.5 - 0.5 * std::cos(std::numbers::pi * ui / a) : 1.0;
            if (ui > b) w = len > b ? 0.5 - 0.5 * std::cos(std::numbers::pi * (len - ui) / (len - b)) : 1.0;
            lift[i] = std::max(lift[i], w * std::max(0.0, need - z[i]));
        }
    }
    for (std::size_t i = 0; i < n; ++i) z[i] = std::max(z[i] + lift[i], ground[i]);
}

std::vector<Vec2> CurveDataCache::samplePoints(LayerId layer, AncestorId ancestor) const {
    const Arc& a = arc(layer, ancestor);
    // Flatten, then place samples at regular arc length along the polyline.
    std::vector<Vec2> pts;
    std::vector<double> cum;
    for (const BezierPiece& b : a.pieces) {
        const int n = std::max(kPolylineSegmentsPerPiece, int(std::ceil(arcLength(b, 1.0) / (0.25 * params_.sampleSpacing))));
        for (int i = pts.empty() ? 0 : 1; i <= n; ++i) {
            const Vec2 p = evaluate(b, double(i) / n);
            cum.push_back(pts.empty() ? 0.0 : cum.back() + glm::length(p - pts.back()));
            pts.push_back(p);
        }
    }
    const auto n = std::size_t(std::max(1.0, std::ceil(a.start.back() / params_.sampleSpacing))) + 1;
    std::vector<Vec2> out(n, pts.empty() ? Vec2(0.0) : pts.front());
    if (pts.size() < 2) return out;
    std::size_t seg = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double target = cum.back() * double(i) / double(n - 1);
        while (seg + 2 < cum.size() && cum[seg + 1] < target) ++seg;
        const double span = cum[seg + 1] - cum[seg];
        const double f = span > 0.0 ? std::clamp((target - cum[seg]) / span, 0.0, 1.0) : 0.0;
        out[i] = pts[seg] + (pts[seg + 1] - pts[seg]) * f;
    }
    return out;
}

std::unique_ptr<ZProfile> CurveDataCache::terrainProfile(LayerId layer, AncestorId ancestor) const {
    const Curve& c = quadtree_.ancestorCurve(layer, ancestor);
    const std::vector<Vec2> points = samplePoints(layer, ancestor);
    auto prof = std::make_unique<ZProfile>();
    prof->length = length(layer, ancestor);
    const std::size_t n = points.size();
    prof->spacing = prof->length / double(n - 1);
    std::vector<double> raw(n);
    for (std::size_t i = 0; i < n; ++i) raw[i] = heights_.height(points[i]);
    // Triangular kernel of half-width kernelRadius, indices clamped at the ends.
    const int half = prof->spacing > 0.0 ? int(params_.kernelRadius / prof->spacing) : 0;
    auto& z = prof->z;
    z.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        double sum = 0.0, wsum = 0.0;
        for (int j = -half; j <= half; ++j) {
            const double w = 1.0 - std::abs(j) / double(half + 1);
            const auto k = std::size_t(std::clamp<std::ptrdiff_t>(std::ptrdiff_t(i) + j, 0, std::ptrdiff_t(n - 1)));
            sum += w * raw[k];
            wsum += w;
        }
        z[i] = sum / wsum;
    }
    const bool river = quadtree_.scene().layers[layer].kind == LayerKind::Rivers;
    const bool hasStart = c.start != kNoElement, hasEnd = c.end != kNoElement;
    const double h0 = hasStart ? nodeHeight(layer, c.start) : z.front();
    const double h1 = hasEnd ? nodeHeight(layer, c.end) : z.back();
    if (river) {
        // Never above the terrain under it (smoothing lifts a river where its floor flattens
        // below a steep stretch, and near its ends where the kernel is clamped), then never rising.
        for (std::size_t i = 0; i < n; ++i) z[i] = std::min(z[i], raw[i]);
        for (std::size_t i = 1; i < n; ++i) z[i] = std::min(z[i], z[i - 1]);
        const double hi = std::max(h0, h1), lo = std::min(h0, h1);
        for (double& v : z) v = std::clamp(v, lo, hi);
    } else {
        // Pull towards the node heights near the ends, each pull vanishing before the other end.
        const double reach = std::min(params_.kernelRadius, 0.5 * prof->length);
        const double d0 = h0 - z.front(), d1 = h1 - z.back();
        for (std::size_t i = 0; i < n; ++i) {
            const double ui = prof->spacing * double(i);
            if (reach > 0.0) {
                z[i] += d0 * std::max(0.0, 1.0 - ui / reach);
                z[i] += d1 * std::max(0.0, 1.0 - (prof->length - ui) / reach);
            }
        }
    }
    z.front() = h0;
    if (n > 1) z.back() = h1;
    return prof;
}

const ZProfile& CurveDataCache::zProfile(LayerId layer, AncestorId ancestor) const {
    return getOrCompute<ZProfile>(profiles_, Key{layer, ancestor}, counters_.zProfiles,
                                  [&] { return computeProfile(layer, ancestor); });
}

double CurveDataCache::lakeLevel(LayerId layer, ElementId area) const {
    return getOrCompute<double>(lakeLevels_, Key{layer, area}, counters_.lakeLevels, [&] {
        const Layer& l = quadtree_.scene().layers[layer];
        double lowest = INFINITY;
        for (const auto& loop : l.areas[area].loops)
            for (const auto& e : loop)
                forEachPiece(l.curves[e.curve].vertices, [&](const BezierPiece& b, std::size_t) {
                    const int n = std::max(2, int(std::ceil(arcLength(b, 1.0) / params_.sampleSpacing)));
                    for (int i = 0; i <= n; ++i) lowest = std::min(lowest, heights_.height(evaluate(b, double(i) / n)));
                });
        return std::make_unique<double>(lowest);
    });
}

void CurveDataCache::dropCurve(LayerId layer, ElementId curve, bool arcs, std::vector<ElementRef>& dropped) {
    bool profile = profiles_.erase(Key{layer, curve}) > 0;
    if (arcs) arcs_.erase(Key{layer, curve});
    // Its procedural curves: the cached ones in its id range, whatever it expands to now.
    const auto first = procedural_.lower_bound(Key{layer, proceduralId(curve, 0)});
    const auto last = procedural_.upper_bound(Key{layer, proceduralId(curve, kMaxProceduralCurves - 1)});
    for (auto it = first; it != last;) {
        profile = profiles_.erase(*it) > 0 || profile;
        if (arcs) arcs_.erase(*it);
        it = arcs_.count(*it) || profiles_.count(*it) ? std::next(it) : procedural_.erase(it);
    }
    if (profile) dropped.push_back({layer, ElementKind::Curve, curve});
    // Decks whose height read this curve's profile (a bridge over a river downstream of an edit).
    const auto readers = readers_.find(Key{layer, curve});
    if (readers != readers_.end()) {
        const std::set<Key> decks = std::move(readers->second);
        readers_.erase(readers);
        for (const Key& k : decks)
            if (profiles_.erase(k) > 0) dropped.push_back({k.layer, ElementKind::Curve, rootCurveOf(k.id)});
    }
}

void CurveDataCache::dropDownstream(LayerId layer, ElementId node, std::vector<ElementRef>& dropped) {
    const Layer& l = quadtree_.scene().layers[layer];
    std::vector<ElementId> pending{node};
    std::vector<ElementId> seen;
    while (!pending.empty()) {
        const ElementId n = pending.back();
        pending.pop_back();
        if (n >= l.nodes.size() || std::find(seen.begin(), seen.end(), n) != seen.end()) continue;
        seen.push_back(n);
        nodeHeights_.erase(Key{layer, n});
        for (ElementId c : l.nodes[n].curves) {
            dropCurve(layer, c, false, dropped);
            if (l.curves[c].start == n) pending.push_back(l.curves[c].end);
        }
    }
}

std::vector<ElementRef> CurveDataCache::invalidate(const Changeset& cs) {
    std::lock_guard lock(mutex_);
    std::vector<ElementRef> dropped;
    const Scene& scene = quadtree_.scene();
    for (const auto* list : {&cs.removed, &cs.added})
        for (const ElementRef& r : *list) {
            const Layer& l = scene.layers[r.layer];
            switch (r.kind) {
                case ElementKind::Curve:
                    dropCurve(r.layer, r.id, true, dropped);
                    if (l.kind == LayerKind::Rivers && r.id < l.curves.size()) dropDownstream(r.layer, l.curves[r.id].end, dropped);
                    break;
                case ElementKind::Node:
                    nodeHeights_.erase(Key{r.layer, r.id});
                    if (r.id < l.nodes.size())
                        for (ElementId c : l.nodes[r.id].curves) dropCurve(r.layer, c, false, dropped);
                    if (l.kind == LayerKind::Rivers) dropDownstream(r.layer, r.id, dropped);
                    break;
                case ElementKind::Area: lakeLevels_.erase(Key{r.layer, r.id}); break;
            }
        }
    std::sort(dropped.begin(), dropped.end());
    dropped.erase(std::unique(dropped.begin(), dropped.end()), dropped.end());
    return dropped;
}

}  // namespace lacet
