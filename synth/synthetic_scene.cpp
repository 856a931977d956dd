// Synthetic scene generator: driver, occupancy grid, roads and rivers. Lakes, forests and
// fields are in synthetic_areas.cpp. See synth/synthetic_scene.h.

#include "synth/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "model/roundabouts.h"
#include "synth/synthetic_internal.h"

namespace lacet {
namespace synth {

Occupancy::Occupancy(double side)
    : cell_(std::clamp(side / 2000.0, 10.0, 50.0)),
      n_(std::max<std::size_t>(1, std::size_t(std::ceil(side / cell_)))),
      bits_(n_ * n_, 0) {}

std::size_t Occupancy::index(double x) const {
    const double c = std::floor(x / cell_);
    return c <= 0.0 ? 0 : std::min(n_ - 1, std::size_t(c));
}

bool Occupancy::any(const Box& b, std::uint8_t bits) const {
    const std::size_t x0 = index(b.min.x), x1 = index(b.max.x);
    for (std::size_t y = index(b.min.y), y1 = index(b.max.y); y <= y1; ++y)
        for (std::size_t x = x0; x <= x1; ++x)
            if (bits_[y * n_ + x] & bits) return true;
    return false;
}

void Occupancy::mark(const Box& b, std::uint8_t bits) {
    const std::size_t x0 = index(b.min.x), x1 = index(b.max.x);
    for (std::size_t y = index(b.min.y), y1 = index(b.max.y); y <= y1; ++y)
        for (std::size_t x = x0; x <= x1; ++x) bits_[y * n_ + x] |= bits;
}

void Occupancy::markEllipse(Vec2 c, Vec2 r, std::uint8_t bits) {
    const Vec2 rr = r + cell_;
    const std::size_t x0 = index(c.x - rr.x), x1 = index(c.x + rr.x);
    for (std::size_t y = index(c.y - rr.y), y1 = index(c.y + rr.y); y <= y1; ++y)
        for (std::size_t x = x0; x <= x1; ++x) {
            const Vec2 d = (Vec2((double(x) + 0.5) * cell_, (double(y) + 0.5) * cell_) - c) / rr;
            if (d.x * d.x + d.y * d.y <= 1.0) bits_[y * n_ + x] |= bits;
        }
}

double Occupancy::freeFraction(const Box& b, std::uint8_t bits) const {
    const std::size_t x0 = index(b.min.x), x1 = index(b.max.x);
    std::size_t total = 0, free = 0;
    for (std::size_t y = index(b.min.y), y1 = index(b.max.y); y <= y1; ++y)
        for (std::size_t x = x0; x <= x1; ++x) {
            ++total;
            free += (bits_[y * n_ + x] & bits) == 0;
        }
    return double(free) / double(total);
}

namespace {

constexpr double kPi = std::numbers::pi;

// --- Roads -----------------------------------------------------------------------------------

constexpr double kJunctionSpacing = 1500.0;  // m, at every scale (constant density)
constexpr double kBlockMargin = 20.0;        // m from a road's control hull to a block
constexpr double kBorderMargin = 5.0;        // m from the extent border to a block
struct RoadClass {
    float w, wf;
};
constexpr RoadClass kRoadClasses[3] = {{7.0f, 15.0f}, {5.0f, 11.0f}, {3.0f, 7.0f}};

// The quadratic closest to a cubic (same ends, midpoint preserved).
BezierPiece toQuadratic(const BezierPiece& c) {
    BezierPiece q;
    q.degree = 2;
    q.p = {c.p[0], (3.0 * (c.p[1] + c.p[2]) - c.p[0] - c.p[3]) * 0.25, c.p[3], Vec2(0.0)};
    return q;
}

Box hullOf(const std::vector<Vertex>& v) {
    Box b{v.front().p, v.front().p};
    for (const Vertex& x : v) {
        b.min = glm::min(b.min, x.p);
        b.max = glm::max(b.max, x.p);
    }
    return b;
}

// A slightly curved cubic road from a to b, split in two pieces (of mixed degrees) sometimes.
std::vector<Vertex> roadGeometry(Vec2 a, Vec2 b, Rng& rng) {
    const Vec2 d = b - a;
    const Vec2 n = perp(d);  // |n| = |d|
    BezierPiece c;
    c.degree = 3;
    c.p = {a, a + d / 3.0 + n * rng.uniform(-0.05, 0.05), a + d * (2.0 / 3.0) + n * rng.uniform(-0.05, 0.05), b};
    std::vector<Vertex> v;
    v.reserve(7);
    v.push_back(onCurve(a));
    if (rng.chance(0.3)) {
        auto [l, r] = split(c, rng.uniform(0.35, 0.65));
        const double mix = rng.uniform();
        appendPiece(v, mix < 0.25 ? toQuadratic(l) : l);
        appendPiece(v, mix >= 0.25 && mix < 0.5 ? toQuadratic(r) : r);
    } else {
        appendPiece(v, c);
    }
    v.back().p = b;
    return v;
}

}  // namespace

void buildRoads(Layer& layer, Context& ctx, Rng& rng) {
    const double side = ctx.side;
    const std::size_t n = std::max<std::size_t>(2, std::size_t(std::lround(side / kJunctionSpacing)));
    const double s = side / double(n);
    std::vector<Vec2> junction(n * n);
    for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < n; ++i)
            junction[j * n + i] = Vec2((double(i) + 0.5 + rng.uniform(-0.1, 0.1)) * s,
                                       (double(j) + 0.5 + rng.uniform(-0.1, 0.1)) * s);
    const std::size_t primaryRow = rng.below(4), primaryColumn = rng.below(4);
    // An inner junction that keeps its 4 roads, so that small scenes have a 4-way crossing too.
    const std::size_t anchor = n >= 3 ? (1 + rng.below(n - 2)) * n + 1 + rng.below(n - 2) : n * n;

    // Edges: horizontal (i,j)-(i+1,j) at j*(n-1)+i, then vertical (i,j)-(i,j+1) at H+i*(n-1)+j.
    const std::size_t H = n * (n - 1);
    struct Edge {
        std::size_t a, b;
        std::uint16_t cls;
        bool present;
        std::vector<Vertex> v;
    };
    std::vector<Edge> edges(2 * H);
    std::vector<Box> hull(2 * H);
    std::vector<std::size_t> degree(n * n, 0);
    std::size_t present = 0;
    for (std::size_t k = 0; k < 2 * H; ++k) {
        const bool horizontal = k < H;
        const std::size_t line = (horizontal ? k : k - H) / (n - 1), pos = (horizontal ? k : k - H) % (n - 1);
        Edge& e = edges[k];
        e.a = horizontal ? line * n + pos : pos * n + line;
        e.b = horizontal ? e.a + 1 : e.a + n;
        const bool primary = line % 4 == (horizontal ? primaryRow : primaryColumn);
        e.cls = primary ? 0 : (rng.chance(0.25) ? 2 : 1);
        e.present = primary || e.a == anchor || e.b == anchor || !rng.chance(e.cls == 2 ? 0.3 : 0.1);
        if (e.present) {
            e.v = roadGeometry(junction[e.a], junction[e.b], rng);
            ++degree[e.a], ++degree[e.b], ++present;
        } else {
            e.v = {onCurve(junction[e.a]), onCurve(junction[e.b])};  // only bounds the blocks
        }
        hull[k] = hullOf(e.v);
    }

    std::vector<ElementId> node(n * n, kNoElement);
    layer.nodes.reserve(n * n);
    for (std::size_t j = 0; j < n * n; ++j)
        if (degree[j] > 0) node[j] = addNode(layer, junction[j], degree[j]);
    layer.curves.reserve(present);
    for (Edge& e : edges) {
        if (!e.present) continue;
        const RoadClass rc = kRoadClasses[e.cls];
        layer.addCurve(makeCurve(std::move(e.v), node[e.a], node[e.b], rc.w, rc.wf, e.cls, 0));
    }

    // Blocks: the rectangles between consecutive road lines (and the extent border), kept off
    // the control hulls of their bounding roads (a curve lies in its control hull).
    const auto N = std::ptrdiff_t(n);
    const auto J = [&](std::ptrdiff_t i, std::ptrdiff_t j) { return junction[std::size_t(j * N + i)]; };
    const auto hEdge = [&](std::ptrdiff_t i, std::ptrdiff_t j) { return hull[std::size_t(j * (N - 1) + i)]; };
    const auto vEdge = [&](std::ptrdiff_t i, std::ptrdiff_t j) { return hull[H + std::size_t(i * (N - 1) + j)]; };
    const auto inner = [&](std::ptrdiff_t k) { return k >= 0 && k < N - 1; };
    const auto clampLine = [&](std::ptrdiff_t k) { return std::clamp<std::ptrdiff_t>(k, 0, N - 1); };
    ctx.blocks.reserve(std::size_t((N + 1) * (N + 1)));
    for (std::ptrdiff_t bj = -1; bj < N; ++bj)
        for (std::ptrdiff_t bi = -1; bi < N; ++bi) {
            Box b;
            b.min.x = bi < 0 ? kBorderMargin
                             : (inner(bj) ? vEdge(bi, bj).max.x : J(bi, clampLine(bj)).x) + kBlockMargin;
            b.max.x = bi + 1 >= N ? side - kBorderMargin
                                  : (inner(bj) ? vEdge(bi + 1, bj).min.x : J(bi + 1, clampLine(bj)).x) - kBlockMargin;
            b.min.y = bj < 0 ? kBorderMargin
                             : (inner(bi) ? hEdge(bi, bj).max.y : J(clampLine(bi), bj).y) + kBlockMargin;
            b.max.y = bj + 1 >= N ? side - kBorderMargin
                                  : (inner(bi) ? hEdge(bi, bj + 1).min.y : J(clampLine(bi), bj + 1).y) - kBlockMargin;
            if (b.max.x - b.min.x > 2.0 * kBlockMargin && b.max.y - b.min.y > 2.0 * kBlockMargin)
                ctx.blocks.push_back(b);
        }
}

// --- Rivers ----------------------------------------------------------------------------------

void buildRivers(Layer& layer, Context& ctx, Rng& rng) {
    const double side = ctx.side;
    const std::size_t systems = std::max<std::size_t>(1, std::size_t(std::lround(side * side * 1e-6 / 1000.0)));
    const std::size_t total = std::max<std::size_t>(6, ctx.target / 300);
    const double reachLength = std::min(1500.0, side / 6.0);
    const double ignoreRadius = 0.4 * reachLength;  // near its start a reach may touch its parent and siblings
    const double avoidRadius = std::max(0.2 * reachLength, ctx.occ.cell());
    const double corridor = 25.0;                    // widest river footprint (30 m) / 2 + a gap
    constexpr std::size_t kNone = ~std::size_t(0);

    struct Reach {
        std::vector<Vertex> v;  // from its downstream end (v[0]) upstream
        std::size_t parent;     // downstream reach, kNone at an outlet
        std::size_t root;       // outlet reach of its system
        std::size_t up = 1;     // reaches upstream of its downstream end, itself included
        std::size_t children = 0;
    };
    struct Tip {
        std::size_t parent;
        Vec2 p;
        double heading;  // upstream direction
        bool trunk;      // the main stem of its system
    };
    std::vector<Reach> reaches;
    reaches.reserve(total);
    std::vector<Vec2> samples;

    // Grows one reach upstream from a tip; returns its heading at the upstream end, or NaN.
    const auto grow = [&](const Tip& tip) -> double {
        const double length = reachLength * rng.uniform(0.6, 1.3);
        const std::size_t pieces = 1 + rng.below(3);
        const double l = length / double(pieces);
        const std::size_t steps = std::max<std::size_t>(4, std::size_t(std::ceil(l / ctx.occ.cell())));
        for (int attempt = 0; attempt < 8; ++attempt) {  // turning further away at each attempt
            double course = tip.heading + 0.2 * double(attempt) * rng.uniform(-1.0, 1.0);
            double tangent = course;
            std::vector<Vertex> v{onCurve(tip.p)};
            v.reserve(1 + 3 * pieces);
            samples.clear();
            Vec2 p = tip.p;
            for (std::size_t k = 0; k < pieces; ++k) {
                course += rng.uniform(-0.35, 0.35);
                const Vec2 q = p + direction(course) * l;
                BezierPiece b;
                if (rng.chance(0.5)) {
                    b.degree = 2;
                    b.p = {p, p + direction(tangent) * (0.5 * l), q, Vec2(0.0)};
                    tangent = std::atan2(q.y - b.p[1].y, q.x - b.p[1].x);
                } else {
                    const double end = course + rng.uniform(-0.25, 0.25);
                    b.degree = 3;
                    b.p = {p, p + direction(tangent) * (l / 3.0), q - direction(end) * (l / 3.0), q};
                    tangent = end;
                }
                appendPiece(v, b);
                for (std::size_t i = 1; i <= steps; ++i) samples.push_back(evaluate(b, double(i) / double(steps)));
                p = q;
            }
            bool ok = true;
            for (Vec2 q : samples) {
                const bool nearStart = glm::length(q - tip.p) < ignoreRadius;
                const double m = nearStart ? 0.0 : avoidRadius;
                if (q.x < m || q.y < m || q.x > side - m || q.y > side - m ||
                    (!nearStart && ctx.occ.any(Box{q, q}, kNearRiver))) {
                    ok = false;
                    break;
                }
            }
            if (!ok) continue;
            for (Vec2 q : samples) {
                ctx.occ.mark(Box{q - avoidRadius, q + avoidRadius}, kNearRiver);
                ctx.occ.mark(Box{q - corridor, q + corridor}, kBlocked);
            }
            const std::size_t id = reaches.size();
            const std::size_t root = tip.parent == kNone ? id : reaches[tip.parent].root;
            if (tip.parent != kNone) ++reaches[tip.parent].children;
            reaches.push_back(Reach{std::move(v), tip.parent, root});
            return tangent;
        }
        return std::nan("");
    };

    const double phase = rng.uniform();
    for (std::size_t sys = 0; sys < systems; ++sys) {
        const std::size_t budget = total / systems + (sys < total % systems ? 1 : 0);
        // A trunk first, reaching well inside the extent with a tributary at each of its nodes;
        // then tributaries grow from random pending tips, branching or going on. Outlets are
        // spread evenly along the border (one turn from a random start); another spot along the
        // same stretch is tried if the first reach cannot grow from there.
        double inward = 0.0;
        const auto outletTip = [&] {
            const double along = 4.0 * std::fmod(phase + (double(sys) + rng.uniform(0.2, 0.8)) / double(systems), 1.0);
            const auto edge = std::size_t(along);
            const double t = (0.1 + 0.8 * (along - double(edge))) * side;
            inward = double(edge + 1) * 0.5 * kPi;
            return Tip{kNone, edge == 0 ? Vec2(t, 0.0) : edge == 1 ? Vec2(side, t) : edge == 2 ? Vec2(t, side) : Vec2(0.0, t),
                       inward + rng.uniform(-0.3, 0.3), true};
        };
        // `next` is a stack of tips grown first (the trunk's next reach, then the tributary at
        // its upper node); `tips` the other pending tips, grown in random order.
        std::vector<Tip> next{outletTip()}, tips;
        int outletTries = 8;
        std::size_t trunkLeft = std::clamp<std::size_t>(std::size_t(side * rng.uniform(0.4, 0.8) / reachLength), 2,
                                                        std::max<std::size_t>(2, budget / 2));
        for (std::size_t grown = 0, head = 0; grown < budget;) {
            Tip tip;
            if (!next.empty()) {
                tip = next.back();
                next.pop_back();
            } else if (head < tips.size()) {
                std::swap(tips[head], tips[head + rng.below(tips.size() - head)]);
                tip = tips[head++];
            } else {
                break;
            }
            const double h = grow(tip);
            if (std::isnan(h)) {
                if (tip.parent == kNone && --outletTries > 0) next.push_back(outletTip());
                continue;
            }
            ++grown;
            const std::size_t id = reaches.size() - 1;
            const Vec2 p = reaches.back().v.back().p;
            const double u = rng.uniform();
            if (tip.trunk && --trunkLeft > 0) {  // the trunk goes on first, then the tributary beside it
                const double on = h + 0.4 * std::remainder(inward - h, 2.0 * kPi) + rng.uniform(-0.2, 0.2);
                next.push_back({id, p, on + (u < 0.5 ? 1.0 : -1.0) * rng.uniform(0.6, 1.0), false});
                next.push_back({id, p, on, true});
            } else if (tip.trunk || u < 0.5) {  // confluence (right away at the trunk's end)
                auto& to = tip.trunk ? next : tips;
                to.push_back({id, p, h + rng.uniform(0.45, 0.8), false});
                to.push_back({id, p, h - rng.uniform(0.45, 0.8), false});
            } else if (u < 0.95) {
                tips.push_back({id, p, h + rng.uniform(-0.25, 0.25), false});
            }
        }
    }

    // Rivers always have a confluence: if none grew, a tributary is added where one fits.
    const auto confluence = [&] {
        return std::any_of(reaches.begin(), reaches.end(), [](const Reach& r) { return r.children >= 2; });
    };
    for (std::size_t r = 0, n = reaches.size(); r < n && !confluence(); ++r)
        for (int k = 0; k < 12 && reaches[r].children == 1; ++k)
            if (!std::isnan(grow({r, reaches[r].v.back().p, double(k) * kPi / 6.0, false}))) break;

    // Widths grow with the number of reaches upstream (reaches are stored parents first).
    for (std::size_t r = reaches.size(); r-- > 0;)
        if (reaches[r].parent != kNone) reaches[reaches[r].parent].up += reaches[r].up;
    const auto inside = [&](Vec2 p) { return glm::clamp(p, Vec2(0.0), Vec2(side)); };
    std::vector<ElementId> upNode(reaches.size()), outletNode(reaches.size(), kNoElement);
    layer.nodes.reserve(reaches.size() + systems);
    layer.curves.reserve(reaches.size());
    for (std::size_t r = 0; r < reaches.size(); ++r) {
        Reach& reach = reaches[r];
        for (Vertex& x : reach.v) x.p = inside(x.p);
        if (reach.parent == kNone) outletNode[r] = addNode(layer, reach.v.front().p, 1);
        upNode[r] = addNode(layer, reach.v.back().p, reach.children + 1);
    }
    for (std::size_t r = 0; r < reaches.size(); ++r) {
        Reach& reach = reaches[r];
        const double flow = double(reach.up - 1) / double(std::max<std::size_t>(reaches[reach.root].up - 1, 1));
        const auto w = float(2.0 + 18.0 * std::sqrt(flow));
        const ElementId down = reach.parent == kNone ? outletNode[r] : upNode[reach.parent];
        std::reverse(reach.v.begin(), reach.v.end());  // downstream orientation
        layer.addCurve(makeCurve(std::move(reach.v), upNode[r], down, w, w + 10.0f, 0, 0));
    }
}

}  // namespace synth

double syntheticExtentSide(std::size_t curves) {
    return 100000.0 * std::sqrt(double(std::max<std::size_t>(curves, 1)) / 600000.0);
}

struct SyntheticSceneParts::State {
    Scene scene;
    synth::Context ctx;
    synth::Rng fieldRng;
    std::size_t fieldBudget = 0;
    bool fieldsMade = false;
};

namespace {

// One independent stream per layer (splitmix64 of seed and layer), so that a change in one layer's
// generator does not reshuffle the others.
synth::Rng layerStream(std::uint64_t seed, std::uint64_t layer) {
    std::uint64_t z = seed + 0x9e3779b97f4a7c15ull * (layer + 1);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return synth::Rng(z ^ (z >> 31));
}

}  // namespace

SyntheticSceneParts::SyntheticSceneParts(const SyntheticParams& params) {
    using namespace synth;
    const double side = syntheticExtentSide(params.curves);
    state_ = std::make_unique<State>(State{{}, Context{side, params.curves, Occupancy(side), {}}, layerStream(params.seed, kFieldsLayer)});
    Scene& scene = state_->scene;
    Context& ctx = state_->ctx;
    scene.extent = Box{Vec2(0.0), Vec2(side)};
    scene.layers.resize(5);
    const std::pair<const char*, LayerKind> layers[5] = {{"roads", LayerKind::Roads},
                                                         {"rivers", LayerKind::Rivers},
                                                         {"lakes", LayerKind::Lakes},
                                                         {"fields", LayerKind::Fields},
                                                         {"forests", LayerKind::Forests}};
    for (std::size_t i = 0; i < 5; ++i) {
        scene.layers[i].name = layers[i].first;
        scene.layers[i].kind = layers[i].second;
    }
    const std::size_t n = params.curves;
    Rng roads = layerStream(params.seed, kRoadsLayer), rivers = layerStream(params.seed, kRiversLayer),
        lakes = layerStream(params.seed, kLakesLayer), forests = layerStream(params.seed, kForestsLayer);
    if (n >= 40) buildRoads(scene.layers[kRoadsLayer], ctx, roads);
    else ctx.blocks.push_back(scene.extent.dilated(-kBorderMargin));
    if (n >= 60) buildRivers(scene.layers[kRiversLayer], ctx, rivers);
    buildLakes(scene.layers[kLakesLayer], ctx, lakes);
    buildForests(scene.layers[kForestsLayer], ctx, forests);
    std::size_t used = 0;
    for (const Layer& layer : scene.layers) used += layer.curves.size();
    state_->fieldBudget = n > used ? n - used : 0;
    // Roundabouts from their own stream, so that the other layers do not depend on them; they look
    // at the roads alone (model/roundabouts.h), so the fields made after them change nothing.
    Rng rings = layerStream(params.seed, 5);
    Layer& roadLayer = scene.layers[kRoadsLayer];
    for (ElementId id = 0; id < roadLayer.nodes.size(); ++id) {
        if (roadLayer.nodes[id].curves.size() < 3 || !rings.chance(params.roundaboutFraction)) continue;
        const auto radius = float(rings.uniform(10.0, 18.0));
        if (!roundaboutRefusal(scene, kRoadsLayer, id, radius)) roadLayer.nodes[id].roundabout = radius;
    }
}

SyntheticSceneParts::~SyntheticSceneParts() = default;

Scene SyntheticSceneParts::takeScene() { return std::exchange(state_->scene, Scene{}); }

void SyntheticSceneParts::fields(const std::function<void(Layer&& part)>& sink, std::size_t partCurves) {
    if (state_->fieldsMade) throw std::logic_error("SyntheticSceneParts::fields: the fields are made once");
    state_->fieldsMade = true;
    synth::buildFields(state_->ctx, state_->fieldRng, state_->fieldBudget, partCurves, sink);
}

Scene makeSyntheticScene(const SyntheticParams& params) {
    SyntheticSceneParts parts(params);
    Scene scene = parts.takeScene();
    parts.fields([&](Layer&& part) { appendLayerPart(scene.layers[kFieldsLayer], std::move(part)); },
                 std::numeric_limits<std::size_t>::max());
    return scene;
}

}  // namespace lacet
