#pragma once
// Internal to the appearance producer: curves and area borders as polylines of segments, which
// segments can be nearest to the pixels of a block, and the fall-off of border strips.

#include <vector>

#include "model/clip_and_refine.h"
#include "model/curve_data.h"
#include "raster/float4.h"

namespace lacet::appearance {

struct Segment {
    Vec2 p0, p1;
    double u0 = 0.0, u1 = 0.0;
    bool startCap = false, endCap = false;  // p0 (p1) is the ancestor's start (end) node
};

// The on-curve polyline of a curve's pieces in a quad, with the curvilinear coordinate u of
// each vertex when `data` is given (0 otherwise).
std::vector<Segment> segmentsOf(const std::vector<ClippedCurve>& pieces, const CurveDataCache* data, LayerId l, AncestorId a);

// The segments that can be nearest to some point of `box` within `reach`: a segment whose
// lower bound (the distance from its bounding box) exceeds the reach, or exceeds some segment's
// upper bound over the box (the distance to a segment is convex, so its maximum over the box is
// at a corner), is nearest nowhere in it; nor is a segment with a non-finite end. Returns the
// least lower bound of those kept (infinity if none).
double candidatesNear(const std::vector<Segment>& segments, const Box& box, double reach,
                      std::vector<const Segment*>& out);

constexpr int kBlock = 16;  // pixels: the blocks whose candidate segments are found together

template <class Real>
float smoothFall(Real d, Real width) {  // 1 at d <= 0, 0 at d >= width
    if (width <= Real(0) || d >= width) return 0.0f;
    if (d <= Real(0)) return 1.0f;
    const Real t = Real(1) - d / width;
    return float(t * t * (Real(3) - Real(2) * t));
}

// smoothFall(d, width) of four distances.
inline Float4 smoothFall4(Float4 d, float width) {
    if (width <= 0.0f) return splat(0.0f);
    const Float4 t = 1.0f - d / width;
    const Float4 f = t * t * (3.0f - 2.0f * t);
    return width <= d ? splat(0.0f) : d <= 0.0f ? splat(1.0f) : f;
}

}  // namespace lacet::appearance
