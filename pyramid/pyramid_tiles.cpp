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

namespace {
bool wellFormed(const PyramidImage* c, int n) {
    return c && c->size == n && n > 0 && c->rgb.size() == std::size_t(n) * std::size_t(n) * 3 &&
           c->water.size() == std::size_t(n) * std::size_t(n);
}
}  // namespace

PyramidImage halve(const PyramidImage& image) {
    const int n = image.size;
    if (!wellFormed(&image, n) || n % 2 != 0) throw std::invalid_argument("halve(): an image of even size with its planes required");
    const std::size_t half = std::size_t(n / 2), stride = std::size_t(n);
    PyramidImage h;
    h.size = int(half);
    h.rgb.resize(half * half * 3);
    h.water.resize(half * half);
    for (std::size_t r = 0; r < half; ++r) {
        const std::uint8_t* top = image.rgb.data() + 2 * r * stride * 3;
        const std::uint8_t* bottom = top + stride * 3;
        std::uint8_t* out = h.rgb.data() + r * half * 3;
        for (std::size_t x = 0; x < half * 3; x += 3) {
            const std::size_t a = 2 * x;  // texel 2x/3 of the row, in bytes
            for (std::size_t ch = 0; ch < 3; ++ch)
                out[x + ch] = std::uint8_t((unsigned(top[a + ch]) + top[a + 3 + ch] + bottom[a + ch] + bottom[a + 3 + ch] + 2) / 4);
        }
        const std::uint8_t* wt = image.water.data() + 2 * r * stride;
        const std::uint8_t* wb = wt + stride;
        std::uint8_t* wo = h.water.data() + r * half;
        for (std::size_t x = 0; x < half; ++x)
            wo[x] = std::uint8_t((unsigned(wt[2 * x]) + wt[2 * x + 1] + wb[2 * x] + wb[2 * x + 1] + 2) / 4);
    }
    return h;
}

PyramidImage assemble(const std::array<const PyramidImage*, 4>& halves) {
    const int h = halves[0] ? halves[0]->size : 0;
    for (const PyramidImage* c : halves)
        if (!wellFormed(c, h)) throw std::invalid_argument("assemble(): four images of one size > 0 with their planes required");
    const std::size_t half = std::size_t(h), n = 2 * half;
    PyramidImage parent;
    parent.size = int(n);
    parent.rgb.resize(n * n * 3);
    parent.water.resize(n * n);
    for (int k = 0; k < 4; ++k) {  // the parent's top rows are its upper children (2 left, 3 right)
        const PyramidImage& c = *halves[std::size_t(k)];
        const std::size_t col0 = (k & 1) ? half : 0, row0 = (k & 2) ? 0 : half;
        for (std::size_t r = 0; r < half; ++r) {
            std::copy_n(c.rgb.data() + r * half * 3, half * 3, parent.rgb.data() + ((row0 + r) * n + col0) * 3);
            std::copy_n(c.water.data() + r * half, half, parent.water.data() + (row0 + r) * n + col0);
        }
    }
    return parent;
}

PyramidImage mipmap(const std::array<const PyramidImage*, 4>& children) {
    const int n = children[0] ? children[0]->size : 0;
    for (const PyramidImage* c : children)
        if (!wellFormed(c, n) || n % 2 != 0) throw std::invalid_argument("mipmap(): four children of one even size required");
    const std::array<PyramidImage, 4> h{halve(*children[0]), halve(*children[1]), halve(*children[2]), halve(*children[3])};
    return assemble({&h[0], &h[1], &h[2], &h[3]});
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
