#pragma once
// The elevation texture of one quad (§5.2): per sample, the original height z_o, the footprint
// (enforced height z_e and blending coefficient b), the modified height z_m and the modified
// height at half resolution z_c.
//
// Grid convention: `resolution` + 1 samples per side lie on the quad, at its corners and every
// delta = size / resolution metres, so adjacent quads of one level share their border samples;
// `border` more samples lie outside on each side (the 3x3 filter and normals read them). Sample
// (i, j), -border <= i, j <= resolution + border, is at bounds.min + (i, j) * delta and is stored
// at index (j + border) * stride + (i + border).

#include <vector>

#include "model/types.h"

namespace lacet {

struct ElevationTile {
    Box bounds;
    int resolution = 0;
    int border = 0;
    double delta = 0.0;  // metres between samples
    int stride = 0;      // resolution + 1 + 2 * border
    std::vector<float> zo, ze, b, zm, zc;

    std::size_t index(int i, int j) const { return std::size_t(j + border) * std::size_t(stride) + std::size_t(i + border); }
    Vec2 position(int i, int j) const { return bounds.min + Vec2(double(i), double(j)) * delta; }
    friend bool operator==(const ElevationTile&, const ElevationTile&) = default;
};

}  // namespace lacet
