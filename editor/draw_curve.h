#pragma once
// The curve the draw tool makes from the points the user clicked: a smooth curve through them,
// each span a cubic Bezier piece of the Catmull-Rom spline (tangent at a point: the chord between
// its neighbours, over 6; at the ends, the chord to the one neighbour), so that it passes through
// every point with a continuous tangent. Its width, footprint and class are the draw tool's.

#include <cstdint>
#include <span>

#include "model/graph.h"

namespace lacet {

// What a new curve gets (the draw tool's fields).
struct NewCurveStyle {
    float width = 7.0f;       // carriageway or bed width w (metres, > 0)
    float footprint = 16.0f;  // footprint width wf (metres); raised to `width` when smaller
    int cls = 1;              // class (clamped to 0..65535)
};

// The curve through `points` (at least 2; consecutive points distinct) with `style`: 3 (n - 1) + 1
// vertices, on-curve at the points. `start` and `end` are left for the caller (kNoElement).
Curve curveThrough(std::span<const Vec2> points, const NewCurveStyle& style);

}  // namespace lacet
