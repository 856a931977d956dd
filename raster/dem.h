#pragma once
// A digital elevation model (DEM): a regular grid of heights over a box of the scene, sampled
// smoothly anywhere in scene coordinates. It is the source of the elevation producer (z_o, §5)
// and of the z-profiles of curves (§5.2). Voids are filled at import: a Dem holds no NaN.
//
// Grid convention: sample (i, j), 0 <= i < width(), 0 <= j < height(), is the height at the
// CENTRE of cell (i, j), i.e. at extent.min + (i + 0.5, j + 0.5) * cellSize(); i grows with x,
// j with y. Heights are stored row by row: heights[j * width + i].
//
// Units: positions in scene CRS metres; heights in metres; gradients in metres per metre.

#include <vector>

#include "model/types.h"

namespace lacet {

class Dem {
public:
    // `heights` holds width * height values, row by row (see above); `extent` must have
    // max > min on both axes, width and height must be >= 1. Throws std::invalid_argument
    // otherwise, and on a NaN or infinite height, naming its cell (i, j).
    Dem(const Box& extent, int width, int height, std::vector<float> heights);

    const Box& extent() const { return extent_; }
    int width() const { return width_; }
    int height() const { return height_; }
    Vec2 cellSize() const { return cell_; }
    // Position of sample (i, j), the centre of its cell (metres).
    Vec2 samplePosition(int i, int j) const;
    // Grid value (metres); indices outside the grid are clamped to it.
    float at(int i, int j) const;
    const std::vector<float>& heights() const { return heights_; }

    // Height (metres) at p by Catmull-Rom bicubic interpolation of the samples: C1 over the
    // whole extent, equal to the grid values at sample centres, exact on linear height fields.
    // In the half cell between the outermost sample centres and the extent border, the grid is
    // continued by linear extrapolation of its two outermost rows or columns (a grid one sample
    // wide is continued as a constant). Outside the extent, p is clamped to the extent: the
    // height continues the border's values, constant across the border. NaN for a NaN p.
    double sample(Vec2 p) const;

    // Analytic derivative of sample() with respect to p (metres per metre). Outside the extent,
    // the component across the border that p is beyond is 0 (the clamped height is constant
    // there); on the border itself the inside derivative is returned. NaN for a NaN p.
    Vec2 gradient(Vec2 p) const;

    // sample(p) and gradient(p) from one stencil: the same values, for callers wanting both.
    double sampleAndGradient(Vec2 p, Vec2& gradient) const;

private:
    struct Stencil;
    Stencil stencil(Vec2 p) const;

    Box extent_;
    int width_;
    int height_;
    Vec2 cell_;
    std::vector<float> heights_;
};

}  // namespace lacet
