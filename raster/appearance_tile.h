#pragma once
// The appearance texture of one quad (§5.1): colour and water mask (RGBm, 8 bits each) per texel.
//
// Grid convention: `resolution` x `resolution` texels cover the quad; texel (i, j) covers
// bounds.min + [i, i+1) x [j, j+1) * delta and is sampled at its centre. `border` more texels lie
// outside on each side (for seamless filtering), so -border <= i, j < resolution + border; texel
// (i, j) is stored at 4 * ((j + border) * stride + (i + border)). Rows go with y (north up is
// row resolution - 1; images flip them).
//
// A uniform quad (inside one area, or inside one wide river) stores no texels: `rgbm` is empty
// and `shade` says what covers it; tileTexels() (raster/appearance_producer.h) makes its texels
// when an image needs them, equal bit for bit to what the producer would have drawn.

#include <cstdint>
#include <vector>

#include "model/types.h"

namespace lacet {

// What covers a uniform quad, enough to shade any point of it.
enum class Surface : std::uint8_t { None, Water, Field, Forest, Other };
struct SurfaceShade {
    Surface surface = Surface::None;
    std::uint16_t cls = 0;   // class of the element (the crop of a field)
    std::uint32_t seed = 0;  // per element: its root element's id in the scene file (a field's tint, furrow direction)
    friend bool operator==(const SurfaceShade&, const SurfaceShade&) = default;
};

struct AppearanceTile {
    Box bounds;
    int resolution = 0;
    int border = 0;
    int stride = 0;       // resolution + 2 * border
    int samples = 1;      // supersampling it was produced with (per axis)
    double delta = 0.0;   // metres per texel
    bool uniform = false;
    SurfaceShade shade;   // uniform tiles only
    std::vector<std::uint8_t> rgbm;  // stride * stride * 4, empty when uniform

    std::size_t index(int i, int j) const { return 4 * (std::size_t(j + border) * std::size_t(stride) + std::size_t(i + border)); }
    Vec2 texelCentre(int i, int j) const { return bounds.min + (Vec2(double(i), double(j)) + 0.5) * delta; }
    friend bool operator==(const AppearanceTile&, const AppearanceTile&) = default;
};

}  // namespace lacet
