#pragma once
// Bezier math for one piece of a spline: a line (degree 1), quadratic (2) or cubic (3) Bezier
// segment. Every function stays correct for degenerate pieces: coincident control points, zero
// length, cusps, collinear controls.
//
// Units: positions and distances in metres (scene CRS); t in [0, 1].

#include <array>
#include <utility>
#include <vector>

#include "model/segment.h"  // distanceToSegment, which flatness() and the fit measure with
#include "model/types.h"

namespace lacet {

struct BezierPiece {
    int degree = 1;             // 1, 2 or 3
    std::array<Vec2, 4> p{};    // p[0..degree] are used; p[0] and p[degree] are on-curve

    Vec2 start() const { return p[0]; }
    Vec2 end() const { return p[degree]; }
    BezierPiece reversed() const;
};

Vec2 evaluate(const BezierPiece& b, double t);

// First derivative dB/dt (metres per unit t). Zero at a cusp or on a degenerate piece.
Vec2 derivative(const BezierPiece& b, double t);

// Unit tangent at t. Where the first derivative vanishes (cusp, coincident end controls) the
// direction of the first non-vanishing higher derivative is used (the limit of the tangent),
// then the chord; a piece whose points all coincide has no direction and gives (0, 0).
Vec2 unitTangent(const BezierPiece& b, double t);

// de Casteljau split at t: {b restricted to [0, t], b restricted to [t, 1]}.
std::pair<BezierPiece, BezierPiece> split(const BezierPiece& b, double t);

// de Casteljau split at t = 0.5 with midpoints (a + b) * 0.5, which are symmetric in a and b:
// splitting a reversed piece gives the bitwise mirror of splitting the piece. Refinement uses it.
std::pair<BezierPiece, BezierPiece> splitHalf(const BezierPiece& b);

// The smallest axis-aligned box containing the curve (from the roots of the derivative), not
// the box of the control points.
Box tightBounds(const BezierPiece& b);
Box controlBounds(const BezierPiece& b);

// Largest distance from a control point to the chord segment p[0]-p[degree] (metres). When it
// is <= tol, the chord and the curve are within tol of each other (Hausdorff): the curve lies
// in the convex hull of its controls, and every chord point is crossed by the curve's
// perpendicular projection.
double flatness(const BezierPiece& b);

// Arc length, by adaptive subdivision until the control-polygon and chord lengths agree within
// `tolerance` metres.
double arcLength(const BezierPiece& b, double tolerance);

// Distance from q to the curve (metres), within `tolerance` metres of the exact value, by
// branch-and-bound subdivision.
double distanceTo(const BezierPiece& b, Vec2 q, double tolerance);

}  // namespace lacet
