#pragma once
// Shading functions of the appearance producer (§5.1), one per class of surface: the colour
// (linear RGB in [0, 1]) and the water mask at a point of the scene. Every function depends only
// on the point (scene metres), the element's parameters and the texel size of the level, never on
// the quad, so adjacent tiles agree and a uniform quad can be shaded from its SurfaceShade alone.
//
// The texel size fades out patterns finer than a few texels (furrows, forest canopy) instead of
// letting them alias.

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "model/graph.h"
#include "raster/appearance_tile.h"

namespace lacet {

// rgb + water mask.
using Rgbm = glm::vec4;

// Ground by altitude (m) and slope (|gradient|, m/m): grass, alpine meadow, rock, snow.
glm::vec3 groundColour(double z, double slope);

// Ground where the DEM has no data (the scene beyond the DEM's extent): a flat violet grey that no
// terrain has, so a user sees the heights there are not measured.
inline constexpr glm::vec3 kNoDataGround(0.46f, 0.42f, 0.52f);

// Water (mask 1), fields (crop colour with a per-field tint and furrows along a per-field
// direction), forests (canopy noise), other areas. The shader computes what does not depend on
// the point once per element.
// Corner values of a value noise over a box, computed once (tables give the same values as
// computing them at each point, so results do not depend on the box).
struct NoiseLattice {
    std::int64_t x0 = 0, y0 = 0;
    int nx = 0, ny = 0;
    std::vector<double> values;
    bool holds(std::int64_t x, std::int64_t y) const { return x >= x0 && y >= y0 && x + 1 < x0 + nx && y + 1 < y0 + ny; }
};

class SurfaceShader {
public:
    SurfaceShader(const SurfaceShade& shade, double texel);
    // Optional: tables for the points of `box` (metres), so at() costs less there.
    void prepare(const Box& box);
    Rgbm at(Vec2 p) const;  // inline below: it runs at every texel an area covers
    // Blocks, after prepareBlocks(step): at() of the points start + (i step, j step), i < nx,
    // j < ny (nx, ny <= kMaxBlock), into out[j * stride + i], up to rounding (about 1e-7 of a
    // channel). Fields step the furrows' phase along rows and columns by angle addition, with
    // tables made once by prepareBlocks: two cosines per block instead of one per point. Other
    // surfaces call at().
    static constexpr int kMaxBlock = 16;
    void prepareBlocks(double step);
    void block(Vec2 start, int nx, int ny, Rgbm* out, std::size_t stride) const;

private:
    Rgbm forestAt(Vec2 p) const;
    void forestBlock(Vec2 start, int nx, int ny, Rgbm* out, std::size_t stride) const;
    double step_ = 0.0;
    bool tables_ = false;                                  // a field with a pattern, prepared
    double cosX_[kMaxBlock] = {}, sinX_[kMaxBlock] = {};   // cos and sin of i * step * direction_.x
    double cosY_[kMaxBlock] = {}, sinY_[kMaxBlock] = {};   // and of j * step * direction_.y

    SurfaceShade shade_;
    glm::vec3 base_{0.0f};
    float mask_ = 0.0f;
    Vec2 direction_{0.0};        // fields: furrow phase gradient (radians per metre)
    double weight_[2] = {0.0, 0.0};  // pattern amplitudes after fading by texel size
    NoiseLattice lattice_[2];        // forests: the two octaves of canopy noise
};
Rgbm surfaceColour(const SurfaceShade& shade, Vec2 p, double texel);

// cos(x) within 1e-8 for |x| up to 1e7 (the field pattern's phase in radians, for coordinates up
// to 4000 km from the origin): reduced to [-pi, pi] in double, then 2 cos^2(x/2) - 1 with
// cos(x/2), |x/2| <= pi/2, from its Taylor series to x^12. Several times cheaper than libm's cos,
// which the field pattern calls at every texel. The reduction rounds through an integer, not
// nearbyint (a libm call on x86-64's baseline); beyond 2^52 turns, and for infinities and NaN,
// it is libm's cos.
inline double fastCos(double x) {
    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    const double q = x * (1.0 / kTwoPi);
    if (!(std::abs(q) < 0x1p52)) return std::cos(x);  // huge or not finite: out of the series' range
    const double turns = double(std::int64_t(q + (q < 0.0 ? -0.5 : 0.5)));
    const double h = 0.5 * (x - kTwoPi * turns);
    const double h2 = h * h;
    const double c = 1.0 + h2 * (-1.0 / 2 + h2 * (1.0 / 24 + h2 * (-1.0 / 720 + h2 * (1.0 / 40320 +
                     h2 * (-1.0 / 3628800 + h2 * (1.0 / 479001600))))));
    return 2.0 * c * c - 1.0;
}

inline Rgbm SurfaceShader::at(Vec2 p) const {
    switch (shade_.surface) {
        case Surface::Field:
            if (weight_[0] == 0.0) return Rgbm(base_, 0.0f);
            return Rgbm(base_ * float(1.0 + weight_[0] * fastCos(p.x * direction_.x + p.y * direction_.y)), 0.0f);
        case Surface::Forest:
            return forestAt(p);
        default:
            return Rgbm(base_, mask_);
    }
}

// The strip of width wf outside an area's border: banks of lakes, field margins, forest edges.
glm::vec3 borderStripColour(Surface surface);
// River banks (between w/2 and wf/2 of the axis).
glm::vec3 riverBankColour();
glm::vec3 tunnelPortalColour();  // the stone frame of a tunnel's mouth

// Roads: asphalt by class (0 primary, 1 secondary, 2 track), and markings.
glm::vec3 roadColour(std::uint16_t cls);
glm::vec3 markingColour();
bool roadHasMarkings(std::uint16_t cls);

// Road marking geometry (metres).
struct MarkingGeometry {
    double lineWidth = 0.15;      // side and centre lines
    double sideInset = 0.3;       // from the road edge to the outer edge of a side line
    double dashLength = 4.0;      // centre line: dashes of dashLength every dashPeriod
    double dashPeriod = 12.0;
    double stopLineWidth = 0.5;   // along the road
    double stopLineGap = 0.5;     // between the junction and the stop line
};

// Surface kind of an area layer.
Surface surfaceOf(LayerKind kind);

}  // namespace lacet
