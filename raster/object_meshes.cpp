#include "raster/object_meshes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "model/bezier.h"
#include "raster/appearance_shading.h"

namespace lacet {
namespace {

using Colour = std::array<std::uint8_t, 4>;
constexpr Colour kAsphalt{70, 70, 74, 255};
constexpr Colour kConcrete{178, 173, 163, 255};
constexpr Colour kPillar{160, 155, 146, 255};
constexpr Colour kAbutment{140, 132, 120, 255};

// Newton's iterations mapping a length along a Bezier piece to its parameter, and the accuracy
// (m) where they stop; a bisection bracket keeps every step inside the piece.
constexpr int kNewtonIterations = 12;
constexpr double kNewtonTolerance = 1e-5;

// The ancestor curve as the curve data measures it: its Bezier pieces and u at each on-curve
// vertex (CurveDataCache::u at s = k). Points at a given u are found from these only, so they are
// a function of the ancestor and u, whatever quad asks.
struct Arc {
    std::vector<BezierPiece> pieces;
    std::vector<double> start;  // u at on-curve vertex k (pieces.size() + 1 values)
    double length = 0.0;
    double tolerance = 1e-4;    // m, CurveDataCache's arc length tolerance

    Arc(const Quadtree& tree, const CurveDataCache& data, LayerId layer, AncestorId a) {
        const Curve& c = tree.ancestorCurve(layer, a);
        forEachPiece(std::span<const Vertex>(c.vertices), [&](const BezierPiece& b, std::size_t) { pieces.push_back(b); });
        for (std::size_t k = 0; k <= pieces.size(); ++k) start.push_back(data.u(layer, a, double(k)));
        length = pieces.empty() ? 0.0 : start.back();
        tolerance = data.params().arcLengthTolerance;
    }

    struct Frame {
        Vec2 p{0.0};
        Vec2 tangent{1.0, 0.0};  // unit, along u
        Vec2 left() const { return {-tangent.y, tangent.x}; }
    };

    // The point at arc length u (clamped to [0, length]).
    Frame at(double u) const {
        Frame f;
        if (pieces.empty()) return f;
        u = std::clamp(u, 0.0, length);
        std::size_t k = std::size_t(std::upper_bound(start.begin(), start.end(), u) - start.begin());
        k = std::min(k == 0 ? 0 : k - 1, pieces.size() - 1);
        const BezierPiece& b = pieces[k];
        const double d = u - start[k], len = start[k + 1] - start[k];
        double t = len > 0.0 ? std::clamp(d / len, 0.0, 1.0) : 0.0;
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < kNewtonIterations && len > 0.0; ++i) {
            const double l = t <= 0.0 ? 0.0 : t >= 1.0 ? len : arcLength(split(b, t).first, tolerance);
            const double err = l - d;
            if (std::abs(err) < kNewtonTolerance) break;
            (err > 0.0 ? hi : lo) = t;
            const double speed = glm::length(derivative(b, t));
            double next = speed > 0.0 ? t - err / speed : 0.5 * (lo + hi);
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            t = next;
        }
        f.p = evaluate(b, t);
        const Vec2 tan = unitTangent(b, t);
        if (glm::length(tan) > 0.0) f.tangent = glm::normalize(tan);
        return f;
    }
};

// Points along an ancestor's pieces for trees: each piece flattened into chords of at most
// `step` metres (a function of the piece only), u along them scaled to the curve data's u at the
// piece's ends, so a tree's place is a function of (ancestor, u) whatever quad asks, and costs a
// binary search instead of Newton's iterations on arc lengths.
class FlatArc {
public:
    FlatArc(const Quadtree& tree, const CurveDataCache& data, LayerId layer, AncestorId a, double step)
        : data_(data), layer_(layer), a_(a), step_(step) {
        const Curve& c = tree.ancestorCurve(layer, a);
        forEachPiece(std::span<const Vertex>(c.vertices), [&](const BezierPiece& b, std::size_t) { pieces_.push_back(b); });
        tables_.resize(pieces_.size());
    }
    Arc::Frame at(double u) {
        Arc::Frame f;
        if (pieces_.empty()) return f;
        if (start_.empty())
            for (std::size_t k = 0; k <= pieces_.size(); ++k) start_.push_back(data_.u(layer_, a_, double(k)));
        u = std::clamp(u, 0.0, start_.back());
        std::size_t k = std::size_t(std::upper_bound(start_.begin(), start_.end(), u) - start_.begin());
        k = std::min(k == 0 ? 0 : k - 1, pieces_.size() - 1);
        const Table& t = table(k);
        std::size_t i = std::size_t(std::upper_bound(t.u.begin(), t.u.end(), u) - t.u.begin());
        i = std::clamp<std::size_t>(i, 1, t.u.size() - 1);
        const double du = t.u[i] - t.u[i - 1];
        const double w = du > 0.0 ? std::clamp((u - t.u[i - 1]) / du, 0.0, 1.0) : 0.0;
        f.p = t.p[i - 1] + w * (t.p[i] - t.p[i - 1]);
        const Vec2 d = t.p[i] - t.p[i - 1];
        if (glm::length(d) > 0.0) f.tangent = glm::normalize(d);
        return f;
    }

private:
    struct Table {
        std::vector<Vec2> p;
        std::vector<double> u;
    };
    const Table& table(std::size_t k) {
        Table& t = tables_[k];
        if (!t.p.empty()) return t;
        const BezierPiece& b = pieces_[k];
        double hull = 0.0;
        for (int i = 0; i < b.degree; ++i) hull += glm::length(b.p[i + 1] - b.p[i]);
        const std::size_t n = std::clamp<std::size_t>(std::size_t(std::ceil(hull / step_)), 1, 1u << 16);
        double chord = 0.0;
        std::vector<double> c(n + 1, 0.0);
        for (std::size_t i = 0; i <= n; ++i) {
            t.p.push_back(i == n ? b.end() : evaluate(b, double(i) / double(n)));
            if (i > 0) chord += glm::length(t.p[i] - t.p[i - 1]);
            c[i] = chord;
        }
        const double u0 = start_[k], u1 = start_[k + 1];
        for (std::size_t i = 0; i <= n; ++i) t.u.push_back(chord > 0.0 ? u0 + (u1 - u0) * (c[i] / chord) : u0);
        t.u.back() = u1;
        return t;
    }
    const CurveDataCache& data_;
    LayerId layer_;
    AncestorId a_;
    double step_;
    std::vector<BezierPiece> pieces_;
    std::vector<double> start_;
    std::vector<Table> tables_;
};

// A mesh in scene coordinates (doubles), converted relative to the quad's origin at the end.
struct Builder {
    std::vector<glm::dvec3> p;
    std::vector<glm::dvec3> n;
    std::vector<Colour> c;
    std::vector<std::uint32_t> idx;

    std::uint32_t vertex(glm::dvec3 pos, glm::dvec3 normal, Colour colour) {
        p.push_back(pos), n.push_back(normal), c.push_back(colour);
        return std::uint32_t(p.size() - 1);
    }
    // A flat quadrilateral a b c d (its normal from that winding; the renderer lights both faces).
    void quad(glm::dvec3 a, glm::dvec3 b, glm::dvec3 cc, glm::dvec3 d, Colour colour) {
        glm::dvec3 nn = glm::cross(cc - a, d - b);
        const double l = glm::length(nn);
        if (!(l > 1e-12)) return;  // degenerate (a zero-width parapet)
        nn /= l;
        const std::uint32_t i = vertex(a, nn, colour);
        vertex(b, nn, colour), vertex(cc, nn, colour), vertex(d, nn, colour);
        idx.insert(idx.end(), {i, i + 1, i + 2, i, i + 2, i + 3});
    }
    // A hexahedron: bottom corners counter-clockwise seen from above, top corners above them.
    void block(const std::array<glm::dvec3, 4>& bottom, const std::array<glm::dvec3, 4>& top, Colour colour) {
        quad(bottom[0], bottom[3], bottom[2], bottom[1], colour);
        quad(top[0], top[1], top[2], top[3], colour);
        for (int k = 0; k < 4; ++k) {
            const int m = (k + 1) % 4;
            quad(bottom[k], bottom[m], top[m], top[k], colour);
        }
    }
};

std::uint64_t mix(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ULL;
    x ^= x >> 33;
    return x;
}
// A deterministic number in [-1, 1] for a tree.
double jitter(AncestorId a, std::int64_t k, int side, std::uint64_t salt) {
    const std::uint64_t h = mix(a ^ mix(std::uint64_t(k) * 0x9e3779b97f4a7c15ULL ^ std::uint64_t(side + 7) ^ (salt << 40)));
    return double(h >> 11) / double(1ULL << 53) * 2.0 - 1.0;
}

struct Context {
    const Quad& quad;
    const Quadtree& tree;
    const CurveDataCache& data;
    const Dem& dem;
    const ElevationTile* elevation;
    const ObjectParams& params;
    ObjectCounters* counters;
    Builder b;
    std::vector<ObjectPart> parts;

    void beginPart(ObjectKind kind, LayerId layer, AncestorId a, std::int64_t index, int side, glm::dvec3 anchor) {
        ObjectPart part;
        part.kind = kind, part.layer = layer, part.ancestor = a, part.index = index, part.side = side, part.anchor = anchor;
        part.firstVertex = std::uint32_t(b.p.size());
        part.firstIndex = std::uint32_t(b.idx.size());
        parts.push_back(part);
    }
    void endPart() {
        ObjectPart& part = parts.back();
        part.vertexCount = std::uint32_t(b.p.size()) - part.firstVertex;
        part.indexCount = std::uint32_t(b.idx.size()) - part.firstIndex;
    }

    // The displayed ground (z_m of the quad's tile, bilinear) for trees.
    double ground(Vec2 p) const {
        const ElevationTile* e = elevation;
        if (!e || e->zm.empty() || e->bounds != quad.bounds) return dem.sample(p);
        const Vec2 g = (p - e->bounds.min) / e->delta;
        const int i = std::clamp(int(std::floor(g.x)), 0, e->resolution - 1), j = std::clamp(int(std::floor(g.y)), 0, e->resolution - 1);
        const double fx = std::clamp(g.x - i, 0.0, 1.0), fy = std::clamp(g.y - j, 0.0, 1.0);
        auto z = [&](int a, int bb) { return double(e->zm[e->index(a, bb)]); };
        return (1 - fy) * ((1 - fx) * z(i, j) + fx * z(i + 1, j)) + fy * ((1 - fx) * z(i, j + 1) + fx * z(i + 1, j + 1));
    }

    void bridge(LayerId layer, AncestorId a);
    void trees(LayerId layer, AncestorId a, const std::vector<ClippedCurve>& pieces, const TreeRule& rule, std::size_t ruleIndex);
};

void Context::bridge(LayerId layer, AncestorId a) {
    const Arc arc(tree, data, layer, a);
    if (arc.pieces.empty() || !(arc.length > 0.0)) return;
    const Arc::Frame mid = arc.at(0.5 * arc.length);
    if (!ownsPoint(quad.bounds, tree.root().bounds, mid.p)) return;
    const Curve& c = tree.ancestorCurve(layer, a);
    const ZProfile& zp = data.zProfile(layer, a);
    const ProceduralCurve* proc = tree.proceduralCurve(layer, a);
    const ObjectParams& P = params;
    const double L = arc.length, dt = P.deckThickness, ph = P.parapetHeight;
    const double hw = 0.5 * double(c.w), ho = hw + P.parapetWidth;
    beginPart(ObjectKind::Deck, layer, a, 0, 0, glm::dvec3(mid.p, zp.at(0.5 * L)));

    // The deck: cross-sections every stationSpacing along u, joined by strips, one per side of the
    // section (across: metres to the left of the axis; up: metres above the road surface).
    const std::size_t n = std::max<std::size_t>(1, std::size_t(std::ceil(L / P.stationSpacing)));
    struct Station {
        Arc::Frame f;
        double z;
    };
    std::vector<Station> st(n + 1);
    for (std::size_t i = 0; i <= n; ++i) {
        const double u = L * double(i) / double(n);
        st[i] = {arc.at(u), zp.at(u)};
    }
    // The road on the deck in the texture's colour for its class (raster/appearance_shading.h).
    Colour road = kAsphalt;
    if (tree.scene().layers[layer].kind == LayerKind::Roads) {
        const glm::vec3 rc = roadColour(c.cls);
        road = {std::uint8_t(std::lround(rc.r * 255.0f)), std::uint8_t(std::lround(rc.g * 255.0f)), std::uint8_t(std::lround(rc.b * 255.0f)), 255};
    }
    auto at = [&](const Station& s, double across, double up) { return glm::dvec3(s.f.p + across * s.f.left(), s.z + up); };
    const std::array<std::pair<double, double>, 9> section{{{-ho, -dt}, {ho, -dt}, {ho, ph}, {hw, ph}, {hw, 0.0},
                                                            {-hw, 0.0}, {-hw, ph}, {-ho, ph}, {-ho, -dt}}};
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k + 1 < section.size(); ++k) {
            const auto [x0, y0] = section[k];
            const auto [x1, y1] = section[k + 1];
            const Colour colour = k == 4 ? road : kConcrete;
            b.quad(at(st[i], x0, y0), at(st[i + 1], x0, y0), at(st[i + 1], x1, y1), at(st[i], x1, y1), colour);
        }
    // The ends: the slab and the two parapets.
    for (const Station* s : {&st.front(), &st.back()}) {
        b.quad(at(*s, -ho, -dt), at(*s, ho, -dt), at(*s, ho, 0.0), at(*s, -ho, 0.0), kConcrete);
        b.quad(at(*s, hw, 0.0), at(*s, ho, 0.0), at(*s, ho, ph), at(*s, hw, ph), kConcrete);
        b.quad(at(*s, -ho, 0.0), at(*s, -hw, 0.0), at(*s, -hw, ph), at(*s, -ho, ph), kConcrete);
    }

    endPart();

    // The water levels of the crossed rivers near each span (a pillar there stands in the bed).
    struct Water {
        double u, halfLength, z;
    };
    std::vector<Water> water;
    if (proc)
        for (const BridgeSpan& s : proc->spans)
            if (s.layer < tree.scene().layers.size() && tree.scene().layers[s.layer].kind == LayerKind::Rivers)
                water.push_back({s.u, s.halfLength, data.zProfile(s.layer, s.over).at(data.u(s.layer, s.over, s.overS))});
    auto footOf = [&](double u, std::span<const Vec2> corners) {
        double z = std::numeric_limits<double>::infinity();
        for (Vec2 q : corners) z = std::min(z, dem.sample(q));
        for (const Water& w : water)
            if (std::abs(u - w.u) <= w.halfLength) z = std::min(z, w.z);
        return z;
    };

    // Abutments: a block under each end of the deck, from its underside into the ground.
    const double al = std::min(P.abutmentLength, 0.5 * L);
    for (int end = 0; end < 2; ++end) {
        const double u0 = end == 0 ? 0.0 : L - al, u1 = end == 0 ? al : L;
        const Arc::Frame f0 = arc.at(u0), f1 = arc.at(u1);
        const double w = ho;
        const std::array<Vec2, 4> xy{f0.p - w * f0.left(), f1.p - w * f1.left(), f1.p + w * f1.left(), f0.p + w * f0.left()};
        const double top0 = zp.at(u0) - dt, top1 = zp.at(u1) - dt;
        const double bottom = std::min(footOf(0.5 * (u0 + u1), xy), std::min(top0, top1)) - P.footDepth;
        std::array<glm::dvec3, 4> lo, hi;
        for (int k = 0; k < 4; ++k) {
            lo[k] = glm::dvec3(xy[std::size_t(k)], bottom);
            hi[k] = glm::dvec3(xy[std::size_t(k)], k == 0 || k == 3 ? top0 : top1);
        }
        const Arc::Frame fm = arc.at(0.5 * (u0 + u1));
        beginPart(ObjectKind::Abutment, layer, a, end, 0, glm::dvec3(fm.p, bottom));
        b.block(lo, hi, kAbutment);
        endPart();
    }

    // Pillars: evenly between the abutments, about pillarSpacing apart, where the deck stands
    // higher than minPillarHeight above the ground (or the water).
    const double inner = L - 2.0 * al;
    const std::size_t bays = inner > 0.0 ? std::max<std::size_t>(1, std::size_t(std::ceil(inner / P.pillarSpacing))) : 1;
    for (std::size_t i = 1; i < bays; ++i) {
        const double u = al + inner * double(i) / double(bays);
        const Arc::Frame f = arc.at(u);
        const double h = 0.5 * P.pillarThickness, w = P.pillarWidthFraction * ho;
        const Vec2 t = f.tangent, l = f.left();
        const std::array<Vec2, 4> xy{f.p - h * t - w * l, f.p + h * t - w * l, f.p + h * t + w * l, f.p - h * t + w * l};
        const double top = std::max({zp.at(u - h), zp.at(u), zp.at(u + h)}) - dt;
        const std::array<Vec2, 5> under{xy[0], xy[1], xy[2], xy[3], f.p};
        const double ground = footOf(u, under);
        if (zp.at(u) - dt - ground < P.minPillarHeight) continue;
        std::array<glm::dvec3, 4> lo, hi;
        for (int k = 0; k < 4; ++k) {
            lo[k] = glm::dvec3(xy[std::size_t(k)], ground - P.footDepth);
            hi[k] = glm::dvec3(xy[std::size_t(k)], top);
        }
        beginPart(ObjectKind::Pillar, layer, a, std::int64_t(i), 0, glm::dvec3(f.p, ground - P.footDepth));
        b.block(lo, hi, kPillar);
        endPart();
        if (counters) ++counters->pillars;
    }
    if (counters) ++counters->bridges;
}

void Context::trees(LayerId layer, AncestorId a, const std::vector<ClippedCurve>& pieces, const TreeRule& rule,
                    std::size_t ruleIndex) {
    // The k whose u = k * spacing some piece of this quad spans: only they can be owned here.
    std::set<std::int64_t> ks;
    for (const ClippedCurve& piece : pieces) {
        if (piece.s.empty()) continue;
        const double u0 = data.u(layer, a, piece.s.front()), u1 = data.u(layer, a, piece.s.back());
        const std::int64_t k0 = std::int64_t(std::ceil(std::min(u0, u1) / rule.spacing));
        const std::int64_t k1 = std::int64_t(std::floor(std::max(u0, u1) / rule.spacing));
        for (std::int64_t k = k0; k <= k1; ++k) ks.insert(k);
    }
    if (ks.empty()) return;
    const Curve& c = tree.ancestorCurve(layer, a);
    const double L = data.length(layer, a);
    const double offset = rule.offsetFraction * 0.5 * double(c.wf);
    std::optional<FlatArc> arc;
    for (std::int64_t k : ks) {
        const double u = double(k) * rule.spacing;
        if (u < rule.endClearance || u > L - rule.endClearance) continue;
        if (!arc) arc.emplace(tree, data, layer, a, params.treeSampleStep);
        const Arc::Frame f = arc->at(u);
        const int sides[2] = {offset > 0.0 ? -1 : 0, 1};
        for (int si = 0; si < (offset > 0.0 ? 2 : 1); ++si) {
            const int side = sides[si];
            const Vec2 p = f.p + double(side) * offset * f.left();
            if (!ownsPoint(quad.bounds, tree.root().bounds, p)) continue;
            const double z0 = ground(p);
            const double scale = 1.0 + rule.heightJitter * jitter(a, k, side, ruleIndex);
            const double h = rule.height * scale, r = rule.crownRadius * scale;
            const double base = z0 + rule.crownBase * h;
            const double turn = std::numbers::pi * jitter(a, k, side, ruleIndex + 1000);
            beginPart(ObjectKind::Tree, layer, a, k, side, glm::dvec3(p, z0));
            if (rule.trunkRadius > 0.0) {  // a square trunk from just below the ground into the crown
                std::array<glm::dvec3, 4> lo, hi;
                for (int q = 0; q < 4; ++q) {
                    const double ang = turn + q * 0.5 * std::numbers::pi;
                    const Vec2 d = rule.trunkRadius * Vec2(std::cos(ang), std::sin(ang));
                    lo[std::size_t(q)] = glm::dvec3(p + d, z0 - 0.5);
                    hi[std::size_t(q)] = glm::dvec3(p + d, base + 0.25 * (z0 + h - base));
                }
                b.block(lo, hi, rule.trunkColour);
            }
            // The crown: a bottom apex, two rings of 6, a top apex; smooth normals from its centre.
            constexpr int kRing = 6;
            const double ch = z0 + h - base;
            const glm::dvec3 centre(p, base + 0.5 * ch);
            auto add = [&](glm::dvec3 q) {
                glm::dvec3 nn = q - centre;
                nn.z *= (r * r) / std::max(1e-6, 0.25 * ch * ch);  // the normal of the ellipsoid through q
                const double l = glm::length(nn);
                return b.vertex(q, l > 0.0 ? nn / l : glm::dvec3(0, 0, 1), rule.crownColour);
            };
            const std::uint32_t bottom = add(glm::dvec3(p, base));
            std::uint32_t ring[2][kRing];
            const double rz[2] = {base + 0.35 * ch, base + 0.75 * ch}, rr[2] = {r, 0.75 * r};
            for (int m = 0; m < 2; ++m)
                for (int q = 0; q < kRing; ++q) {
                    const double ang = turn + (q + 0.5 * m) * 2.0 * std::numbers::pi / kRing;
                    ring[m][q] = add(glm::dvec3(p + rr[m] * Vec2(std::cos(ang), std::sin(ang)), rz[m]));
                }
            const std::uint32_t top = add(glm::dvec3(p, z0 + h));
            for (int q = 0; q < kRing; ++q) {
                const int q1 = (q + 1) % kRing;
                b.idx.insert(b.idx.end(), {bottom, ring[0][q1], ring[0][q]});
                b.idx.insert(b.idx.end(), {ring[0][q], ring[0][q1], ring[1][q]});
                b.idx.insert(b.idx.end(), {ring[0][q1], ring[1][q1], ring[1][q]});
                b.idx.insert(b.idx.end(), {ring[1][q], ring[1][q1], top});
            }
            endPart();
            if (counters) ++counters->trees;
        }
    }
}

}  // namespace

std::vector<TreeRule> ObjectParams::defaultTrees() {
    TreeRule alley;  // secondary roads: class 1 of io/feature_mapping.cpp and synth/synthetic_scene.h
    alley.kind = LayerKind::Roads;
    alley.cls = 1;
    alley.spacing = 14.0;
    alley.offsetFraction = 1.0;
    alley.height = 10.0;
    alley.crownRadius = 2.8;
    TreeRule hedge;  // every field border
    hedge.kind = LayerKind::Fields;
    hedge.cls = -1;
    hedge.spacing = 5.0;
    hedge.offsetFraction = 0.0;
    hedge.endClearance = 2.0;
    hedge.height = 2.6;
    hedge.crownRadius = 1.9;
    hedge.trunkRadius = 0.0;
    hedge.crownBase = 0.05;
    hedge.heightJitter = 0.2;
    hedge.crownColour = {44, 82, 36, 255};
    hedge.maxQuadSize = 320.0;  // a 2.6 m bush seen from 2.8 x 320 m is about 3 pixels high
    return {alley, hedge};
}

void ObjectParams::validate() const {
    auto fail = [](const char* what) { throw std::invalid_argument(std::string("ObjectParams: ") + what); };
    if (!(deckThickness > 0.0)) fail("deckThickness must be > 0 m");
    if (!(parapetHeight >= 0.0)) fail("parapetHeight must be >= 0 m");
    if (!(parapetWidth >= 0.0)) fail("parapetWidth must be >= 0 m");
    if (!(pillarSpacing > 0.0)) fail("pillarSpacing must be > 0 m");
    if (!(pillarThickness > 0.0)) fail("pillarThickness must be > 0 m");
    if (!(pillarWidthFraction > 0.0 && pillarWidthFraction <= 1.0)) fail("pillarWidthFraction must be in (0, 1]");
    if (!(minPillarHeight >= 0.0)) fail("minPillarHeight must be >= 0 m");
    if (!(footDepth >= 0.0)) fail("footDepth must be >= 0 m");
    if (!(abutmentLength > 0.0)) fail("abutmentLength must be > 0 m");
    if (!(stationSpacing > 0.0)) fail("stationSpacing must be > 0 m");
    if (!(treeSampleStep > 0.0)) fail("treeSampleStep must be > 0 m");
    for (std::size_t i = 0; i < trees.size(); ++i) {
        const TreeRule& r = trees[i];
        std::ostringstream where;
        where << "trees[" << i << "]: ";
        auto check = [&](bool ok, const char* what) {
            if (!ok) throw std::invalid_argument("ObjectParams: " + where.str() + what);
        };
        check(r.spacing > 0.0, "spacing must be > 0 m");
        check(r.offsetFraction >= 0.0 && r.offsetFraction <= 1.0, "offsetFraction must be in [0, 1]");
        check(r.endClearance >= 0.0, "endClearance must be >= 0 m");
        check(r.height > 0.0, "height must be > 0 m");
        check(r.crownRadius > 0.0, "crownRadius must be > 0 m");
        check(r.trunkRadius >= 0.0, "trunkRadius must be >= 0 m");
        check(r.crownBase >= 0.0 && r.crownBase < 1.0, "crownBase must be in [0, 1)");
        check(r.heightJitter >= 0.0 && r.heightJitter < 1.0, "heightJitter must be in [0, 1)");
        check(r.maxQuadSize > 0.0, "maxQuadSize must be > 0 m");
        check(r.cls >= -1 && r.cls <= 0xffff, "cls must be -1 or a class in [0, 65535]");
    }
}

void ObjectCounters::reset() {
    meshesBuilt = 0;
    bridges = 0;
    pillars = 0;
    trees = 0;
}

bool ownsPoint(const Box& bounds, const Box& root, Vec2 p) {
    auto inside = [](double v, double lo, double hi, double rootHi) { return lo <= v && (v < hi || (hi == rootHi && v == hi)); };
    return inside(p.x, bounds.min.x, bounds.max.x, root.max.x) && inside(p.y, bounds.min.y, bounds.max.y, root.max.y);
}

ObjectMesh produceObjects(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData, const Dem& dem,
                          const ElevationTile* elevation, const ObjectParams& params, ObjectCounters* counters) {
    ObjectMesh mesh;
    mesh.origin = glm::dvec3(quad.bounds.min, 0.0);
    const Scene& scene = quadtree.scene();
    bool trees = false;
    for (const TreeRule& r : params.trees) trees = trees || quad.bounds.size().x <= r.maxQuadSize;
    Context ctx{quad, quadtree, curveData, dem, elevation, params, counters, {}, {}};
    for (LayerId l = 0; l < quad.layers.size() && l < scene.layers.size(); ++l) {
        if (l < params.hiddenLayers.size() && params.hiddenLayers[l]) continue;
        const LayerKind kind = scene.layers[l].kind;
        bool ruled = false;
        if (trees)
            for (const TreeRule& r : params.trees) ruled = ruled || (r.kind == kind && quad.bounds.size().x <= r.maxQuadSize);
        if (!params.bridges && !ruled) continue;
        // By ancestor id, so that the mesh does not depend on the hash map's order.
        std::vector<AncestorId> ids;
        ids.reserve(quad.layers[l].curves.size());
        for (const auto& [a, pieces] : quad.layers[l].curves) {
            const Curve& c = quadtree.ancestorCurve(l, a);
            if ((params.bridges && (c.flags & kBridge)) || (ruled && !(c.flags & (kBridge | kTunnel)))) ids.push_back(a);
        }
        std::sort(ids.begin(), ids.end());
        for (AncestorId a : ids) {
            const Curve& c = quadtree.ancestorCurve(l, a);
            if (c.flags & kBridge) {
                ctx.bridge(l, a);
                continue;
            }
            const auto& pieces = quad.layers[l].curves.at(a);
            for (std::size_t i = 0; i < params.trees.size(); ++i) {
                const TreeRule& r = params.trees[i];
                if (r.kind == kind && (r.cls < 0 || r.cls == int(c.cls)) && quad.bounds.size().x <= r.maxQuadSize)
                    ctx.trees(l, a, pieces, r, i);
            }
        }
    }
    const Builder& b = ctx.b;
    if (b.idx.empty()) return mesh;
    mesh.vertices.resize(b.p.size());
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t i = 0; i < b.p.size(); ++i) {
        ObjectVertex& v = mesh.vertices[i];
        v.position = glm::vec3(b.p[i] - mesh.origin);
        v.normal = glm::vec3(b.n[i]);
        v.colour = b.c[i];
        lo = glm::min(lo, v.position), hi = glm::max(hi, v.position);
    }
    mesh.lo = lo, mesh.hi = hi;
    mesh.indices = b.idx;
    mesh.parts = std::move(ctx.parts);
    if (counters) ++counters->meshesBuilt;
    return mesh;
}

}  // namespace lacet
