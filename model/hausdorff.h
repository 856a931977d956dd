#pragma once
// Hausdorff distances between Bezier curves and polylines, measured densely along the whole of
// both, never only at vertices: the fit tolerance of an import (io/spline_fit.h) is a bound on
// these, and reports quote them (DESIGN.md invariant 6).
//
// A directed distance max_{x in A} d(x, B) is found by branch and bound along A: the distance to a
// set is 1-Lipschitz, so over a stretch of A of length L whose ends are at d0 and d1 from B, it is
// at most (d0 + d1 + L) / 2. Stretches whose bound cannot beat the largest distance found so far
// by more than `precision` are dropped, the others halved. On a Bezier piece the length of the
// stretch [t0, t1] is bounded by speedBound(b) * (t1 - t0). The result is a pair of bounds:
// `lower` (a distance attained by a point of A) and `upper` (no point of A is farther), with
// upper - lower <= precision unless the evaluation budget ran out (upper then stays a true bound).
//
// Order of calls: make a DistanceBound, feed it every segment or piece of A with maxAlongSegment /
// maxAlongPiece and a distance function to B, read lower and upper.
//
// Units: metres (scene CRS).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include <glm/geometric.hpp>

#include "model/bezier.h"
#include "model/graph.h"

namespace lacet {

struct HausdorffParams {
    // Metres, > 0: the upper bound is within this of the true distance (and of `lower`).
    double precision = 0.01;
    // Decision mode ("is the distance within a tolerance?"), metres: stop as soon as a point of A
    // is proven farther than giveUpAbove from B, and do not refine a stretch proven within
    // goodEnough (`upper` is then only a bound: at most max(goodEnough, lower + precision)).
    // Measure mode: infinity and 0.
    double giveUpAbove = std::numeric_limits<double>::infinity();
    double goodEnough = 0.0;
    // Distance evaluations per call, >= 1; on exhaustion `upper` stays a true bound, only looser.
    std::size_t maxEvaluations = 200000;
};

struct DistanceBound {
    double lower = 0.0;  // metres: attained by the point `where` of A
    double upper = 0.0;  // metres: no point of A is farther from B
    Vec2 where{0.0};
    bool exhausted = false;  // the evaluation budget ran out somewhere
};

// Distance from q to the piece (metres): never below the true distance, and within `precision`
// (> 0) of it.
double distanceUpperBound(const BezierPiece& b, Vec2 q, double precision);

// Upper bound of |B'(t)| over [0, 1] (metres per unit t): the hodograph's control points bound it.
double speedBound(const BezierPiece& b);

// What a distance function to a set B returns for a point q: an upper bound of q's distance to
// B (within the function's precision of it), and the item of B that attains it. When two points
// have the same convex item (a segment) nearest, every point between them on a straight line is
// no farther from it than the farther of the two (distance to a convex set is convex).
struct Nearest {
    double distance = std::numeric_limits<double>::infinity();
    std::size_t item = std::size_t(-1);
    bool convex = false;
};

// Adds the largest distance from a point of the segment a-b to a set B into `bound`.
// `distance(q)` returns a Nearest whose distance is within `oraclePrecision` of the true one.
template <class Distance>
void maxAlongSegment(Vec2 a, Vec2 b, Distance&& distance, double oraclePrecision, const HausdorffParams& params,
                     DistanceBound& bound);

// The same along a Bezier piece.
template <class Distance>
void maxAlongPiece(const BezierPiece& piece, Distance&& distance, double oraclePrecision, const HausdorffParams& params,
                   DistanceBound& bound);

// Both directed distances between a Bezier chain (model/graph.h Vertex list) and a polyline:
// curveToSource is the largest distance from a point of the curve to the polyline, sourceToCurve
// the largest from a point of the polyline to the curve. Brute force over the other side's
// segments or pieces (pruned by their boxes): for a curve and the polyline it was fitted to.
// The overloads taking `running` add to bounds already found (of other curves, say): stretches
// that cannot beat them are not refined, so the maximum over many curves costs little more than
// that of the worst one.
struct Hausdorff {
    DistanceBound curveToSource, sourceToCurve;
    double upper() const { return std::max(curveToSource.upper, sourceToCurve.upper); }
    double lower() const { return std::max(curveToSource.lower, sourceToCurve.lower); }
};
Hausdorff hausdorff(std::span<const Vertex> curve, std::span<const Vec2> polyline, const HausdorffParams& params);
Hausdorff hausdorff(const BezierPiece& piece, std::span<const Vec2> polyline, const HausdorffParams& params);
void addHausdorff(std::span<const Vertex> curve, std::span<const Vec2> polyline, const HausdorffParams& params,
                  Hausdorff& running);

// ---- implementation of the templates ----

namespace hausdorff_detail {

// Branch and bound of a 1-Lipschitz-in-length function f over a parameter interval [0, 1] whose
// stretches [s0, s1] have length at most lengthPerUnit * (s1 - s0); point(s) gives the position,
// on a straight line when `straight`.
template <class Point, class Distance>
void maxAlong(Point&& point, double lengthPerUnit, bool straight, Distance&& distance, double oraclePrecision,
              const HausdorffParams& params, DistanceBound& bound) {
    struct Stretch {
        double s0, s1;
        Nearest n0, n1;
    };
    const double precision = std::max(params.precision, oraclePrecision);
    std::size_t evaluations = 0;
    auto eval = [&](double s) {
        ++evaluations;
        const Vec2 p = point(s);
        const Nearest n = distance(p);
        // An upper bound within oraclePrecision: the true distance is at least n.distance - oraclePrecision.
        if (n.distance - oraclePrecision > bound.lower) {
            bound.lower = n.distance - oraclePrecision;
            bound.where = p;
        }
        bound.upper = std::max(bound.upper, n.distance);
        return n;
    };
    std::vector<Stretch> stack{{0.0, 1.0, eval(0.0), eval(1.0)}};
    while (!stack.empty()) {
        if (!std::isfinite(bound.lower)) return;  // nothing of B is near (an empty B): upper is infinite too
        const Stretch st = stack.back();
        stack.pop_back();
        const double d0 = st.n0.distance, d1 = st.n1.distance;
        if (straight && st.n0.convex && st.n0.item == st.n1.item) continue;  // max(d0, d1): counted
        const double length = lengthPerUnit * (st.s1 - st.s0);
        const double ub = 0.5 * (d0 + d1 + length);
        if (ub <= std::max(bound.lower + precision, params.goodEnough) || bound.lower > params.giveUpAbove) {
            bound.upper = std::max(bound.upper, ub);
            continue;
        }
        if (evaluations >= params.maxEvaluations || !(length > 1e-12 * (1.0 + std::abs(lengthPerUnit)))) {
            bound.upper = std::max(bound.upper, ub);
            bound.exhausted = bound.exhausted || evaluations >= params.maxEvaluations;
            continue;
        }
        const double sm = 0.5 * (st.s0 + st.s1);
        const Nearest nm = eval(sm);
        stack.push_back({st.s0, sm, st.n0, nm});
        stack.push_back({sm, st.s1, nm, st.n1});
    }
    bound.upper = std::max(bound.upper, bound.lower);
}

}  // namespace hausdorff_detail

template <class Distance>
void maxAlongSegment(Vec2 a, Vec2 b, Distance&& distance, double oraclePrecision, const HausdorffParams& params,
                     DistanceBound& bound) {
    hausdorff_detail::maxAlong([&](double s) { return s == 1.0 ? b : a + (b - a) * s; }, glm::length(b - a), true, distance,
                               oraclePrecision, params, bound);
}

template <class Distance>
void maxAlongPiece(const BezierPiece& piece, Distance&& distance, double oraclePrecision, const HausdorffParams& params,
                   DistanceBound& bound) {
    // A line piece is straight; evaluate() of a line piece is a lerp, on its segment.
    hausdorff_detail::maxAlong([&](double t) { return evaluate(piece, t); }, speedBound(piece), piece.degree == 1, distance,
                               oraclePrecision, params, bound);
}

}  // namespace lacet
