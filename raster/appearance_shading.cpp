#include "raster/appearance_shading.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <glm/geometric.hpp>

#include "raster/float4.h"

namespace lacet {
namespace {

glm::vec3 mix(glm::vec3 a, glm::vec3 b, double t) {
    const float f = float(std::clamp(t, 0.0, 1.0));
    return a + (b - a) * f;
}

// A 32-bit integer hash (lowbias32, Chris Wellons), for deterministic per-element and per-cell
// variation.
std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}
double unit(std::uint32_t h) { return double(h >> 8) / double(1u << 24); }  // [0, 1)

double latticeValue(std::int64_t x, std::int64_t y, std::uint32_t seed) {
    return unit(hash32(std::uint32_t(x) * 0x9e3779b9U ^ hash32(std::uint32_t(y) ^ seed)));
}

// Value noise in [0, 1] with cells of `cell` metres, smooth (C1) between cell corners. The
// corner values come from `lattice` when it holds them (the same values, so the same result).
double valueNoise(Vec2 p, double cell, std::uint32_t seed, const NoiseLattice* lattice = nullptr) {
    const Vec2 q = p / cell;
    const double fx = std::floor(q.x), fy = std::floor(q.y);
    const auto ix = std::int64_t(fx), iy = std::int64_t(fy);
    double a, b, c, d;
    if (lattice && lattice->holds(ix, iy)) {
        const double* row = &lattice->values[std::size_t(iy - lattice->y0) * std::size_t(lattice->nx) + std::size_t(ix - lattice->x0)];
        a = row[0], b = row[1], c = row[lattice->nx], d = row[lattice->nx + 1];
    } else {
        a = latticeValue(ix, iy, seed), b = latticeValue(ix + 1, iy, seed);
        c = latticeValue(ix, iy + 1, seed), d = latticeValue(ix + 1, iy + 1, seed);
    }
    double tx = q.x - fx, ty = q.y - fy;
    tx = tx * tx * (3.0 - 2.0 * tx);
    ty = ty * ty * (3.0 - 2.0 * ty);
    return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

// Weight of a pattern of period `period` metres at this texel size: 1 when a period spans 6
// texels or more, 0 at 2 texels or less (it would alias), linear between.
double patternWeight(double period, double texel) { return std::clamp((period / texel - 2.0) / 4.0, 0.0, 1.0); }

constexpr glm::vec3 kWater(0.10f, 0.24f, 0.33f);
constexpr glm::vec3 kCrops[6] = {{0.78f, 0.70f, 0.38f}, {0.42f, 0.58f, 0.25f}, {0.47f, 0.36f, 0.25f},
                                 {0.50f, 0.64f, 0.30f}, {0.84f, 0.79f, 0.27f}, {0.70f, 0.62f, 0.45f}};
constexpr double kFurrowSpacing = 3.0;   // m
constexpr double kCanopyCell = 12.0;     // m
constexpr double kCanopyDetail = 4.0;    // m
constexpr std::uint32_t kCanopySeeds[2] = {0x51f15eedU, 0x2545f491U};

}  // namespace

glm::vec3 groundColour(double z, double slope) {
    const glm::vec3 grass(0.40f, 0.52f, 0.28f), meadow(0.53f, 0.56f, 0.34f), rock(0.50f, 0.47f, 0.43f), snow(0.92f, 0.93f, 0.95f);
    glm::vec3 c = z < 1800.0 ? mix(grass, meadow, (z - 1200.0) / 600.0)
                             : z < 2500.0 ? mix(meadow, rock, (z - 1800.0) / 700.0) : mix(rock, snow, (z - 2500.0) / 300.0);
    return mix(c, rock, (slope - 0.6) / 0.4);
}

SurfaceShader::SurfaceShader(const SurfaceShade& shade, double texel) : shade_(shade) {
    switch (shade.surface) {
        case Surface::Water:
            base_ = kWater;
            mask_ = 1.0f;
            break;
        case Surface::Field: {
            const std::uint32_t h = hash32(shade.seed * 2654435761U + 17U);
            base_ = kCrops[shade.cls % 6] * float(0.88 + 0.24 * unit(h));
            const double angle = std::numbers::pi * unit(hash32(h));
            direction_ = Vec2(std::cos(angle), std::sin(angle)) * (2.0 * std::numbers::pi / kFurrowSpacing);
            weight_[0] = 0.12 * patternWeight(kFurrowSpacing, texel);
            break;
        }
        case Surface::Forest:
            base_ = glm::vec3(0.16f, 0.30f, 0.14f);
            weight_[0] = 0.6 * patternWeight(kCanopyCell, texel);
            weight_[1] = 0.36 * patternWeight(kCanopyDetail, texel);
            break;
        case Surface::Other:
            base_ = glm::vec3(0.60f, 0.58f, 0.52f);
            break;
        case Surface::None:
            break;
    }
}

void SurfaceShader::prepare(const Box& box) {
    if (shade_.surface != Surface::Forest) return;
    const double cells[2] = {kCanopyCell, kCanopyDetail};
    for (int o = 0; o < 2; ++o) {
        NoiseLattice& l = lattice_[o];
        l.x0 = std::int64_t(std::floor(box.min.x / cells[o])) - 1;
        l.y0 = std::int64_t(std::floor(box.min.y / cells[o])) - 1;
        l.nx = int(std::int64_t(std::floor(box.max.x / cells[o])) - l.x0 + 3);
        l.ny = int(std::int64_t(std::floor(box.max.y / cells[o])) - l.y0 + 3);
        if (weight_[o] == 0.0 || std::int64_t(l.nx) * l.ny > 1 << 20) {
            l.nx = l.ny = 0;
            continue;
        }
        l.values.resize(std::size_t(l.nx) * std::size_t(l.ny));
        for (int j = 0; j < l.ny; ++j)
            for (int i = 0; i < l.nx; ++i) l.values[std::size_t(j) * std::size_t(l.nx) + std::size_t(i)] = latticeValue(l.x0 + i, l.y0 + j, kCanopySeeds[o]);
    }
}

void SurfaceShader::prepareBlocks(double step) {
    step_ = step;
    tables_ = shade_.surface == Surface::Field && weight_[0] != 0.0;
    if (!tables_) return;
    for (int i = 0; i < kMaxBlock; ++i) {
        cosX_[i] = std::cos(double(i) * step * direction_.x);
        sinX_[i] = std::sin(double(i) * step * direction_.x);
        cosY_[i] = std::cos(double(i) * step * direction_.y);
        sinY_[i] = std::sin(double(i) * step * direction_.y);
    }
}

void SurfaceShader::block(Vec2 start, int nx, int ny, Rgbm* out, std::size_t stride) const {
    if (shade_.surface == Surface::Forest) {
        forestBlock(start, nx, ny, out, stride);
        return;
    }
    if (!tables_) {  // not a field with a pattern
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) out[std::size_t(j) * stride + std::size_t(i)] = at(start + Vec2(double(i), double(j)) * step_);
        return;
    }
    // cos(a + b) = cos a cos b - sin a sin b and sin(a + b) = sin a cos b + cos a sin b: from the
    // block's first point down the column (j), then along each row (i).
    const double phase = start.x * direction_.x + start.y * direction_.y;
    const double c0 = fastCos(phase), s0 = fastCos(phase - 0.5 * std::numbers::pi);
    const Float4 base{base_.r, base_.g, base_.b, 0.0f};
    for (int j = 0; j < ny; ++j) {
        const double c = c0 * cosY_[j] - s0 * sinY_[j], s = s0 * cosY_[j] + c0 * sinY_[j];
        float factor[kMaxBlock];
        for (int i = 0; i < nx; ++i) factor[i] = float(1.0 + weight_[0] * (c * cosX_[i] - s * sinX_[i]));
        Rgbm* row = out + std::size_t(j) * stride;
        for (int i = 0; i < nx; ++i) {  // base_ * factor, the three channels at once
            const Float4 v = base * factor[i];
            std::memcpy(&row[i], &v, sizeof v);
        }
    }
}

// forestAt's arithmetic, with what depends on x alone (the cell column, its smoothed fraction)
// made once per column and what depends on y once per row: the same doubles, so the same colours.
void SurfaceShader::forestBlock(Vec2 start, int nx, int ny, Rgbm* out, std::size_t stride) const {
    const double cells[2] = {kCanopyCell, kCanopyDetail};
    struct Axis {
        std::int64_t cell[kMaxBlock];
        double smooth[kMaxBlock];
    };
    Axis columns[2];
    int octaves[2], count = 0;
    for (int o = 0; o < 2; ++o) {
        if (!(weight_[o] > 0.0)) continue;
        octaves[count++] = o;
        for (int i = 0; i < nx; ++i) {
            const double q = (start.x + double(i) * step_) / cells[o], f = std::floor(q), t = q - f;
            columns[o].cell[i] = std::int64_t(f);
            columns[o].smooth[i] = t * t * (3.0 - 2.0 * t);
        }
    }
    for (int j = 0; j < ny; ++j) {
        const double y = start.y + double(j) * step_;
        double n[kMaxBlock] = {};
        for (int c = 0; c < count; ++c) {
            const int o = octaves[c];
            const double q = y / cells[o], f = std::floor(q), t = q - f;
            const std::int64_t iy = std::int64_t(f);
            const double ty = t * t * (3.0 - 2.0 * t);
            const NoiseLattice& l = lattice_[o];
            const auto corners = [&](std::int64_t ix, double& a, double& b, double& cc, double& d) {
                if (l.holds(ix, iy)) {
                    const double* row = &l.values[std::size_t(iy - l.y0) * std::size_t(l.nx) + std::size_t(ix - l.x0)];
                    a = row[0], b = row[1], cc = row[l.nx], d = row[l.nx + 1];
                } else {
                    a = latticeValue(ix, iy, kCanopySeeds[o]), b = latticeValue(ix + 1, iy, kCanopySeeds[o]);
                    cc = latticeValue(ix, iy + 1, kCanopySeeds[o]), d = latticeValue(ix + 1, iy + 1, kCanopySeeds[o]);
                }
            };
            const double w = weight_[o];
            const double* smooth = columns[o].smooth;
            if (columns[o].cell[0] == columns[o].cell[nx - 1]) {  // the row within one cell: its corners once
                double a, b, cc, d;
                corners(columns[o].cell[0], a, b, cc, d);
                for (int i = 0; i < nx; ++i) {
                    const double tx = smooth[i];
                    n[i] += w * (((a + (b - a) * tx) + ((cc + (d - cc) * tx) - (a + (b - a) * tx)) * ty) - 0.5);
                }
                continue;
            }
            for (int i = 0; i < nx; ++i) {
                double a, b, cc, d;
                corners(columns[o].cell[i], a, b, cc, d);
                const double tx = smooth[i];
                n[i] += w * (((a + (b - a) * tx) + ((cc + (d - cc) * tx) - (a + (b - a) * tx)) * ty) - 0.5);
            }
        }
        Rgbm* row = out + std::size_t(j) * stride;
        for (int i = 0; i < nx; ++i) row[i] = Rgbm(base_ * float(1.0 + n[i]), 0.0f);
    }
}

Rgbm SurfaceShader::forestAt(Vec2 p) const {
    double n = 0.0;
    if (weight_[0] > 0.0) n += weight_[0] * (valueNoise(p, kCanopyCell, kCanopySeeds[0], &lattice_[0]) - 0.5);
    if (weight_[1] > 0.0) n += weight_[1] * (valueNoise(p, kCanopyDetail, kCanopySeeds[1], &lattice_[1]) - 0.5);
    return Rgbm(base_ * float(1.0 + n), 0.0f);
}

Rgbm surfaceColour(const SurfaceShade& shade, Vec2 p, double texel) { return SurfaceShader(shade, texel).at(p); }

glm::vec3 borderStripColour(Surface surface) {
    switch (surface) {
        case Surface::Water: return {0.56f, 0.51f, 0.39f};
        case Surface::Field: return {0.36f, 0.48f, 0.24f};
        case Surface::Forest: return {0.26f, 0.40f, 0.19f};
        default: return {0.50f, 0.50f, 0.45f};
    }
}

glm::vec3 riverBankColour() { return {0.56f, 0.51f, 0.39f}; }
glm::vec3 tunnelPortalColour() { return {0.42f, 0.41f, 0.39f}; }

glm::vec3 roadColour(std::uint16_t cls) {
    switch (cls) {
        case 0: return {0.20f, 0.20f, 0.21f};
        case 1: return {0.27f, 0.27f, 0.27f};
        default: return {0.55f, 0.46f, 0.33f};
    }
}

glm::vec3 markingColour() { return {0.93f, 0.93f, 0.90f}; }
bool roadHasMarkings(std::uint16_t cls) { return cls <= 1; }

Surface surfaceOf(LayerKind kind) {
    switch (kind) {
        case LayerKind::Lakes: return Surface::Water;
        case LayerKind::Rivers: return Surface::Water;  // river areas (large rivers, §4.1)
        case LayerKind::Fields: return Surface::Field;
        case LayerKind::Forests: return Surface::Forest;
        case LayerKind::Other: return Surface::Other;
        default: return Surface::None;
    }
}

}  // namespace lacet
