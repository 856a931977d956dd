// Synthetic scene generator: lakes, forests and fields (the areal layers). See
// synth/synthetic_scene.h; roads, rivers and the driver are in synthetic_scene.cpp.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "synth/synthetic_internal.h"

namespace lacet::synth {
namespace {

constexpr double kBlobEnvelope = 1.15;  // a blob's border stays within this factor of its radii
constexpr double kBlobGap = 15.0;       // m kept free around a lake or forest
constexpr float kLakeWf = 10.0f, kForestWf = 5.0f, kFieldWf = 2.0f;

// Adds a closed loop of `m` border curves around c: a perturbed ellipse of radii r through K
// points, joined by the cubic pieces of a closed Catmull-Rom spline. Curves are stored in a
// random direction; the loop runs counter-clockwise, or clockwise for a hole.
std::vector<AreaEdge> addBlobLoop(Layer& layer, Rng& rng, Vec2 c, Vec2 r, std::size_t m, float wf, bool hole) {
    const std::size_t K = std::max<std::size_t>(2 * m, 8 + rng.below(5));
    std::vector<Vec2> P(K);
    for (std::size_t k = 0; k < K; ++k) {
        const double a = 2.0 * std::numbers::pi * (double(k) + rng.uniform(-0.3, 0.3)) / double(K);
        const double rho = rng.uniform(0.8, 1.0);
        P[k] = c + Vec2(r.x * rho * std::cos(a), r.y * rho * std::sin(a));
    }
    const std::size_t off = rng.below(K);
    const auto at = [&](std::size_t k) { return P[k % K]; };
    std::vector<ElementId> nodes(m);
    for (std::size_t i = 0; i < m; ++i) nodes[i] = addNode(layer, at(off + i * K / m), 2);
    std::vector<AreaEdge> loop;
    loop.reserve(m);
    for (std::size_t i = 0; i < m; ++i) {
        const std::size_t k0 = off + i * K / m, k1 = off + (i + 1) * K / m;
        std::vector<Vertex> v{onCurve(at(k0))};
        v.reserve(1 + 3 * (k1 - k0));
        for (std::size_t k = k0; k < k1; ++k) {
            const Vec2 a = at(k), b = at(k + 1);
            v.push_back(control(a + (b - at(k + K - 1)) / 6.0));
            v.push_back(control(b - (at(k + 2) - a) / 6.0));
            v.push_back(onCurve(b));
        }
        const bool flip = rng.chance(0.5);
        if (flip) std::reverse(v.begin(), v.end());
        const ElementId from = nodes[i], to = nodes[(i + 1) % m];
        loop.push_back({layer.addCurve(makeCurve(std::move(v), flip ? to : from, flip ? from : to, 0.0f, wf, 0, 1)), flip});
    }
    if (hole) {
        std::reverse(loop.begin(), loop.end());
        for (AreaEdge& e : loop) e.reversed = !e.reversed;
    }
    return loop;
}

// Picks a free spot for a blob with radii in [rmin, rmax] (smaller where blocks are small)
// inside a random block, and marks it taken.
bool placeBlob(Context& ctx, Rng& rng, double rmin, double rmax, int attempts, Vec2& c, Vec2& r) {
    for (int attempt = 0; attempt < attempts && !ctx.blocks.empty(); ++attempt) {
        const Box& b = ctx.blocks[rng.below(ctx.blocks.size())];
        const Vec2 avail = (b.size() * 0.5 - kBlobGap) / kBlobEnvelope;
        double rx = rng.uniform(rmin, rmax), ry = rx * rng.uniform(0.6, 1.0);
        if (rng.chance(0.5)) std::swap(rx, ry);
        rx = std::min(rx, avail.x);
        ry = std::min(ry, avail.y);
        if (rx < 0.4 * rmin || ry < 0.4 * rmin) continue;
        const Vec2 reach = Vec2(rx, ry) * kBlobEnvelope + kBlobGap;
        c = Vec2(rng.uniform(b.min.x + reach.x, b.max.x - reach.x), rng.uniform(b.min.y + reach.y, b.max.y - reach.y));
        if (ctx.occ.any(Box{c - reach, c + reach}, kBlocked)) continue;
        ctx.occ.markEllipse(c, reach, kBlocked);
        r = Vec2(rx, ry);
        return true;
    }
    return false;
}

// Adds `count` blob areas; the first one placed (and a fraction `holeChance` of the others)
// gets a hole: an island or a clearing.
void buildBlobs(Layer& layer, Context& ctx, Rng& rng, std::size_t count, double rmin, double rmax,
                std::size_t minCurves, std::size_t maxCurves, float wf, double holeChance) {
    layer.areas.reserve(count);
    bool holeDone = false;
    for (std::size_t i = 0; i < count; ++i) {
        Vec2 c, r;
        if (!placeBlob(ctx, rng, rmin, rmax, layer.areas.empty() ? 400 : 40, c, r)) continue;
        Area a;
        a.wf = wf;
        a.loops.reserve(2);
        a.loops.push_back(addBlobLoop(layer, rng, c, r, minCurves + rng.below(maxCurves - minCurves + 1), wf, false));
        if (!holeDone || rng.chance(holeChance)) {
            holeDone = true;
            const double radius = std::min(r.x, r.y) * rng.uniform(0.15, 0.3);
            const Vec2 offset(rng.uniform(-0.15, 0.15) * r.x, rng.uniform(-0.15, 0.15) * r.y);
            a.loops.push_back(addBlobLoop(layer, rng, c + offset, Vec2(radius * rng.uniform(0.7, 1.0), radius),
                                          2 + rng.below(2), wf, true));
        }
        layer.addArea(std::move(a));
    }
}

// Curves of a k x k patch.
std::size_t patchCurves(std::size_t k) { return 2 * k * (k + 1); }

// Adds a patch of k x k parcels in the slot: a jittered (k+1) x (k+1) lattice of nodes, slightly
// rotated, whose inner border curves are shared by the two parcels on either side.
void addPatch(Layer& layer, Rng& rng, const Box& slot, std::size_t k) {
    constexpr double kInset = 4.0;  // m between the patch and its slot
    const Vec2 c = slot.center();
    const Vec2 half = slot.size() * 0.5 - kInset;
    const double phi = rng.uniform(-0.08, 0.08), cs = std::cos(phi), sn = std::sin(phi), as = std::abs(sn);
    const double det = cs * cs - as * as;
    // Half sizes of the rotated rectangle that fits the slot, with room for rounding.
    const Vec2 h = glm::max(Vec2(cs * half.x - as * half.y, cs * half.y - as * half.x) / det, half * 0.3) * 0.96;
    const double cell = 2.0 / double(k);
    const std::size_t k1 = k + 1;
    std::vector<ElementId> node(k1 * k1);
    std::vector<Vec2> pos(k1 * k1);
    for (std::size_t j = 0; j <= k; ++j)
        for (std::size_t i = 0; i <= k; ++i) {
            const auto jitter = [&](std::size_t idx) {
                if (idx == 0) return rng.uniform(0.0, 0.08) * cell;         // inwards only
                if (idx == k) return -rng.uniform(0.0, 0.08) * cell;
                return rng.uniform(-0.18, 0.18) * cell;
            };
            const double u = (-1.0 + double(i) * cell + jitter(i)) * h.x;
            const double v = (-1.0 + double(j) * cell + jitter(j)) * h.y;
            const Vec2 p = c + Vec2(cs * u - sn * v, sn * u + cs * v);
            const std::size_t degree = (i == 0 || i == k ? 1 : 2) + (j == 0 || j == k ? 1 : 2);
            pos[j * k1 + i] = p;
            node[j * k1 + i] = addNode(layer, p, degree);
        }
    // Mostly straight borders, some quadratic; outer borders only bulge inwards.
    const auto border = [&](std::size_t a, std::size_t b, bool outer) {
        const Vec2 A = pos[a], B = pos[b];
        std::vector<Vertex> v;
        v.reserve(3);
        v.push_back(onCurve(A));
        if (rng.chance(0.45)) {
            const Vec2 mid = (A + B) * 0.5, n = perp(B - A);  // |n| = chord length
            double bulge = outer ? rng.uniform(0.03, 0.12) : rng.uniform(-0.12, 0.12);
            if (outer && glm::dot(n, c - mid) < 0.0) bulge = -bulge;
            v.push_back(control(mid + n * bulge));
        }
        v.push_back(onCurve(B));
        return layer.addCurve(makeCurve(std::move(v), node[a], node[b], 0.0f, kFieldWf, 0, outer ? 1 : 2));
    };
    std::vector<ElementId> hc(k * k1), vc(k * k1);  // hc[j*k+i]: (i,j)-(i+1,j); vc[i*k+j]: (i,j)-(i,j+1)
    for (std::size_t j = 0; j <= k; ++j)
        for (std::size_t i = 0; i < k; ++i) hc[j * k + i] = border(j * k1 + i, j * k1 + i + 1, j == 0 || j == k);
    for (std::size_t i = 0; i <= k; ++i)
        for (std::size_t j = 0; j < k; ++j) vc[i * k + j] = border(j * k1 + i, (j + 1) * k1 + i, i == 0 || i == k);
    for (std::size_t j = 0; j < k; ++j)
        for (std::size_t i = 0; i < k; ++i) {
            Area a;
            a.wf = kFieldWf;
            a.cls = std::uint16_t(rng.below(6));  // crop type
            a.loops.push_back({{hc[j * k + i], false}, {vc[(i + 1) * k + j], false},
                               {hc[(j + 1) * k + i], true}, {vc[i * k + j], true}});
            layer.addArea(std::move(a));
        }
}

// Free slots of about t x t metres tiling the blocks.
std::vector<Box> freeSlots(const Context& ctx, double t) {
    std::vector<Box> slots;
    for (const Box& b : ctx.blocks) {
        const Vec2 size = b.size();
        const auto count = [&](double len) {
            return len < 0.5 * t ? std::size_t(0) : std::max<std::size_t>(1, std::size_t(std::lround(len / t)));
        };
        const std::size_t nx = count(size.x), ny = count(size.y);
        const Vec2 step(size.x / double(std::max<std::size_t>(nx, 1)), size.y / double(std::max<std::size_t>(ny, 1)));
        for (std::size_t y = 0; y < ny; ++y)
            for (std::size_t x = 0; x < nx; ++x) {
                const Vec2 lo = b.min + step * Vec2(double(x), double(y));
                const Box s{lo, lo + step};
                if (!ctx.occ.any(s, kBlocked)) slots.push_back(s);
            }
    }
    return slots;
}

}  // namespace

void buildLakes(Layer& layer, Context& ctx, Rng& rng) {
    if (ctx.target < 500) return;
    buildBlobs(layer, ctx, rng, std::max<std::size_t>(1, ctx.target / 10000), 150.0, 450.0, 3, 6, kLakeWf, 0.25);
}

void buildForests(Layer& layer, Context& ctx, Rng& rng) {
    if (ctx.target < 300) return;
    buildBlobs(layer, ctx, rng, std::max<std::size_t>(1, ctx.target / 500), 150.0, 600.0, 2, 4, kForestWf, 0.12);
}

void buildFields(Context& ctx, Rng& rng, std::size_t curveBudget, std::size_t partCurves,
                 const std::function<void(Layer&& part)>& sink) {
    if (curveBudget < patchCurves(1)) return;
    constexpr double kMeanCurves = 0.9 * 12.0 + 0.1 * 24.0;  // 2x2 patches, 10% of 3x3
    constexpr double kMeadows = 0.1;                         // fraction of slots left empty
    double freeArea = 0.0;
    for (const Box& b : ctx.blocks) freeArea += b.size().x * b.size().y * ctx.occ.freeFraction(b, kBlocked);
    const double wanted = std::max(1.0, double(curveBudget) / kMeanCurves / (1.0 - kMeadows));
    // Slot size from the free area, adjusted until the slot count is just above the wanted one.
    double t = std::sqrt(freeArea / wanted);
    std::vector<Box> slots = freeSlots(ctx, t), best;
    for (int it = 0; it < 10; ++it) {
        const double ratio = double(slots.size()) / wanted;
        if (ratio >= 0.97 && (best.empty() || slots.size() < best.size())) best = slots;
        if (ratio >= 0.97 && ratio <= 1.08) break;
        t *= slots.empty() ? 0.5 : std::clamp(std::sqrt(ratio * (1.0 / 1.02)), 0.7, 1.3);
        slots = freeSlots(ctx, t);
    }
    if (!best.empty()) slots = std::move(best);
    // Patch sizes, drawn over the slots in random order until the budget is spent; then the
    // patches are built in slot order (blocks in grid order) for spatial coherence.
    std::vector<std::size_t> order(slots.size()), size(slots.size(), 0);
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
    std::size_t left = curveBudget, curves = 0, areas = 0, nodes = 0;
    for (std::size_t i = 0; i < order.size() && left >= patchCurves(1); ++i) {
        const double perSlot = double(left) / double(order.size() - i);
        if (perSlot < kMeanCurves * (1.0 - kMeadows) && rng.chance(kMeadows)) continue;
        const double p3 = std::clamp((perSlot - 12.0) / 12.0, 0.1, 1.0);
        std::size_t k = left >= patchCurves(3) && rng.chance(p3) ? 3 : left >= patchCurves(2) ? 2 : 1;
        if (perSlot > 24.0 && left >= patchCurves(4) && rng.chance((perSlot - 24.0) / 16.0)) k = 4;  // scarce space
        size[order[i]] = k;
        left -= patchCurves(k);
        curves += patchCurves(k), areas += k * k, nodes += (k + 1) * (k + 1);
    }
    // The part's arrays reserved at their final size (the whole layer in one part, when it fits).
    const double share = std::min(1.0, double(std::max<std::size_t>(partCurves, 1)) / double(std::max<std::size_t>(curves, 1)));
    const auto reserve = [&](Layer& part) {
        part.nodes.reserve(std::size_t(double(nodes) * share) + 16);
        part.curves.reserve(std::min(curves, std::max<std::size_t>(partCurves, 1)) + patchCurves(4));
        part.areas.reserve(std::size_t(double(areas) * share) + 16);
    };
    Layer part;
    reserve(part);
    for (std::size_t i = 0; i < slots.size(); ++i) {
        if (size[i] == 0) continue;
        addPatch(part, rng, slots[i], size[i]);
        if (part.curves.size() >= partCurves) {
            sink(std::move(part));
            part = Layer{};
            reserve(part);
        }
    }
    if (!part.curves.empty()) sink(std::move(part));
}

}  // namespace lacet::synth
