#pragma once
// The CPU rasterizer: the project's reference renderer (DESIGN.md "Producers"). It fills
// triangles and triangle strips of one tile, calling a shading functor once per covered pixel
// with the vertex attributes interpolated at the pixel centre, and gives the anti-aliasing
// coverage helpers the producers use for curve edges and area edges.
//
// Frame and units: tile pixel space. Pixel (x, y) covers [x, x+1) x [y, y+1) and is sampled
// at its centre (x + 0.5, y + 0.5); x grows along a row, y from row to row (downwards in an
// image). A tile is width x height pixels, 0 <= width, height <= kMaxTileSize.
//
// Coverage is exact and deterministic: vertices are snapped to a grid of 1/kSubpixelSteps
// pixel, edge functions are evaluated in int64, and a pixel centre lying exactly on an edge
// belongs to the triangle for which that edge is a top or left edge (the top-left rule, as in
// Direct3D; it is equivalent to moving every sample point by an infinitesimal (e, e^2)). So a
// mesh whose triangles share edges covers every pixel centre inside it exactly once, shared
// vertices included. Both windings are accepted; a triangle whose snapped area is zero
// covers nothing; a triangle with a non-finite coordinate is dropped. A triangle with a vertex
// farther than kGuardBandPixels from the tile is first clipped (in double) against the guard
// band, symmetrically in the two triangles sharing an edge, so a huge triangle covering the tile
// still fills it and meshes stay watertight; its edges then keep a precision of about 1e-16
// times the farthest vertex's distance, and one whose doubled area overflows a double (vertices
// beyond about 1e150 pixels) is dropped.
//
// Attributes are linear in screen space (no perspective): barycentric interpolation from the
// snapped vertex positions, evaluated in double as the equivalent plane equation and handed to
// the functor as float. Results depend only on the inputs: the same on every run and with any
// number of threads rasterizing other triangles at the same time (no shared state).
//
// Order of calls: for each triangle or strip, rasterizeTriangle() or rasterizeStrip() with a
// functor `shade(int x, int y, const float* attributes)`; the functor does the blending.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/vec2.hpp>

namespace lacet {

constexpr int kMaxAttributes = 8;

// Sub-pixel grid of the snapped vertex positions: 2^kSubpixelBits steps per pixel.
constexpr int kSubpixelBits = 8;
constexpr std::int64_t kSubpixelSteps = std::int64_t{1} << kSubpixelBits;

// Largest tile side in pixels, and the distance in pixels beyond the tile past which vertices
// are clipped away. Together they keep snapped coordinates below 2^29 steps in magnitude, so
// that every edge function (a difference of two products of coordinate differences) fits in
// int64.
constexpr int kMaxTileSize = 1 << 16;
constexpr double kGuardBandPixels = double(1 << 20);

struct RasterVertex {
    glm::dvec2 p{0.0};                         // position, tile pixels
    std::array<float, kMaxAttributes> a{};     // attributes; the first nAttributes are used
};

// Fraction of a pixel covered by the inside of a straight edge whose signed distance from the
// pixel centre is `signedDistancePixels` (positive: the centre is inside). Box filter of width
// one pixel taken across the edge: a linear ramp from 0 at -0.5 to 1 at +0.5, clamped. Exact for
// axis-aligned edges, an approximation otherwise; edgeCoverage(d) + edgeCoverage(-d) == 1, so
// the two sides of a shared area border add up to a full pixel.
inline float edgeCoverage(float signedDistancePixels) {
    return std::clamp(signedDistancePixels + 0.5f, 0.0f, 1.0f);
}

// Fraction of a pixel covered by a band |t| <= halfWidthPixels (a curve of width 2 *
// halfWidthPixels seen across its axis) whose axis lies at `distanceFromAxisPixels` (the v
// coordinate across the strip, in pixels, either sign) from the pixel centre: the same box
// filter as edgeCoverage applied to both edges of the band, so bands thinner than a pixel get
// their true width as coverage. halfWidthPixels >= 0.
inline float bandCoverage(float distanceFromAxisPixels, float halfWidthPixels) {
    return edgeCoverage(halfWidthPixels - distanceFromAxisPixels) +
           edgeCoverage(halfWidthPixels + distanceFromAxisPixels) - 1.0f;
}

namespace raster_detail {

// A triangle in snapped fixed-point coordinates (kSubpixelSteps per pixel) with positive area
// (x1 - x0)(y2 - y0) - (y1 - y0)(x2 - x0) > 0.
struct FixedTriangle {
    std::array<std::int64_t, 3> x;
    std::array<std::int64_t, 3> y;
};

// Attribute k < nAttributes at pixel-space point p is a0[k] + dadx[k] (p.x - x0) + dady[k] (p.y - y0).
struct AttributePlanes {
    double x0 = 0.0, y0 = 0.0;
    std::array<double, kMaxAttributes> a0, dadx, dady;
};

// A triangle clipped against the guard band is a convex polygon of at most 7 vertices, fanned
// into at most 5 triangles.
constexpr int kMaxClippedTriangles = 5;

// Left uninitialized beyond what is used: it is made once per triangle, on the hot path.
struct TriangleSetup {
    int count = 0;  // triangles[0, count) are to be scanned; 0 when nothing can be covered
    std::array<FixedTriangle, kMaxClippedTriangles> triangles;
    AttributePlanes planes;
};

// Validates the arguments (std::invalid_argument on misuse), culls, snaps, clips and computes
// the attribute planes.
TriangleSetup setupTriangle(const RasterVertex& v0, const RasterVertex& v1, const RasterVertex& v2,
                            int nAttributes, int width, int height);

inline std::int64_t floorDiv(std::int64_t a, std::int64_t b) {  // b > 0
    const std::int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}
inline std::int64_t ceilDiv(std::int64_t a, std::int64_t b) { return -floorDiv(-a, b); }

// Where an edge function E(x) = c + x step (step != 0) is >= 0 along a row of `width` pixels:
// x >= first (step > 0) or x <= last (step < 0). The crossing is estimated in double, clamped
// to the row, then corrected with exact integer evaluations of E (a step or two at most), which
// is exact and cheaper than a 64-bit integer division.
inline std::int64_t firstInside(std::int64_t c, std::int64_t step, std::int64_t width) {  // step > 0
    const double estimate = std::clamp(std::ceil(-double(c) / double(step)), 0.0, double(width));
    std::int64_t x = static_cast<std::int64_t>(estimate);
    while (x > 0 && c + (x - 1) * step >= 0) --x;
    while (x < width && c + x * step < 0) ++x;
    return x;
}
inline std::int64_t lastInside(std::int64_t c, std::int64_t step, std::int64_t width) {  // step < 0
    const double estimate = std::clamp(std::floor(double(c) / double(-step)), -1.0, double(width - 1));
    std::int64_t x = static_cast<std::int64_t>(estimate);
    while (x < width - 1 && c + (x + 1) * step >= 0) ++x;
    while (x >= 0 && c + x * step < 0) --x;
    return x;
}

// Walks the rows of t's bounding box inside the tile. On each row the covered pixels form one
// run, bounded exactly by firstInside/lastInside of the three edge functions, whose values at
// the row start are stepped incrementally from row to row.
template <int nAttributes, class F>
void scanTriangle(const FixedTriangle& t, const AttributePlanes& planes, int width, int height, F& shade) {
    constexpr std::int64_t half = kSubpixelSteps / 2;
    const std::int64_t minY = std::min({t.y[0], t.y[1], t.y[2]});
    const std::int64_t maxY = std::max({t.y[0], t.y[1], t.y[2]});
    const std::int64_t rowBegin = std::max<std::int64_t>(0, ceilDiv(minY - half, kSubpixelSteps));
    const std::int64_t rowEnd = std::min<std::int64_t>(height - 1, floorDiv(maxY - half, kSubpixelSteps));
    if (rowBegin > rowEnd) return;

    // Edge i runs from vertex i to vertex i+1; at sample (sx, sy) its function is
    // E = dx (sy - ay) - dy (sx - ax), >= 0 inside. rowValue[i] is E at the centre of pixel
    // (0, row) plus the fill-rule bias; E grows by xStep[i] per pixel along the row.
    std::array<std::int64_t, 3> rowValue{}, rowStep{}, xStep{};
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        const std::int64_t dx = t.x[j] - t.x[i];
        const std::int64_t dy = t.y[j] - t.y[i];
        const bool topLeft = dy < 0 || (dy == 0 && dx > 0);
        const std::int64_t sy = rowBegin * kSubpixelSteps + half;
        rowValue[i] = dx * (sy - t.y[i]) - dy * (half - t.x[i]) + (topLeft ? 0 : -1);
        rowStep[i] = dx * kSubpixelSteps;
        xStep[i] = -dy * kSubpixelSteps;
    }

    float attributes[kMaxAttributes] = {};
    double rowBase[kMaxAttributes] = {};
    for (std::int64_t row = rowBegin; row <= rowEnd; ++row) {
        std::int64_t first = 0, last = width - 1;
        for (int i = 0; i < 3; ++i) {
            const std::int64_t c = rowValue[i];
            if (xStep[i] > 0) first = std::max(first, firstInside(c, xStep[i], width));
            else if (xStep[i] < 0) last = std::min(last, lastInside(c, xStep[i], width));
            else if (c < 0) last = -1;
            rowValue[i] += rowStep[i];
        }
        if (first > last) continue;

        const int y = static_cast<int>(row);
        const double sampleY = double(row) + 0.5;
        for (int k = 0; k < nAttributes; ++k) rowBase[k] = planes.a0[k] + planes.dady[k] * (sampleY - planes.y0);
        for (int x = static_cast<int>(first); x <= static_cast<int>(last); ++x) {
            const double offsetX = double(x) + 0.5 - planes.x0;
            for (int k = 0; k < nAttributes; ++k)
                attributes[k] = static_cast<float>(rowBase[k] + planes.dadx[k] * offsetX);
            shade(x, y, static_cast<const float*>(attributes));
        }
    }
}

// scanTriangle with the attribute count as a compile-time constant, so that the per-pixel
// loops over attributes unroll.
template <class F>
void dispatch(const FixedTriangle& t, const AttributePlanes& planes, int nAttributes, int width, int height, F& shade) {
    static_assert(kMaxAttributes == 8);
    switch (nAttributes) {
        case 0: return scanTriangle<0>(t, planes, width, height, shade);
        case 1: return scanTriangle<1>(t, planes, width, height, shade);
        case 2: return scanTriangle<2>(t, planes, width, height, shade);
        case 3: return scanTriangle<3>(t, planes, width, height, shade);
        case 4: return scanTriangle<4>(t, planes, width, height, shade);
        case 5: return scanTriangle<5>(t, planes, width, height, shade);
        case 6: return scanTriangle<6>(t, planes, width, height, shade);
        case 7: return scanTriangle<7>(t, planes, width, height, shade);
        default: return scanTriangle<8>(t, planes, width, height, shade);
    }
}

}  // namespace raster_detail

// Calls shade(x, y, attributes) exactly once for every pixel of the width x height tile whose
// centre the triangle covers (see the top of this file). attributes points to nAttributes
// floats (0 <= nAttributes <= kMaxAttributes), valid during the call only.
template <class F>
void rasterizeTriangle(const RasterVertex& v0, const RasterVertex& v1, const RasterVertex& v2,
                       int nAttributes, int width, int height, F&& shade) {
    const raster_detail::TriangleSetup setup = raster_detail::setupTriangle(v0, v1, v2, nAttributes, width, height);
    for (int i = 0; i < setup.count; ++i)
        raster_detail::dispatch(setup.triangles[i], setup.planes, nAttributes, width, height, shade);
}

// Triangle strip: triangle i is (v[i], v[i+1], v[i+2]), for i + 2 < v.size(). Consecutive
// triangles share an edge, so the strip covers each pixel centre inside it once.
template <class F>
void rasterizeStrip(std::span<const RasterVertex> v, int nAttributes, int width, int height, F&& shade) {
    for (std::size_t i = 0; i + 2 < v.size(); ++i)
        rasterizeTriangle(v[i], v[i + 1], v[i + 2], nAttributes, width, height, shade);
}

}  // namespace lacet
