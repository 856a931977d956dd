#pragma once
// The nearest point of a closed segment to a point: the one primitive that the distance fields
// (roads, rivers, area borders, elevation footprints), the fit's Hausdorff proof and the editor's
// picking measure with. Its 4-wide float twin, for a row of pixels at once, is
// raster/segment4.h's distanceSquared4, tested against this one in tests/raster/segment4_test.cpp.
//
// Units are those of the inputs (metres everywhere in Lacet); any frame, as long as p, a and b
// share it.
//
// The rule, written once here so that every caller agrees bit for bit:
//   ab = b - a, len2 = dot(ab, ab);
//   t = clamp(dot(p - a, ab) / len2, 0, 1)   when len2 > 0,
//   t = 0                                    otherwise: a degenerate segment (a == b, or so short
//                                            that len2 underflows) is its point a, and a
//                                            non-finite len2 (NaN) gives t = 0 too;
//   point = a + ab t, distance2 = dot(p - point, p - point), distance = sqrt(distance2).
// t is clamped only at the ends: t == 0.0 (1.0) says that p projects at or beyond a (b), up to
// the rounding of the dot product, and so that the end point is nearest (p == a gives t == 0
// and distance 0 exactly; p == b gives t == 1). With finite inputs whose differences square
// without overflow (below about 1e150), t is in [0, 1] and the distance is within a few
// roundings, in the magnitude of the coordinates, of the exact one: point is rounded to the
// coordinates' precision, so far from the origin the error is a few of their ulps. The point at
// t == 1 is a + (b - a), which may differ from b in the last bit.

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "model/types.h"

namespace lacet {

struct SegmentNearest {
    double t = 0.0;          // in [0, 1]: point = a + (b - a) t
    Vec2 point{0.0};         // the nearest point of the segment
    double distance2 = 0.0;  // squared distance from p to point
};

// The parameter t of the nearest point, by the rule above.
inline double nearestParameter(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    return len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
}

inline SegmentNearest nearestOnSegment(Vec2 p, Vec2 a, Vec2 b) {
    SegmentNearest n;
    n.t = nearestParameter(p, a, b);
    n.point = a + (b - a) * n.t;
    const Vec2 d = p - n.point;
    n.distance2 = glm::dot(d, d);
    return n;
}

// Distance from p to the closed segment a-b (a == b allowed): sqrt of nearestOnSegment's
// distance2, equal to glm::length(p - point).
inline double distanceToSegment(Vec2 p, Vec2 a, Vec2 b) { return std::sqrt(nearestOnSegment(p, a, b).distance2); }

}  // namespace lacet
