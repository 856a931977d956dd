#pragma once
// Renders a hand-made scene (tests/raster/hand_scenes.h) as the appearance of the 4 quads of
// level 1, one RGB mosaic of 2 * resolution pixels a side, north up, over a gently sloping DEM.

#include <cstdint>
#include <vector>

#include "model/quadtree.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "raster/tile_images.h"

namespace lacet::test {

inline Dem gentleSlope(const Box& extent) {
    std::vector<float> h(64);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) h[std::size_t(j * 8 + i)] = 900.0f + 3.0f * float(i) + 2.0f * float(j);
    return Dem(extent, 8, 8, std::move(h));
}

inline std::vector<std::uint8_t> renderHandScene(const Scene& scene, const AppearanceParams& params = {}, int resolution = 128,
                                                 AppearanceCounters* counters = nullptr) {
    const Dem dem = gentleSlope(scene.extent);
    Quadtree qt(scene, RefineParams{{.resolution = resolution}});
    qt.subdivide(qt.root());
    DemHeightField heights(dem);
    CurveDataCache data(qt, heights);
    const int n = resolution, side = 2 * n;
    std::vector<std::uint8_t> mosaic(std::size_t(side) * std::size_t(side) * 3), rgb;
    for (int k = 0; k < 4; ++k) {
        const AppearanceTile tile = produceAppearance(*qt.root().children[std::size_t(k)], qt, data, dem, params, counters);
        appearanceImage(tile, rgb);
        const int ox = (k & 1) * n, oy = (1 - (k >> 1)) * n;
        for (int r = 0; r < n; ++r)
            std::copy_n(rgb.begin() + std::ptrdiff_t(r) * n * 3, n * 3, mosaic.begin() + (std::ptrdiff_t(oy + r) * side + ox) * 3);
    }
    return mosaic;
}

}  // namespace lacet::test
