#pragma once
// The 4-wide float twin of model/segment.h's nearestOnSegment: squared distances from four
// pixel centres of a row to one segment at once, in a local frame (metres from a block's first
// pixel centre). Call localSegment once per segment and block, then distanceSquared4 per four
// pixels. tests/raster/segment4_test.cpp checks it against the scalar primitive.
//
// It follows the scalar rule (t = clamp(dot(r, ab) / len2, 0, 1), 0 for a degenerate segment)
// in float, with two differences a caller must accept: 1 / len2 is rounded once and multiplied
// (not divided), and the offset is r - ab t from the segment's start (not p - (a + ab t)). So a
// distance is within about 1e-6 of the local coordinates' magnitude
// (|a - origin| + |p - a| + |b - a|) of the scalar one: far below a texel for
// segments of a block's reach, which is what the local frame is for. Points beyond float's range
// (about 3e38 m from the origin) are not supported.

#include <glm/geometric.hpp>

#include "model/types.h"
#include "raster/float4.h"

namespace lacet {

struct LocalSegment {
    float x0 = 0.0f, y0 = 0.0f;  // start, metres from the frame's origin
    float dx = 0.0f, dy = 0.0f;  // end minus start, metres
    float invLen2 = 0.0f;        // 1 / |end - start|^2, 0 for a degenerate segment
};

// The segment a-b (scene coordinates, metres) in the frame whose origin is `origin`.
inline LocalSegment localSegment(Vec2 a, Vec2 b, Vec2 origin) {
    const Vec2 p0 = a - origin, ab = b - a;
    const double len2 = glm::dot(ab, ab);
    return {float(p0.x), float(p0.y), float(ab.x), float(ab.y), len2 > 0.0 ? float(1.0 / len2) : 0.0f};
}

// Squared distances (m^2) from the four points (qx[i], qy) of the local frame to the segment.
inline Float4 distanceSquared4(const LocalSegment& l, Float4 qx, float qy) {
    const Float4 dx = splat(l.dx), dy = splat(l.dy);
    const float ry = qy - l.y0;
    const Float4 rx = qx - l.x0;
    const Float4 t = clamp4((rx * dx + ry * dy) * l.invLen2, splat(0.0f), splat(1.0f));
    const Float4 ex = rx - dx * t, ey = ry - dy * t;
    return ex * ex + ey * ey;
}

}  // namespace lacet
