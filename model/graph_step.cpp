#include "model/graph_step.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_set>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <glm/geometric.hpp>

#include "model/roundabouts.h"

namespace lacet {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// A curve flattened within the crossing tolerance: points and their root parameters s.
struct Polyline {
    std::vector<Vec2> p;
    std::vector<double> s;
    std::vector<double> u;  // arc length along the polyline
    Box box{};
};

void flattenPiece(const BezierPiece& b, double t0, double t1, double tol, int depth, std::size_t k, Polyline& out) {
    if (depth < 40 && flatness(b) > tol) {
        const auto [l, r] = splitHalf(b);
        const double tm = 0.5 * (t0 + t1);
        flattenPiece(l, t0, tm, tol, depth + 1, k, out);
        flattenPiece(r, tm, t1, tol, depth + 1, k, out);
        return;
    }
    out.u.push_back(out.u.back() + glm::length(b.end() - out.p.back()));
    out.p.push_back(b.end());
    out.s.push_back(double(k) + t1);
}

Polyline flatten(const Curve& c, double tol) {
    Polyline pl;
    if (c.vertices.empty()) return pl;
    pl.p.push_back(c.vertices.front().p);
    pl.s.push_back(0.0);
    pl.u.push_back(0.0);
    std::size_t k = 0;
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) { flattenPiece(b, 0.0, 1.0, tol, 0, k++, pl); });
    pl.box = {pl.p.front(), pl.p.front()};
    for (const Vec2& q : pl.p) pl.box = {glm::min(pl.box.min, q), glm::max(pl.box.max, q)};
    return pl;
}

std::size_t onCurveCount(const Curve& c) {
    return std::size_t(std::count_if(c.vertices.begin(), c.vertices.end(), [](const Vertex& v) { return v.onCurve; }));
}

// The value at x of `values`, linear between the increasing `keys` and clamped to the ends: a
// polyline's root parameter s or point at an arc length u, or its u at an s.
template <class T>
T along(const std::vector<double>& keys, const std::vector<T>& values, double x) {
    if (x <= keys.front()) return values.front();
    if (x >= keys.back()) return values.back();
    const std::size_t i = std::size_t(std::upper_bound(keys.begin(), keys.end(), x) - keys.begin()) - 1;
    const double span = keys[i + 1] - keys[i];
    return values[i] + (values[i + 1] - values[i]) * (span > 0.0 ? (x - keys[i]) / span : 0.0);
}
double sAtU(const Polyline& pl, double u) { return along(pl.u, pl.s, u); }
double uAtS(const Polyline& pl, double s) { return along(pl.s, pl.u, s); }
Vec2 pointAtU(const Polyline& pl, double u) { return along(pl.u, pl.p, u); }

// The box of a curve's vertices, controls included: it holds the curve.
Box controlHull(const Curve& c) {
    Box b{c.vertices.front().p, c.vertices.front().p};
    for (const Vertex& v : c.vertices) b = {glm::min(b.min, v.p), glm::max(b.max, v.p)};
    return b;
}

Box segmentBox(Vec2 a, Vec2 b) { return {glm::min(a, b), glm::max(a, b)}; }

Kernel::Point_2 point(Vec2 p) { return {p.x, p.y}; }

}  // namespace

void GraphStepParams::validate() const {
    auto need = [](bool ok, const char* what) {
        if (!ok) throw std::invalid_argument(std::string("GraphStepParams: ") + what);
    };
    need(crossingTolerance > 0.0 && std::isfinite(crossingTolerance), "crossingTolerance must be a positive number of metres");
    need(abutmentLength >= 0.0 && std::isfinite(abutmentLength), "abutmentLength must be >= 0 m");
    need(clearance >= 0.0 && std::isfinite(clearance), "clearance must be >= 0 m");
    need(deckThickness >= 0.0 && std::isfinite(deckThickness), "deckThickness must be >= 0 m");
    need(minBridgedRiverWidth >= 0.0 && std::isfinite(minBridgedRiverWidth), "minBridgedRiverWidth must be >= 0 m");
}

void GraphStepCounters::reset() {
    curvesExpanded = 0;
    crossingsTested = 0;
    crossingsFound = 0;
    flaggedCrossings = 0;
    flaggedRoadCrossings = 0;
    importedBridgesOverRivers = 0;
    bridgedCrossings = 0;
    culverts = 0;
    bridgesMade = 0;
    importedBridges = 0;
    roundaboutRoads = 0;
}

// Uniform cells over boxes: river segments (small) and road curves (an item whose box covers
// more than kMaxCells cells goes to a list every query scans).
class CellIndex {
public:
    explicit CellIndex(double cell) : cell_(cell) {}
    struct Item {
        ElementId curve;
        std::uint32_t segment;
    };
    void insert(const Box& b, Item item) {
        const auto [x0, y0, x1, y1] = cells(b);
        if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCells) {
            large_.push_back({b, item});
            return;
        }
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) cells_[key(x, y)].push_back({b, item});
    }
    void erase(const Box& b, ElementId curve) {
        auto drop = [&](std::vector<Entry>& v) {
            v.erase(std::remove_if(v.begin(), v.end(), [&](const Entry& e) { return e.item.curve == curve; }), v.end());
        };
        const auto [x0, y0, x1, y1] = cells(b);
        if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMaxCells) return drop(large_);
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) {
                const auto it = cells_.find(key(x, y));
                if (it == cells_.end()) continue;
                drop(it->second);
                if (it->second.empty()) cells_.erase(it);
            }
    }
    // f(item) for every item whose box meets b (an item may be reported more than once).
    template <class F>
    void query(const Box& b, F&& f) const {
        for (const Entry& e : large_)
            if (e.box.intersects(b)) f(e.item);
        const auto [x0, y0, x1, y1] = cells(b);
        if ((x1 - x0 + 1) * (y1 - y0 + 1) > 4 * kMaxCells) {  // a huge query: walk the cells instead
            for (const auto& [k, v] : cells_)
                for (const Entry& e : v)
                    if (e.box.intersects(b)) f(e.item);
            return;
        }
        for (std::int64_t y = y0; y <= y1; ++y)
            for (std::int64_t x = x0; x <= x1; ++x) {
                const auto it = cells_.find(key(x, y));
                if (it == cells_.end()) continue;
                for (const Entry& e : it->second)
                    if (e.box.intersects(b)) f(e.item);
            }
    }

private:
    static constexpr std::int64_t kMaxCells = 64;
    struct Entry {
        Box box;
        Item item;
    };
    std::array<std::int64_t, 4> cells(const Box& b) const {
        return {std::int64_t(std::floor(b.min.x / cell_)), std::int64_t(std::floor(b.min.y / cell_)),
                std::int64_t(std::floor(b.max.x / cell_)), std::int64_t(std::floor(b.max.y / cell_))};
    }
    static std::uint64_t key(std::int64_t x, std::int64_t y) {
        return std::uint64_t(x) * 0x9e3779b97f4a7c15ull ^ (std::uint64_t(y) + 0x632be59bd9b4e019ull);
    }
    double cell_;
    std::unordered_map<std::uint64_t, std::vector<Entry>> cells_;
    std::vector<Entry> large_;
};

struct GraphStep::Index {
    // Per layer: for Rivers layers, each river curve flattened and its segments in `rivers`; for
    // Roads layers, each road curve's box in `roads` (for the roads a river edit may now cross,
    // and the roads an imported bridge passes over).
    struct LayerIndex {
        LayerKind kind = LayerKind::Other;
        std::unordered_map<ElementId, Polyline> polylines;  // rivers only
        std::unordered_map<ElementId, Box> boxes;           // rivers and roads
        CellIndex cells{64.0};
    };
    std::vector<LayerIndex> layers;
    // Road curves are indexed once a river curve exists (or an imported bridge looks for roads
    // under it): a scene with neither pays nothing for them.
    bool roadsIndexed = false;
    std::size_t riverCurves = 0;   // river curves indexed now: none, no road looks for crossings
    // Roads whose expansion read a river (by river layer and id): UPDATE expands them again when
    // the river changes.
    std::unordered_map<std::uint64_t, std::unordered_set<std::uint64_t>> readers;
    static std::uint64_t ref(LayerId l, ElementId id) { return std::uint64_t(l) << 32 | id; }

    void add(const Scene& scene, LayerId l, ElementId id, double tol) {
        LayerIndex& li = layers[l];
        const Curve& c = scene.layers[l].curves[id];
        if (!c.alive || c.vertices.size() < 2) return;
        if (li.kind == LayerKind::Rivers) {
            Polyline pl = flatten(c, tol);
            for (std::size_t i = 0; i + 1 < pl.p.size(); ++i)
                li.cells.insert(segmentBox(pl.p[i], pl.p[i + 1]), {id, std::uint32_t(i)});
            li.boxes[id] = pl.box;
            li.polylines[id] = std::move(pl);
            ++riverCurves;
        } else if (li.kind == LayerKind::Roads) {
            const Box b = controlHull(c);
            li.cells.insert(b, {id, 0});
            li.boxes[id] = b;
        }
    }
    void remove(LayerId l, ElementId id) {
        LayerIndex& li = layers[l];
        if (li.kind == LayerKind::Rivers) {
            const auto it = li.polylines.find(id);
            if (it == li.polylines.end()) return;
            const Polyline& pl = it->second;
            for (std::size_t i = 0; i + 1 < pl.p.size(); ++i) li.cells.erase(segmentBox(pl.p[i], pl.p[i + 1]), id);
            li.polylines.erase(it);
            li.boxes.erase(id);
            --riverCurves;
        } else {
            const auto it = li.boxes.find(id);
            if (it == li.boxes.end()) return;
            li.cells.erase(it->second, id);
            li.boxes.erase(it);
        }
    }
};

namespace {

struct Crossing {
    double s = 0.0;       // on the road
    LayerId layer = 0;    // the crossed curve
    ElementId over = kNoElement;
    double overS = 0.0;
    double sine = 1.0;    // |sin| of the angle between the two curves there
    double overHalfWidth = 0.0;  // half the crossed curve's footprint width (m)
};

// The crossings of road polyline `road` with polyline `other` (exact predicates on their
// segments), appended to `out`; `tested` counts the segment pairs tested.
template <class Candidates>
void crossingsOf(const Polyline& road, Candidates&& candidates, std::vector<Crossing>& out, std::size_t& tested) {
    for (std::size_t i = 0; i + 1 < road.p.size(); ++i) {
        const Vec2 a = road.p[i], b = road.p[i + 1];
        const Kernel::Segment_2 ab(point(a), point(b));
        candidates(segmentBox(a, b), [&](const Polyline& other, LayerId layer, ElementId id, double halfWidth, std::size_t j) {
            ++tested;
            const Vec2 c = other.p[j], d = other.p[j + 1];
            if (!CGAL::do_intersect(ab, Kernel::Segment_2(point(c), point(d)))) return;
            // Where: the parameters along both segments (a construction; the predicate decided).
            const Vec2 r = b - a, q = d - c;
            const double den = r.x * q.y - r.y * q.x;
            double t = 0.0, w = 0.0;
            if (std::abs(den) > 0.0) {
                t = std::clamp(((c.x - a.x) * q.y - (c.y - a.y) * q.x) / den, 0.0, 1.0);
                w = std::clamp(((c.x - a.x) * r.y - (c.y - a.y) * r.x) / den, 0.0, 1.0);
            }
            const double lr = glm::length(r), lq = glm::length(q);
            const double sine = lr > 0.0 && lq > 0.0 ? std::abs(den) / (lr * lq) : 0.0;
            Crossing x;
            x.s = road.s[i] + (road.s[i + 1] - road.s[i]) * t;
            x.layer = layer;
            x.over = id;
            x.overS = other.s[j] + (other.s[j + 1] - other.s[j]) * w;
            x.sine = sine;
            x.overHalfWidth = halfWidth;
            out.push_back(x);
        });
    }
}


}  // namespace

GraphStep::GraphStep(const Scene& scene, GraphStepParams params) : params_(params), index_(std::make_unique<Index>()) {
    params_.validate();
    index_->layers.resize(scene.layers.size());
    for (LayerId l = 0; l < scene.layers.size(); ++l) index_->layers[l].kind = scene.layers[l].kind;
    for (LayerId l = 0; l < scene.layers.size(); ++l)
        if (scene.layers[l].kind == LayerKind::Rivers)
            for (ElementId id = 0; id < scene.layers[l].curves.size(); ++id) index_->add(scene, l, id, params_.crossingTolerance);
    if (index_->riverCurves > 0) indexRoads(scene);
}

void GraphStep::indexRoads(const Scene& scene) const {
    if (index_->roadsIndexed) return;
    index_->roadsIndexed = true;
    for (LayerId l = 0; l < scene.layers.size(); ++l)
        if (scene.layers[l].kind == LayerKind::Roads)
            for (ElementId id = 0; id < scene.layers[l].curves.size(); ++id) index_->add(scene, l, id, params_.crossingTolerance);
}

GraphStep::~GraphStep() = default;

bool GraphStep::expand(const Scene& scene, LayerId layer, ElementId id, std::vector<ProceduralCurve>& out) const {
    const Layer& L = scene.layers[layer];
    if (L.kind != LayerKind::Roads) return false;
    const Curve& c = L.curves[id];
    const bool ringStart = c.start != kNoElement && L.nodes[c.start].roundabout > 0.0f;
    const bool ringEnd = c.end != kNoElement && L.nodes[c.end].roundabout > 0.0f;
    const bool imported = (c.flags & kBridge) != 0;
    bool lookForBridges = imported || (index_->riverCurves > 0 && params_.bridges && !(c.flags & (kNoBridge | kTunnel)));
    if (!ringStart && !ringEnd && !lookForBridges) return false;
    ++counters_.curvesExpanded;

    const double sEnd = double(onCurveCount(c)) - 1.0;
    double s0 = 0.0, s1 = sEnd;
    std::optional<RoundaboutCut> cut;
    if (ringStart || ringEnd) {
        cut = roundaboutCut(scene, layer, id);
        if (cut) {
            s0 = cut->s0;
            s1 = cut->s1;
            ++counters_.roundaboutRoads;
        }
    }

    // Crossings with river curves (and, for an imported bridge, with other roads).
    std::vector<Crossing> crossings;
    Polyline road;
    if (lookForBridges && !imported) {
        // Most roads are nowhere near a river: their control hull (which holds the curve) meets
        // no river segment's cell, and they are not flattened.
        const Box hull = controlHull(c);
        bool near = false;
        for (const Index::LayerIndex& li : index_->layers)
            if (li.kind == LayerKind::Rivers) li.cells.query(hull, [&](CellIndex::Item) { near = true; });
        if (!near) lookForBridges = false;
    }
    if (imported) indexRoads(scene);
    if (lookForBridges) {
        road = flatten(c, params_.crossingTolerance);
        std::size_t tested = 0;
        for (LayerId l = 0; l < scene.layers.size(); ++l) {
            const Index::LayerIndex& li = index_->layers[l];
            if (li.kind == LayerKind::Rivers) {
                crossingsOf(road, [&](const Box& b, auto&& f) {
                    li.cells.query(b, [&](CellIndex::Item it) {
                        const Polyline& other = li.polylines.at(it.curve);
                        f(other, l, it.curve, 0.5 * double(scene.layers[l].curves[it.curve].wf), it.segment);
                    });
                }, crossings, tested);
            } else if (li.kind == LayerKind::Roads && imported) {
                std::vector<ElementId> near;
                li.cells.query(road.box, [&](CellIndex::Item it) { near.push_back(it.curve); });
                std::sort(near.begin(), near.end());
                near.erase(std::unique(near.begin(), near.end()), near.end());
                for (ElementId o : near) {
                    const Curve& oc = scene.layers[l].curves[o];
                    if ((l == layer && o == id) || (oc.flags & (kBridge | kTunnel))) continue;
                    const bool sharesNode = l == layer && (oc.start == c.start || oc.start == c.end || oc.end == c.start || oc.end == c.end);
                    if (sharesNode) continue;  // roads meeting at a junction do not pass over each other
                    const Polyline other = flatten(oc, params_.crossingTolerance);
                    crossingsOf(road, [&](const Box& b, auto&& f) {
                        for (std::size_t j = 0; j + 1 < other.p.size(); ++j)
                            if (segmentBox(other.p[j], other.p[j + 1]).intersects(b)) f(other, l, o, 0.5 * double(oc.wf), j);
                    }, crossings, tested);
                }
            }
        }
        counters_.crossingsTested += tested;
        std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
            return std::tie(a.s, a.layer, a.over, a.overS) < std::tie(b.s, b.layer, b.over, b.overS);
        });
        // A crossing exactly at a vertex of either polyline is found by both segments there: once.
        crossings.erase(std::unique(crossings.begin(), crossings.end(),
                                    [](const Crossing& a, const Crossing& b) {
                                        return a.layer == b.layer && a.over == b.over && std::abs(a.s - b.s) <= 1e-9 &&
                                               std::abs(a.overS - b.overS) <= 1e-9;
                                    }),
                        crossings.end());
        counters_.crossingsFound += crossings.size();
        for (const Crossing& x : crossings) index_->readers[Index::ref(x.layer, x.over)].insert(Index::ref(layer, id));
    }

    // Bridges: intervals of s, merged where they overlap.
    struct Interval {
        double a, b;
        std::vector<Crossing> crossings;
    };
    std::vector<Interval> bridges;
    if (imported) {
        bridges.push_back({s0, s1, crossings});
        ++counters_.importedBridges;
        std::size_t overRivers = 0;
        for (const Crossing& x : crossings) overRivers += scene.layers[x.layer].kind == LayerKind::Rivers;
        counters_.flaggedCrossings += overRivers;
        counters_.flaggedRoadCrossings += crossings.size() - overRivers;
        counters_.importedBridgesOverRivers += overRivers > 0;
    } else {
        const double roadHalf = 0.5 * double(c.wf);
        for (const Crossing& x : crossings) {
            if (x.s < s0 || x.s > s1) continue;  // inside a roundabout's ring
            // A river area's border (w = 0) is water's edge however thin the curve: it is bridged,
            // and with the river inside the area, makes one bridge from bank to bank.
            const Curve& over = scene.layers[x.layer].curves[x.over];
            if (!(c.flags & kAlwaysBridge) && over.areas.empty() && double(over.w) < params_.minBridgedRiverWidth) {
                ++counters_.culverts;
                continue;
            }
            ++counters_.bridgedCrossings;
            const Polyline& other = index_->layers[x.layer].polylines.at(x.over);
            const double reach = x.overHalfWidth + roadHalf;
            const double ux = uAtS(road, x.s);
            // Walk the road's points away from the crossing until its footprint clears the river's.
            // March along the road away from the crossing (kMarchStep), then bisect, to where its
            // footprint clears the river's: the extent of a bridge, not whether there is one.
            std::vector<std::size_t> near;
            const Box around = road.box.dilated(reach);
            for (std::size_t j = 0; j + 1 < other.p.size(); ++j)
                if (segmentBox(other.p[j], other.p[j + 1]).intersects(around)) near.push_back(j);
            auto inside = [&](double u) {
                const Vec2 p = pointAtU(road, u);
                for (std::size_t j : near)
                    if (distanceToSegment(p, other.p[j], other.p[j + 1]) <= reach) return true;
                return false;
            };
            auto clearAt = [&](int dir) {
                constexpr double kMarchStep = 0.5;  // m
                const double end = dir > 0 ? road.u.back() : 0.0;
                double in = ux;
                for (;;) {
                    const double next = dir > 0 ? std::min(end, in + kMarchStep) : std::max(end, in - kMarchStep);
                    if (next == in) return end;
                    if (!inside(next)) {
                        double clear = next;
                        for (int k = 0; k < 12; ++k) {
                            const double mid = 0.5 * (in + clear);
                            (inside(mid) ? in : clear) = mid;
                        }
                        return clear;
                    }
                    in = next;
                }
            };
            const double ua = clearAt(-1) - params_.abutmentLength;
            const double ub = clearAt(+1) + params_.abutmentLength;
            Interval iv{std::max(s0, sAtU(road, ua)), std::min(s1, sAtU(road, ub)), {x}};
            if (!bridges.empty() && iv.a <= bridges.back().b) {
                bridges.back().b = std::max(bridges.back().b, iv.b);
                bridges.back().crossings.push_back(x);
            } else {
                bridges.push_back(std::move(iv));
            }
        }
        counters_.bridgesMade += bridges.size();
    }
    if (bridges.empty() && !cut) return false;

    // The pieces: road, bridge, road, ... within [s0, s1], then the ring arcs.
    auto piece = [&](double a, double b, bool bridge, const std::vector<Crossing>* over) {
        ProceduralCurve pc;
        pc.curve = c;
        pc.curve.areas.clear();
        pc.curve.vertices = subSpline(c.vertices, a, b);
        if (!out.empty() && out.back().followsRoot())  // one cut point for both pieces, bit for bit
            pc.curve.vertices.front().p = out.back().curve.vertices.back().p;
        pc.curve.start = a <= 0.0 ? c.start : kNoElement;
        pc.curve.end = b >= sEnd ? c.end : kNoElement;
        pc.curve.flags = std::uint16_t(bridge ? (c.flags | kBridge) : (c.flags & ~kBridge));
        pc.rootS0 = a;
        pc.rootS1 = b;
        if (cut && cut->trimmedStart && a == s0) {
            pc.curve.flags |= kYieldAtStart;
            pc.ringAtStart = c.start;
        }
        if (cut && cut->trimmedEnd && b == s1) {
            pc.curve.flags |= kYieldAtEnd;
            pc.ringAtEnd = c.end;
        }
        if (over) {
            const double ua = road.u.empty() ? 0.0 : uAtS(road, a);
            for (const Crossing& x : *over) {
                BridgeSpan span;
                span.layer = x.layer;
                span.over = x.over;
                span.overS = x.overS;
                span.u = uAtS(road, x.s) - ua;
                span.halfLength = x.overHalfWidth / std::max(x.sine, 0.05);
                pc.spans.push_back(span);
            }
        }
        out.push_back(std::move(pc));
    };
    out.clear();
    const double minPiece = 1e-9 * std::max(1.0, sEnd);
    double at = s0;
    for (const Interval& iv : bridges) {
        if (iv.a - at > minPiece) piece(at, iv.a, false, nullptr);
        if (iv.b - iv.a > minPiece) piece(iv.a, iv.b, true, &iv.crossings);
        at = std::max(at, iv.b);
    }
    if (s1 - at > minPiece || out.empty()) piece(at, s1, false, nullptr);
    if (cut)
        for (const ProceduralCurve& arc : cut->arcs) out.push_back(arc);
    return true;
}

void GraphStep::update(const Scene& scene, const Changeset& changeset, std::vector<ElementRef>& out) {
    // The river and road curves the changeset touches, re-indexed; the roads reading a changed
    // river before (readers) or crossing it now; the roads at a changed roundabout node.
    std::vector<std::pair<LayerId, ElementId>> curves;
    for (const auto* list : {&changeset.removed, &changeset.added})
        for (const ElementRef& r : *list) {
            if (r.layer >= scene.layers.size()) continue;
            const Layer& L = scene.layers[r.layer];
            if (r.kind == ElementKind::Curve) curves.push_back({r.layer, r.id});
            if (r.kind == ElementKind::Node && L.kind == LayerKind::Roads && r.id < L.nodes.size())
                for (ElementId c : L.nodes[r.id].curves) out.push_back({r.layer, ElementKind::Curve, c});
            // A curve at a roundabout carries an arc to its neighbour: the neighbours change with it.
            if (r.kind == ElementKind::Curve && L.kind == LayerKind::Roads && r.id < L.curves.size())
                for (ElementId n : {L.curves[r.id].start, L.curves[r.id].end})
                    if (n != kNoElement && n < L.nodes.size() && L.nodes[n].roundabout > 0.0f)
                        for (ElementId c : L.nodes[n].curves) out.push_back({r.layer, ElementKind::Curve, c});
        }
    std::sort(curves.begin(), curves.end());
    curves.erase(std::unique(curves.begin(), curves.end()), curves.end());
    for (const auto& [l, id] : curves) {
        const LayerKind kind = index_->layers[l].kind;
        if (kind != LayerKind::Rivers && !(kind == LayerKind::Roads && index_->roadsIndexed)) continue;
        index_->remove(l, id);
        if (id < scene.layers[l].curves.size()) index_->add(scene, l, id, params_.crossingTolerance);
    }
    if (index_->riverCurves > 0) indexRoads(scene);  // the first river: roads may cross it now
    for (const auto& [l, id] : curves) {
        Index::LayerIndex& li = index_->layers[l];
        if (li.kind != LayerKind::Rivers) continue;
        // Roads that crossed the river before...
        const auto it = index_->readers.find(Index::ref(l, id));
        if (it != index_->readers.end()) {
            for (std::uint64_t r : it->second) out.push_back({LayerId(r >> 32), ElementKind::Curve, ElementId(r & 0xffffffffu)});
            index_->readers.erase(it);
        }
        // ...and the roads whose control hull meets it now (expand() decides whether they cross).
        const auto pl = li.polylines.find(id);
        if (pl == li.polylines.end()) continue;
        for (LayerId rl = 0; rl < scene.layers.size(); ++rl) {
            if (index_->layers[rl].kind != LayerKind::Roads) continue;
            const Polyline& river = pl->second;
            for (std::size_t j = 0; j + 1 < river.p.size(); ++j)
                index_->layers[rl].cells.query(segmentBox(river.p[j], river.p[j + 1]),
                                               [&](CellIndex::Item item) { out.push_back({rl, ElementKind::Curve, item.curve}); });
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::vector<Vertex> subSpline(std::span<const Vertex> vertices, double s0, double s1) {
    std::vector<BezierPiece> pieces;
    forEachPiece(vertices, [&](const BezierPiece& b, std::size_t) { pieces.push_back(b); });
    std::vector<Vertex> out;
    if (pieces.empty()) return out;
    const double n = double(pieces.size());
    s0 = std::clamp(s0, 0.0, n);
    s1 = std::clamp(s1, s0, n);
    auto emit = [&](const BezierPiece& b) {
        if (out.empty()) out.push_back({b.p[0], true});
        for (int k = 1; k < b.degree; ++k) out.push_back({b.p[std::size_t(k)], false});
        out.push_back({b.p[std::size_t(b.degree)], true});
    };
    const std::size_t k0 = std::min(std::size_t(s0), pieces.size() - 1);
    const std::size_t k1 = std::min(std::size_t(s1), pieces.size() - 1);
    for (std::size_t k = k0; k <= k1; ++k) {
        const double a = k == k0 ? s0 - double(k) : 0.0;
        const double b = k == k1 ? s1 - double(k) : 1.0;
        if (b <= a && !(k == k0 && k == k1)) continue;
        BezierPiece p = pieces[k];
        if (b < 1.0) p = split(p, b).first;  // [0, b]
        if (a > 0.0) p = split(p, b > 0.0 ? a / b : 0.0).second;  // then [a, b]
        if (a == 0.0 && k == k0) p.p[0] = pieces[k].p[0];
        if (b == 1.0) p.p[std::size_t(p.degree)] = pieces[k].end();  // exact shared end vertices
        emit(p);
    }
    if (out.size() == 1) out.push_back(out.front());
    return out;
}

}  // namespace lacet
