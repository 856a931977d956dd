// The synthetic DEM finer than memory: base, detail, fade near rivers. See synth/fine_synthetic_dem.h.
#include "synth/fine_synthetic_dem.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model/bezier.h"

namespace lacet {
namespace {

// The distance field's lower bound is its bilinear value less this many distance cells: the
// interpolation reads corners up to a cell diagonal (sqrt 2) away, the curves' samples are a
// quarter cell from the curves at most.
constexpr double kDistanceSlack = 1.75;

std::uint64_t splitmix64(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

// A lattice value in [-1, 1].
double lattice(std::uint64_t seed, std::uint64_t octave, std::int64_t ix, std::int64_t iy) {
    const std::uint64_t h = splitmix64(splitmix64(seed ^ (octave << 56)) ^ (std::uint64_t(std::uint32_t(ix)) << 32 | std::uint32_t(iy)));
    return double(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

double smooth(double f) { return f * f * (3.0 - 2.0 * f); }

double clampedSmooth(double t) { return smooth(std::clamp(t, 0.0, 1.0)); }

}  // namespace

FineSyntheticDem::FineSyntheticDem(const Scene& scene, const Dem& base, const FineDemParams& p) : base_(base), params_(p) {
    if (p.side < 2) throw std::invalid_argument("FineDemParams: side must be >= 2");
    if (!(p.amplitude > 0.0)) throw std::invalid_argument("FineDemParams: amplitude must be > 0");
    if (!(p.shortestWavelength > 0.0) || !(p.longestWavelength >= p.shortestWavelength))
        throw std::invalid_argument("FineDemParams: wavelengths must be > 0, the longest >= the shortest");
    if (!(p.riverFade >= 0.0)) throw std::invalid_argument("FineDemParams: riverFade must be >= 0");
    if (!(p.distanceCell > 0.0)) throw std::invalid_argument("FineDemParams: distanceCell must be > 0");
    extent_ = scene.extent;
    if (!(extent_.size().x > 0.0) || std::abs(extent_.size().x - extent_.size().y) > 1e-6 * extent_.size().x)
        throw std::invalid_argument("FineSyntheticDem: the scene's extent must be a square");
    cell_ = extent_.size().x / p.side;

    // Octaves from the longest wavelength down, amplitudes halving, summing to `amplitude`.
    double sum = 0.0;
    for (double w = p.longestWavelength, a = 1.0; w >= p.shortestWavelength * (1.0 - 1e-9); w /= 2.0, a /= 2.0) {
        wavelengths_.push_back(w);
        amplitudes_.push_back(a);
        sum += a;
    }
    for (double& a : amplitudes_) a *= p.amplitude / sum;

    // Distance to the river curves on the coarse grid, capped where the detail is full.
    const double dc = p.distanceCell, cap = 2.0 * p.riverFade + 2.0 * kDistanceSlack * dc;
    dw_ = std::max(1, int(std::ceil(extent_.size().x / dc)));
    dh_ = std::max(1, int(std::ceil(extent_.size().y / dc)));
    distance_.assign(std::size_t(dw_) * std::size_t(dh_), float(cap));
    auto stamp = [&](Vec2 q) {
        const Vec2 lo = (q - cap - extent_.min) / dc - 0.5, hi = (q + cap - extent_.min) / dc - 0.5;
        const int i0 = std::max(0, int(std::ceil(lo.x))), i1 = std::min(dw_ - 1, int(std::floor(hi.x)));
        const int j0 = std::max(0, int(std::ceil(lo.y))), j1 = std::min(dh_ - 1, int(std::floor(hi.y)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const Vec2 c = extent_.min + (Vec2(i, j) + 0.5) * dc;
                float& d = distance_[std::size_t(j) * std::size_t(dw_) + std::size_t(i)];
                d = std::min(d, float(glm::distance(c, q)));
            }
    };
    for (const Layer& layer : scene.layers) {
        if (layer.kind != LayerKind::Rivers) continue;
        for (const Curve& c : layer.curves) {
            if (!c.alive || c.vertices.size() < 2) continue;
            stamp(c.vertices.front().p);
            forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
                double polygon = 0.0;
                for (int k = 0; k < b.degree; ++k) polygon += glm::distance(b.p[std::size_t(k)], b.p[std::size_t(k + 1)]);
                const auto n = std::max<std::size_t>(1, std::size_t(std::ceil(polygon / (0.5 * dc))));
                for (std::size_t k = 1; k <= n; ++k) stamp(evaluate(b, double(k) / double(n)));
            });
        }
    }
}

Vec2 FineSyntheticDem::topLeft() const { return position(0, 0); }

Vec2 FineSyntheticDem::position(int i, int t) const {
    return {extent_.min.x + (i + 0.5) * cell_, extent_.max.y - (t + 0.5) * cell_};
}

double FineSyntheticDem::fade(Vec2 p) const {
    const double dc = params_.distanceCell;
    const Vec2 g = (p - extent_.min) / dc - 0.5;
    const int i0 = std::clamp(int(std::floor(g.x)), 0, std::max(0, dw_ - 2)), j0 = std::clamp(int(std::floor(g.y)), 0, std::max(0, dh_ - 2));
    const int i1 = std::min(i0 + 1, dw_ - 1), j1 = std::min(j0 + 1, dh_ - 1);
    const double a = std::clamp(g.x - i0, 0.0, 1.0), b = std::clamp(g.y - j0, 0.0, 1.0);
    auto d = [&](int i, int j) { return double(distance_[std::size_t(j) * std::size_t(dw_) + std::size_t(i)]); };
    const double bilinear = (1 - a) * (1 - b) * d(i0, j0) + a * (1 - b) * d(i1, j0) + (1 - a) * b * d(i0, j1) + a * b * d(i1, j1);
    const double lower = bilinear - kDistanceSlack * dc;
    if (params_.riverFade <= 0.0) return lower > 0.0 ? 1.0 : 0.0;
    return clampedSmooth((lower - params_.riverFade) / params_.riverFade);
}

double FineSyntheticDem::detail(Vec2 p) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < wavelengths_.size(); ++k) {
        const Vec2 g = (p - extent_.min) / wavelengths_[k];
        const double fx = std::floor(g.x), fy = std::floor(g.y);
        const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
        const double u = smooth(g.x - fx), v = smooth(g.y - fy);
        const double v00 = lattice(params_.seed, k, ix, iy), v10 = lattice(params_.seed, k, ix + 1, iy);
        const double v01 = lattice(params_.seed, k, ix, iy + 1), v11 = lattice(params_.seed, k, ix + 1, iy + 1);
        sum += amplitudes_[k] * ((1 - v) * ((1 - u) * v00 + u * v10) + v * ((1 - u) * v01 + u * v11));
    }
    return sum;
}

void FineSyntheticDem::row(int t, std::span<float> heights) const {
    if (t < 0 || t >= params_.side || heights.size() != std::size_t(params_.side))
        throw std::invalid_argument("FineSyntheticDem::row(): row or size out of range");
    for (int i = 0; i < params_.side; ++i) {
        const Vec2 p = position(i, t);
        const double f = fade(p);
        heights[std::size_t(i)] = float(base_.sample(p) + (f > 0.0 ? f * detail(p) : 0.0));
    }
}

}  // namespace lacet
