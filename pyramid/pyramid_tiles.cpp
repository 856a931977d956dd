#include "pyramid/pyramid_tiles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "raster/appearance_producer.h"

namespace lacet {

bool PyramidImage::hasWater() const {
    return std::any_of(water.begin(), water.end(), [](std::uint8_t m) { return m != 0; });
}

PyramidImage pyramidImage(const AppearanceTile& tile) {
    std::vector<std::uint8_t> uniformTexels;  // a uniform tile's texels, made here (the others are read in place)
    if (tile.uniform) uniformTexels = tileTexels(tile);
    const std::vector<std::uint8_t>& texels = tile.uniform ? uniformTexels : tile.rgbm;
    const int n = tile.resolution;
    PyramidImage image;
    image.size = n;
    image.rgb.resize(std::size_t(n) * std::size_t(n) * 3);
    image.water.resize(std::size_t(n) * std::size_t(n));
    for (int row = 0; row < n; ++row) {
        const int j = n - 1 - row;  // tile rows grow with y
        std::uint8_t* rgb = image.rgb.data() + std::size_t(row) * std::size_t(n) * 3;
        std::uint8_t* water = image.water.data() + std::size_t(row) * std::size_t(n);
        const std::uint8_t* src = texels.data() + tile.index(0, j);
        for (int i = 0; i < n; ++i, src += 4) {
            rgb[3 * i] = src[0];
            rgb[3 * i + 1] = src[1];
            rgb[3 * i + 2] = src[2];
            water[i] = src[3];
        }
    }
    return image;
}

PyramidImage mipmap(const std::array<const PyramidImage*, 4>& children) {
    const int n = children[0] ? children[0]->size : 0;
    for (const PyramidImage* c : children)
        if (!c || c->size != n || n % 2 != 0 || n <= 0 || c->rgb.size() != std::size_t(n) * std::size_t(n) * 3 ||
            c->water.size() != std::size_t(n) * std::size_t(n))
            throw std::invalid_argument("mipmap(): four children of one even size required");
    PyramidImage parent;
    parent.size = n;
    parent.rgb.resize(std::size_t(n) * std::size_t(n) * 3);
    parent.water.resize(std::size_t(n) * std::size_t(n));
    const int half = n / 2;
    const std::size_t stride = std::size_t(n);
    for (int row = 0; row < n; ++row) {
        for (int col = 0; col < n; ++col) {
            // Top rows of the parent are its upper children (2, 3).
            const int k = (col >= half ? 1 : 0) + (row < half ? 2 : 0);
            const PyramidImage& c = *children[std::size_t(k)];
            const std::size_t cx = std::size_t(2 * (col % half)), cy = std::size_t(2 * (row % half));
            const std::size_t t00 = cy * stride + cx, t01 = t00 + 1, t10 = t00 + stride, t11 = t10 + 1;
            const std::size_t p = std::size_t(row) * stride + std::size_t(col);
            for (std::size_t ch = 0; ch < 3; ++ch)
                parent.rgb[3 * p + ch] = std::uint8_t(
                    (unsigned(c.rgb[3 * t00 + ch]) + c.rgb[3 * t01 + ch] + c.rgb[3 * t10 + ch] + c.rgb[3 * t11 + ch] + 2) / 4);
            parent.water[p] = std::uint8_t((unsigned(c.water[t00]) + c.water[t01] + c.water[t10] + c.water[t11] + 2) / 4);
        }
    }
    return parent;
}

AppearanceTile appearanceTile(const PyramidImage& image, const Box& bounds, int border) {
    const int n = image.size;
    if (n <= 0 || border < 0 || image.rgb.size() != std::size_t(n) * std::size_t(n) * 3 ||
        image.water.size() != std::size_t(n) * std::size_t(n))
        throw std::invalid_argument("appearanceTile(): an image of size > 0 with its planes, border >= 0 required");
    AppearanceTile t;
    t.bounds = bounds;
    t.resolution = n;
    t.border = border;
    t.stride = n + 2 * border;
    t.delta = bounds.size().x / double(n);
    t.rgbm.resize(std::size_t(t.stride) * std::size_t(t.stride) * 4);
    for (int j = -border; j < n + border; ++j) {
        const int row = n - 1 - std::clamp(j, 0, n - 1);
        for (int i = -border; i < n + border; ++i) {
            const std::size_t src = std::size_t(row) * std::size_t(n) + std::size_t(std::clamp(i, 0, n - 1));
            std::uint8_t* dst = t.rgbm.data() + t.index(i, j);
            dst[0] = image.rgb[3 * src];
            dst[1] = image.rgb[3 * src + 1];
            dst[2] = image.rgb[3 * src + 2];
            dst[3] = image.water[src];
        }
    }
    return t;
}

ElevationCells elevationCells(const ElevationTile& tile) {
    const int n = tile.resolution;
    ElevationCells cells;
    cells.size = n;
    cells.z.resize(std::size_t(n) * std::size_t(n));
    double sum = 0.0, sum2 = 0.0;
    cells.min = INFINITY;
    cells.max = -INFINITY;
    for (int row = 0; row < n; ++row) {
        const int j = n - 1 - row;
        for (int i = 0; i < n; ++i) {
            const float z = 0.25f * (tile.zm[tile.index(i, j)] + tile.zm[tile.index(i + 1, j)] + tile.zm[tile.index(i, j + 1)] +
                                     tile.zm[tile.index(i + 1, j + 1)]);
            cells.z[std::size_t(row) * std::size_t(n) + std::size_t(i)] = z;
            sum += double(z);
            sum2 += double(z) * double(z);
            cells.min = std::min(cells.min, double(z));
            cells.max = std::max(cells.max, double(z));
        }
    }
    const double count = double(cells.z.size());
    cells.mean = sum / count;
    cells.stdDev = std::sqrt(std::max(0.0, sum2 / count - cells.mean * cells.mean));
    return cells;
}

}  // namespace lacet
