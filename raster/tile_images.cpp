#include "raster/tile_images.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "raster/appearance_producer.h"

namespace lacet {
namespace {

// Altitude tint: green lowlands to brown to white summits (metres).
glm::dvec3 tint(double z) {
    const double t = std::clamp(z / 2500.0, 0.0, 1.0);
    const glm::dvec3 low(0.45, 0.62, 0.35), mid(0.62, 0.52, 0.38), high(0.95, 0.95, 0.95);
    return t < 0.5 ? low + (mid - low) * (t * 2.0) : mid + (high - mid) * (t * 2.0 - 1.0);
}

double shadeAt(const ElevationTile& t, int i, int j) {
    const double dzdx = (t.zm[t.index(i + 1, j)] - t.zm[t.index(i - 1, j)]) / (2.0 * t.delta);
    const double dzdy = (t.zm[t.index(i, j + 1)] - t.zm[t.index(i, j - 1)]) / (2.0 * t.delta);
    const glm::dvec3 n = glm::normalize(glm::dvec3(-dzdx, -dzdy, 1.0));
    const glm::dvec3 light = glm::normalize(glm::dvec3(-1.0, 1.0, std::sqrt(2.0)));
    return 0.25 + 0.75 * std::max(0.0, glm::dot(n, light));
}

template <class F>
void eachPixel(const ElevationTile& t, std::vector<std::uint8_t>& rgb, F&& colour) {
    const int n = t.resolution;
    rgb.resize(std::size_t(n) * std::size_t(n) * 3);
    for (int row = 0; row < n; ++row)
        for (int i = 0; i < n; ++i) {
            const int j = n - 1 - row;  // north up
            const glm::dvec3 c = glm::clamp(colour(i, j), 0.0, 1.0);
            const std::size_t k = (std::size_t(row) * std::size_t(n) + std::size_t(i)) * 3;
            for (int ch = 0; ch < 3; ++ch) rgb[k + std::size_t(ch)] = std::uint8_t(std::lround(c[ch] * 255.0));
        }
}

}  // namespace

void hillshade(const ElevationTile& t, std::vector<std::uint8_t>& rgb) {
    eachPixel(t, rgb, [&](int i, int j) { return tint(t.zm[t.index(i, j)]) * shadeAt(t, i, j); });
}

void footprintImage(const ElevationTile& t, std::vector<std::uint8_t>& rgb) {
    eachPixel(t, rgb, [&](int i, int j) {
        const double b = t.b[t.index(i, j)];
        const glm::dvec3 ground = glm::dvec3(0.5) * shadeAt(t, i, j);
        return ground * (1.0 - b) + glm::dvec3(0.9, 0.15, 0.1) * b;
    });
}

void appearanceImage(const AppearanceTile& t, std::vector<std::uint8_t>& rgb) {
    const std::vector<std::uint8_t> texels = tileTexels(t);
    const int n = t.resolution;
    rgb.resize(std::size_t(n) * std::size_t(n) * 3);
    for (int row = 0; row < n; ++row)
        for (int i = 0; i < n; ++i) {
            const std::uint8_t* texel = &texels[t.index(i, n - 1 - row)];  // north up
            std::copy_n(texel, 3, &rgb[(std::size_t(row) * std::size_t(n) + std::size_t(i)) * 3]);
        }
}

}  // namespace lacet
