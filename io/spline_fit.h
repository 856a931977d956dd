#pragma once
// Fitting a polyline (e.g. an OSM way, in scene metres) with a chain of cubic Bezier pieces, as
// the vertices of a Curve (model/graph.h): Philip J. Schneider, "An Algorithm for Automatically
// Fitting Digitized Curves", Graphics Gems (1990).
//
// Units: positions, tolerance and errors in metres (scene CRS).

#include <cstddef>
#include <span>
#include <vector>

#include "model/types.h"

namespace lacet {

struct SplineFitParams {
    // Metres (>= 0): the Hausdorff distance between the fitted curve and the input polyline, both
    // ways, along the whole of both (every point of the curve is within it of the polyline, and
    // every point of every input segment within it of the curve).
    double tolerance = 0.5;
    int maxIterations = 4;   // Newton reparameterisation steps per attempt (Schneider), >= 0
    // Metres (> 0): the dense measure of each piece (model/hausdorff.h) is certified within
    // min(precision, tolerance / 20); the reported error exceeds the true one by at most that.
    double precision = 0.01;
};

struct SplineFitResult {
    // First and last on-curve, exactly equal (bitwise) to the input's first and last points; every
    // on-curve vertex is an input point. Cubic pieces (2 controls between on-curve vertices), or
    // line pieces (no control) where 2 points remain or the points lie on a straight span.
    std::vector<Vertex> vertices;
    // Metres, <= tolerance: the largest Hausdorff distance between a piece and the stretch of
    // input polyline it was fitted to, measured densely both ways, within the precision above
    // (looser only where the measure ran out of evaluations: tiny tolerances along long
    // near-parallel stretches). The whole curve's distance to the whole polyline is no larger.
    double maxError = 0.0;
    std::size_t inputPoints = 0;  // after dropping consecutive duplicates
};

// Fits a polyline (scene metres) with a C1-continuous-where-possible chain of cubic Bezier
// pieces: chord-length parameterisation, least-squares cubic with fixed end tangents,
// Newton-Raphson reparameterisation, split at the point of largest error (with the tangent there
// shared by both halves) until every point is within tolerance; then a piece is kept only when
// its dense Hausdorff distance to its stretch of polyline is within tolerance (a curve through
// every point can still bulge between two distant ones), else it is split at the input point
// nearest to where it strays. A span of two points is its segment, exactly. The polyline is split
// first at every point where it turns sharply (a corner, or a reversal): corners stay corners,
// the two sides taking one-sided tangents.
//
// Consecutive duplicate points are dropped first. `keep` lists indices (into the input) of points
// that must stay on-curve vertices exactly (e.g. shared OSM nodes that become junctions later);
// the fit is split there (order and repeats in `keep` do not matter). Closed polylines (first ==
// last) are handled: the closing point is kept, and the curve is C1 there unless it is a corner.
//
// Deterministic: the same input gives bitwise the same output.
// Throws std::invalid_argument for fewer than 2 distinct points, a non-finite coordinate, a keep
// index out of range, or invalid params (negative or non-finite tolerance, negative maxIterations).
SplineFitResult fitSpline(std::span<const Vec2> points, const SplineFitParams& params,
                          std::span<const std::size_t> keep = {});

}  // namespace lacet
