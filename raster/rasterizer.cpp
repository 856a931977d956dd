#include "raster/rasterizer.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>

namespace lacet::raster_detail {
namespace {

using Point = glm::dvec2;

// Nearest grid position, halves rounded up (so that snapping commutes with translations by
// whole grid steps). Exact for |v| < 2^44 pixels; farther values are already on the grid.
double snapToSubpixel(double v) {
    return std::floor(v * double(kSubpixelSteps) + 0.5) / double(kSubpixelSteps);
}

// Fixed-point coordinate of a snapped position inside the guard band.
std::int64_t toFixed(double snapped) { return static_cast<std::int64_t>(snapped * double(kSubpixelSteps)); }

bool isFinite(Point p) { return std::isfinite(p.x) && std::isfinite(p.y); }

// The guard band: the tile dilated by kGuardBandPixels. Vertices inside it are rasterized
// directly; a triangle with a vertex outside it is clipped to it first.
struct GuardBand {
    Point min, max;
    bool contains(Point p) const { return min.x <= p.x && p.x <= max.x && min.y <= p.y && p.y <= max.y; }
};

// One side of the guard band: the points with sign * p[axis] <= sign * bound are kept.
struct ClipPlane {
    int axis;
    double sign;
    double bound;
    bool keeps(Point p) const { return sign * p[axis] <= sign * bound; }
};

// Where segment (kept, dropped) crosses the plane. It depends on the segment and not on the
// direction it is walked in, so the two triangles sharing an edge clip it to the same points
// and the mesh stays watertight. The crossing coordinate is set exactly on the plane.
Point crossing(const ClipPlane& plane, Point kept, Point dropped) {
    const int other = 1 - plane.axis;
    const double s = (plane.bound - kept[plane.axis]) / (dropped[plane.axis] - kept[plane.axis]);
    Point out;
    out[plane.axis] = plane.bound;
    out[other] = kept[other] + s * (dropped[other] - kept[other]);
    return out;
}

constexpr int kMaxClippedVertices = 7;

struct Polygon {
    std::array<Point, kMaxClippedVertices> p{};
    int size = 0;
};

// Sutherland-Hodgman against one plane. A convex polygon gains at most one vertex per plane;
// the capacity check only guards against rounding making it lose convexity.
Polygon clip(const Polygon& in, const ClipPlane& plane) {
    Polygon out;
    const auto push = [&out](Point p) {
        if (out.size < kMaxClippedVertices) out.p[out.size++] = p;
    };
    for (int i = 0; i < in.size; ++i) {
        const Point a = in.p[i];
        const Point b = in.p[(i + 1) % in.size];
        const bool keepA = plane.keeps(a), keepB = plane.keeps(b);
        if (keepA) push(a);
        if (keepA != keepB) push(keepA ? crossing(plane, a, b) : crossing(plane, b, a));
    }
    return out;
}

std::int64_t signedArea2(const FixedTriangle& t) {
    return (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
}

// Gives t positive area by swapping two vertices; false when its area is zero.
bool orientPositive(FixedTriangle& t) {
    const std::int64_t area2 = signedArea2(t);
    if (area2 == 0) return false;
    if (area2 < 0) {
        std::swap(t.x[1], t.x[2]);
        std::swap(t.y[1], t.y[2]);
    }
    return true;
}

// Barycentric interpolation over the snapped triangle, written as planes through vertex 0.
// `area2` is twice the signed area of the snapped triangle in square pixels, non-zero.
AttributePlanes attributePlanes(const std::array<Point, 3>& s, const std::array<const RasterVertex*, 3>& v,
                                double area2, int nAttributes) {
    AttributePlanes planes;
    planes.x0 = s[0].x;
    planes.y0 = s[0].y;
    const Point e1 = s[1] - s[0], e2 = s[2] - s[0];
    const double inverseArea2 = 1.0 / area2;
    for (int k = 0; k < nAttributes; ++k) {
        const double a0 = v[0]->a[k];
        const double d1 = double(v[1]->a[k]) - a0, d2 = double(v[2]->a[k]) - a0;
        planes.a0[k] = a0;
        planes.dadx[k] = (d1 * e2.y - d2 * e1.y) * inverseArea2;
        planes.dady[k] = (d2 * e1.x - d1 * e2.x) * inverseArea2;
    }
    return planes;
}

void checkArguments(int nAttributes, int width, int height) {
    if (nAttributes < 0 || nAttributes > kMaxAttributes)
        throw std::invalid_argument("rasterizeTriangle(): nAttributes " + std::to_string(nAttributes) +
                                    " outside [0, " + std::to_string(kMaxAttributes) + "]");
    if (width < 0 || height < 0 || width > kMaxTileSize || height > kMaxTileSize)
        throw std::invalid_argument("rasterizeTriangle(): tile " + std::to_string(width) + "x" +
                                    std::to_string(height) + " outside [0, " + std::to_string(kMaxTileSize) + "]^2");
}

}  // namespace

TriangleSetup setupTriangle(const RasterVertex& v0, const RasterVertex& v1, const RasterVertex& v2,
                            int nAttributes, int width, int height) {
    checkArguments(nAttributes, width, height);
    TriangleSetup setup;
    const std::array<const RasterVertex*, 3> v{&v0, &v1, &v2};
    if (width == 0 || height == 0 || !isFinite(v0.p) || !isFinite(v1.p) || !isFinite(v2.p)) return setup;

    // Pixel centres lie inside [0, width] x [0, height]; a triangle whose box misses it covers none.
    const Point lo = glm::min(v0.p, glm::min(v1.p, v2.p)), hi = glm::max(v0.p, glm::max(v1.p, v2.p));
    if (hi.x < 0.0 || hi.y < 0.0 || lo.x > double(width) || lo.y > double(height)) return setup;

    std::array<Point, 3> snapped;
    for (int i = 0; i < 3; ++i) snapped[i] = {snapToSubpixel(v[i]->p.x), snapToSubpixel(v[i]->p.y)};

    const GuardBand band{Point(-kGuardBandPixels), Point(double(width), double(height)) + kGuardBandPixels};
    if (band.contains(snapped[0]) && band.contains(snapped[1]) && band.contains(snapped[2])) {
        FixedTriangle& t = setup.triangles[0];
        for (int i = 0; i < 3; ++i) {
            t.x[i] = toFixed(snapped[i].x);
            t.y[i] = toFixed(snapped[i].y);
        }
        const std::int64_t area2 = signedArea2(t);
        if (!orientPositive(t)) return setup;
        setup.count = 1;
        constexpr double kStepsPerSquarePixel = double(kSubpixelSteps * kSubpixelSteps);
        setup.planes = attributePlanes(snapped, v, double(area2) / kStepsPerSquarePixel, nAttributes);
        return setup;
    }

    const Point e1 = snapped[1] - snapped[0], e2 = snapped[2] - snapped[0];
    const double area2 = e1.x * e2.y - e1.y * e2.x;
    if (area2 == 0.0 || !std::isfinite(area2)) return setup;
    setup.planes = attributePlanes(snapped, v, area2, nAttributes);

    Polygon polygon;
    polygon.p = {snapped[0], snapped[1], snapped[2]};
    polygon.size = 3;
    for (const ClipPlane& plane : {ClipPlane{0, -1.0, band.min.x}, ClipPlane{0, 1.0, band.max.x},
                                   ClipPlane{1, -1.0, band.min.y}, ClipPlane{1, 1.0, band.max.y}})
        polygon = clip(polygon, plane);

    // Snap the clipped polygon and drop vertices that snapping merged.
    std::array<std::int64_t, kMaxClippedVertices> fx{}, fy{};
    int n = 0;
    for (int i = 0; i < polygon.size; ++i) {
        const std::int64_t x = toFixed(snapToSubpixel(polygon.p[i].x));
        const std::int64_t y = toFixed(snapToSubpixel(polygon.p[i].y));
        if (n > 0 && x == fx[n - 1] && y == fy[n - 1]) continue;
        fx[n] = x;
        fy[n] = y;
        ++n;
    }
    while (n > 1 && fx[n - 1] == fx[0] && fy[n - 1] == fy[0]) --n;

    // Fan from vertex 0. A fan triangle that snapping turned against the original winding is a
    // sliver along the guard band, far from the tile; dropping it keeps the fan free of overlap.
    for (int i = 1; i + 1 < n; ++i) {
        FixedTriangle t{{fx[0], fx[i], fx[i + 1]}, {fy[0], fy[i], fy[i + 1]}};
        const std::int64_t a = signedArea2(t);
        if (a == 0 || (a > 0) != (area2 > 0.0)) continue;
        orientPositive(t);
        setup.triangles[setup.count++] = t;
    }
    return setup;
}

}  // namespace lacet::raster_detail
