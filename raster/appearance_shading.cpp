#include "raster/appearance_shading.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

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

// Value noise in [0, 1] with cells of `cell` metres, smooth (C1) between cell corners.
double valueNoise(Vec2 p, double cell, std::uint32_t seed) {
    const Vec2 q = p / cell;
    const double fx = std::floor(q.x), fy = std::floor(q.y);
    const auto corner = [&](double x, double y) {
        const auto ix = std::uint32_t(std::int64_t(x)), iy = std::uint32_t(std::int64_t(y));
        return unit(hash32(ix * 0x9e3779b9U ^ hash32(iy ^ seed)));
    };
    double tx = q.x - fx, ty = q.y - fy;
    tx = tx * tx * (3.0 - 2.0 * tx);
    ty = ty * ty * (3.0 - 2.0 * ty);
    const double a = corner(fx, fy), b = corner(fx + 1.0, fy), c = corner(fx, fy + 1.0), d = corner(fx + 1.0, fy + 1.0);
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

}  // namespace

glm::vec3 groundColour(double z, double slope) {
    const glm::vec3 grass(0.40f, 0.52f, 0.28f), meadow(0.53f, 0.56f, 0.34f), rock(0.50f, 0.47f, 0.43f), snow(0.92f, 0.93f, 0.95f);
    glm::vec3 c = z < 1800.0 ? mix(grass, meadow, (z - 1200.0) / 600.0)
                             : z < 2500.0 ? mix(meadow, rock, (z - 1800.0) / 700.0) : mix(rock, snow, (z - 2500.0) / 300.0);
    return mix(c, rock, (slope - 0.6) / 0.4);
}

Rgbm surfaceColour(const SurfaceShade& shade, Vec2 p, double texel) {
    switch (shade.surface) {
        case Surface::Water:
            return Rgbm(kWater, 1.0f);
        case Surface::Field: {
            const std::uint32_t h = hash32(shade.seed * 2654435761U + 17U);
            const glm::vec3 base = kCrops[shade.cls % 6] * float(0.88 + 0.24 * unit(h));
            const double angle = std::numbers::pi * unit(hash32(h));
            const double along = p.x * std::cos(angle) + p.y * std::sin(angle);
            const double furrow = std::cos(2.0 * std::numbers::pi * along / kFurrowSpacing);
            return Rgbm(base * float(1.0 + 0.12 * furrow * patternWeight(kFurrowSpacing, texel)), 0.0f);
        }
        case Surface::Forest: {
            const double coarse = valueNoise(p, kCanopyCell, 0x51f15eedU) - 0.5;
            const double fine = valueNoise(p, kCanopyDetail, 0x2545f491U) - 0.5;
            const double n = coarse * patternWeight(kCanopyCell, texel) + 0.6 * fine * patternWeight(kCanopyDetail, texel);
            return Rgbm(glm::vec3(0.16f, 0.30f, 0.14f) * float(1.0 + 0.6 * n), 0.0f);
        }
        case Surface::Other:
            return Rgbm(0.60f, 0.58f, 0.52f, 0.0f);
        case Surface::None:
            break;
    }
    return Rgbm(0.0f);
}

glm::vec3 borderStripColour(Surface surface) {
    switch (surface) {
        case Surface::Water: return {0.56f, 0.51f, 0.39f};
        case Surface::Field: return {0.36f, 0.48f, 0.24f};
        case Surface::Forest: return {0.26f, 0.40f, 0.19f};
        default: return {0.50f, 0.50f, 0.45f};
    }
}

glm::vec3 riverBankColour() { return {0.56f, 0.51f, 0.39f}; }

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
        case LayerKind::Fields: return Surface::Field;
        case LayerKind::Forests: return Surface::Forest;
        case LayerKind::Other: return Surface::Other;
        default: return Surface::None;
    }
}

}  // namespace lacet
