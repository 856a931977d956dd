#include "io/spline_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "model/bezier.h"
#include "model/hausdorff.h"

namespace lacet {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A point where the polyline turns by more than 70 degrees (the cosine of the angle between the
// incoming and outgoing segments is below this) is a corner: the pieces on both sides take
// one-sided tangents there. A curve sharing one tangent across such a turn could only stay within
// tolerance of both legs with many tiny pieces around it, and a reversal has no shared tangent.
constexpr double kCornerCosine = 0.34202014332566873;  // cos(70 deg)

// Newton reparameterisation is only tried when the first fit of a span is within this many
// tolerances of every point (Schneider's "iteration error"); otherwise the span is split at once.
// 16 rather than Schneider's 2 (his 4 on squared errors): on the test arc and sine it gives 9
// and 38 on-curve vertices instead of 11 and 43, for up to 1.2x the time.
constexpr double kReparameterizeGate = 16.0;

// Tangents at a point are taken towards the nearest points at least this many tolerances away on
// either side (not the immediate neighbours), so that digitising noise finer than the tolerance
// neither tilts them nor makes false corners: on a sine sampled every 0.25 m with 2 cm of noise and
// a 0.2 m tolerance, 119 on-curve vertices instead of 181.
constexpr double kTangentReachTolerances = 4.0;

// Least-squares handles: the 2x2 system is taken as singular when its determinant is below this
// fraction of C00 * C11 (parallel end tangents, or a single interior point).
constexpr double kSingularDeterminant = 1e-10;
// Handles shorter than this fraction of the span's length are rejected (Schneider's epsilon).
constexpr double kMinHandleFraction = 1e-6;

// A span whose end tangents are within this angle (radians, as a sine) of its chord, and whose
// points all lie within tolerance of the chord, becomes a line piece (C1 with its neighbours).
constexpr double kStraightSine = 1e-9;

// The dense Hausdorff measure of a piece is certified within min(precision, this share of the
// tolerance), so that a piece is not refused for the measure's own slack; never below
// kMinPrecision metres (a zero tolerance accepts exact pieces only).
constexpr double kPrecisionShare = 0.05;
constexpr double kMinPrecision = 1e-9;

// Projection of a point onto a cubic: samples of t per piece to start from, then damped Newton.
constexpr int kProjectionSamples = 16;
constexpr int kProjectionNewtonSteps = 16;
constexpr int kProjectionHalvings = 4;

// Unit vector along v; (0, 0) when v is zero or not finite. Scaled first so that tiny or large
// vectors neither underflow nor overflow when squared.
Vec2 unitOrZero(Vec2 v) {
    const double s = std::max(std::abs(v.x), std::abs(v.y));
    if (!(s > 0.0) || !std::isfinite(s)) return Vec2(0.0);
    const Vec2 w = v / s;
    return w / glm::length(w);
}

double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

std::array<double, 4> bernstein3(double t) {
    const double s = 1.0 - t;
    return {s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t};
}

// Second derivative of a cubic (metres per unit t squared).
Vec2 secondDerivative(const BezierPiece& b, double t) {
    const Vec2 a = b.p[2] - 2.0 * b.p[1] + b.p[0];
    const Vec2 c = b.p[3] - 2.0 * b.p[2] + b.p[1];
    return 6.0 * ((1.0 - t) * a + t * c);
}

// Damped Newton descent of |B(t) - q| from t (on a cubic): each accepted step lowers the distance,
// so the result is attained by a point of the curve.
void refineProjection(const BezierPiece& b, Vec2 q, double& t, double& distance) {
    for (int step = 0; step < kProjectionNewtonSteps; ++step) {
        const Vec2 r = evaluate(b, t) - q;
        const Vec2 d1 = derivative(b, t);
        const double f = glm::dot(r, d1);
        const double fp = glm::dot(d1, d1) + glm::dot(r, secondDerivative(b, t));
        if (!(fp > 0.0) || f == 0.0) return;  // not heading to a minimum, or at one
        double h = f / fp;
        bool improved = false;
        for (int halving = 0; halving <= kProjectionHalvings && !improved; ++halving, h *= 0.5) {
            const double nt = std::clamp(t - h, 0.0, 1.0);
            const double nd = glm::length(evaluate(b, nt) - q);
            if (nd < distance) {
                t = nt;
                distance = nd;
                improved = true;
            }
        }
        if (!improved) return;
    }
}

// Distance from q to the cubic b (metres), attained at a point of b, so never below the true
// distance; `hint` is a parameter near the expected foot. Samples the piece, then refines from
// the hint and from the best sample.
double projectedDistance(const BezierPiece& b, Vec2 q, double hint) {
    double hintT = std::clamp(hint, 0.0, 1.0);
    double hintDistance = glm::length(evaluate(b, hintT) - q);
    double sampleT = 0.0, sampleDistance = kInfinity;
    for (int k = 0; k <= kProjectionSamples; ++k) {
        const double t = double(k) / kProjectionSamples;
        const double d = glm::length(evaluate(b, t) - q);
        if (d < sampleDistance) {
            sampleDistance = d;
            sampleT = t;
        }
    }
    refineProjection(b, q, hintT, hintDistance);
    refineProjection(b, q, sampleT, sampleDistance);
    return std::min(hintDistance, sampleDistance);
}

// The point of the polyline that q[i]'s tangent on one side (step -1: before, +1: after) is taken
// towards: the nearest one at least `reach` metres from q[i], else the farthest one along the walk
// (the polyline's end). A closed polyline is walked across its closing point (q[0] == q[m - 1]).
// Looking beyond the immediate neighbours keeps digitising noise much smaller than the tolerance
// out of the tangent and out of the corner test.
std::optional<Vec2> neighbour(std::span<const Vec2> q, std::size_t i, int step, bool closed, double reach) {
    const std::size_t m = q.size();
    const std::size_t cycle = m - 1;  // distinct positions of a closed polyline
    if (closed && i == m - 1) i = 0;
    std::optional<Vec2> found;
    std::size_t j = i;
    for (std::size_t walked = 0; walked + 1 < (closed ? cycle : m); ++walked) {
        if (step < 0) {
            if (j == 0 && !closed) break;
            j = j == 0 ? cycle - 1 : j - 1;
        } else {
            if (j + 1 == m && !closed) break;
            j = j + 1 == cycle && closed ? 0 : j + 1;
        }
        found = q[j];
        if (glm::length(q[j] - q[i]) >= reach) break;
    }
    return found;
}

// Tangents at a point of the polyline (unit vectors): `back` leaves the point towards the
// previous points, `forward` towards the next ones. Shared (back == -forward, along the central
// difference) unless the point is an end of an open polyline or a corner.
struct Joint {
    Vec2 back{0.0};
    Vec2 forward{0.0};
};

Joint jointAt(std::span<const Vec2> q, std::size_t i, bool closed, double reach) {
    const std::optional<Vec2> prev = neighbour(q, i, -1, closed, reach);
    const std::optional<Vec2> next = neighbour(q, i, +1, closed, reach);
    const Vec2 incoming = prev ? unitOrZero(q[i] - *prev) : Vec2(0.0);
    const Vec2 outgoing = next ? unitOrZero(*next - q[i]) : Vec2(0.0);
    Joint j{-incoming, outgoing};
    if (prev && next && glm::dot(incoming, outgoing) >= kCornerCosine) {
        const Vec2 centre = unitOrZero(*next - *prev);
        if (centre != Vec2(0.0)) j = {-centre, centre};
    }
    return j;
}

// Whether the polyline turns by more than kCornerCosine's angle at q[i] (jointAt's test).
bool isCorner(std::span<const Vec2> q, std::size_t i, bool closed, double reach) {
    const Joint j = jointAt(q, i, closed, reach);
    return j.back != -j.forward;
}

// Cumulative chord length of d, normalised to [0, 1] (d has distinct consecutive points).
std::vector<double> chordLengthParameters(std::span<const Vec2> d, double& length) {
    std::vector<double> u(d.size(), 0.0);
    for (std::size_t i = 1; i < d.size(); ++i) u[i] = u[i - 1] + glm::length(d[i] - d[i - 1]);
    length = u.back();
    for (double& x : u) x /= length;
    u.back() = 1.0;
    return u;
}

// Least-squares cubic through d[0] and d.back() with handles along t1 (at the start) and t2 (at
// the end), the points taken at parameters u. Sums are formed relative to d[0], so that large
// coordinates lose no precision; the handles fall back to Schneider's heuristic (a third of the
// chord, or of the polyline for a closed span) when the system is singular or gives a handle
// that is not positive or longer than the polyline (which would swing the curve far away).
BezierPiece leastSquaresCubic(std::span<const Vec2> d, std::span<const double> u, Vec2 t1, Vec2 t2,
                              double polylineLength) {
    const Vec2 p0 = d.front();
    const Vec2 p3 = d.back();
    const Vec2 chord = p3 - p0;
    double c00 = 0.0, c01 = 0.0, c11 = 0.0, x0 = 0.0, x1 = 0.0;
    for (std::size_t i = 0; i < d.size(); ++i) {
        const auto bern = bernstein3(u[i]);
        const Vec2 a1 = t1 * bern[1];
        const Vec2 a2 = t2 * bern[2];
        const Vec2 r = (d[i] - p0) - chord * (bern[2] + bern[3]);
        c00 += glm::dot(a1, a1);
        c01 += glm::dot(a1, a2);
        c11 += glm::dot(a2, a2);
        x0 += glm::dot(a1, r);
        x1 += glm::dot(a2, r);
    }
    const double chordLength = glm::length(chord);
    const double scale = std::max(chordLength, polylineLength);
    const auto valid = [&](double alpha) { return alpha >= kMinHandleFraction * scale && alpha <= polylineLength; };

    double alpha1 = -1.0, alpha2 = -1.0;
    const double det = c00 * c11 - c01 * c01;
    if (det > kSingularDeterminant * c00 * c11) {
        alpha1 = (x0 * c11 - x1 * c01) / det;
        alpha2 = (c00 * x1 - c01 * x0) / det;
    }
    if (!valid(alpha1) || !valid(alpha2)) {
        // Equal handles: one unknown, defined whenever the tangents are not zero.
        const double cc = c00 + 2.0 * c01 + c11;
        alpha1 = alpha2 = cc > 0.0 ? (x0 + x1) / cc : -1.0;
    }
    if (!valid(alpha1) || !valid(alpha2)) alpha1 = alpha2 = (chordLength > 0.0 ? chordLength : polylineLength) / 3.0;

    BezierPiece b;
    b.degree = 3;
    b.p = {p0, p0 + t1 * alpha1, p3 + t2 * alpha2, p3};
    return b;
}

// One Newton-Raphson step per interior point towards its nearest point on b (Schneider's
// reparameterisation); a step that is not finite leaves the parameter as it was.
void reparameterize(const BezierPiece& b, std::span<const Vec2> d, std::vector<double>& u) {
    for (std::size_t i = 1; i + 1 < d.size(); ++i) {
        const Vec2 r = evaluate(b, u[i]) - d[i];
        const Vec2 d1 = derivative(b, u[i]);
        const double numerator = glm::dot(r, d1);
        const double denominator = glm::dot(d1, d1) + glm::dot(r, secondDerivative(b, u[i]));
        if (denominator == 0.0) continue;
        const double v = u[i] - numerator / denominator;
        if (std::isfinite(v)) u[i] = std::clamp(v, 0.0, 1.0);
    }
}

struct Attempt {
    BezierPiece piece;
    std::vector<double> u;
    double maxError = kInfinity;  // metres, an upper bound of every interior point's distance
    std::size_t worst = 0;        // index in the span of the point with the largest error
};

// Errors of the interior points against b: the distance to B(u_i), and where that exceeds the
// tolerance, the projected distance, until one point is found beyond tolerance (the attempt has
// failed; later points keep the cheap bound, which still guides the split).
void measureAttempt(Attempt& a, std::span<const Vec2> d, double tolerance) {
    a.maxError = 0.0;
    a.worst = d.size() / 2;
    bool failed = false;
    for (std::size_t i = 1; i + 1 < d.size(); ++i) {
        double e = glm::length(evaluate(a.piece, a.u[i]) - d[i]);
        if (!(e <= tolerance) && !failed) {
            e = std::min(e, projectedDistance(a.piece, d[i], a.u[i]));
            failed = !(e <= tolerance);
        }
        if (!(e <= a.maxError)) {
            a.maxError = std::isnan(e) ? kInfinity : e;
            a.worst = i;
        }
    }
}

struct Span {
    std::size_t first = 0, last = 0;  // indices into the deduplicated points
    Vec2 t1{0.0};                     // unit tangent leaving q[first] into the span
    Vec2 t2{0.0};                     // unit tangent leaving q[last] back into the span
};

class Fitter {
public:
    Fitter(std::span<const Vec2> q, const SplineFitParams& params, bool closed)
        : q_(q), params_(params), closed_(closed), reach_(kTangentReachTolerances * params.tolerance),
          precision_(std::max(std::min(params.precision, kPrecisionShare * params.tolerance), kMinPrecision)) {
        result_.vertices.push_back(Vertex{q.front(), true});
        result_.inputPoints = q.size();
    }

    // Fits q[first..last] (first < last) and appends its vertices after q[first]'s.
    void fit(std::size_t first, std::size_t last) {
        std::vector<Span> stack{{first, last, jointAt(q_, first, closed_, reach_).forward, jointAt(q_, last, closed_, reach_).back}};
        while (!stack.empty()) {
            const Span s = stack.back();
            stack.pop_back();
            if (const auto split = fitSpan(s)) {
                // Push the right half first: the left one is fitted (and emitted) next.
                const Joint j = jointAt(q_, *split, closed_, reach_);
                stack.push_back({*split, s.last, j.forward, s.t2});
                stack.push_back({s.first, *split, s.t1, j.back});
            }
        }
    }

    SplineFitResult take() { return std::move(result_); }

private:
    // Emits the span's piece when it fits and returns nothing, or returns the index to split at.
    std::optional<std::size_t> fitSpan(const Span& s) {
        const std::span<const Vec2> d = q_.subspan(s.first, s.last - s.first + 1);
        if (d.size() == 2) {
            emitLine(s.last, 0.0);
            return std::nullopt;
        }
        if (const auto error = straightError(d, s)) {
            emitLine(s.last, *error);
            return std::nullopt;
        }

        double length = 0.0;
        Attempt current;
        current.u = chordLengthParameters(d, length);
        current.piece = leastSquaresCubic(d, current.u, s.t1, s.t2, length);
        measureAttempt(current, d, params_.tolerance);
        Attempt best = current;
        if (best.maxError > params_.tolerance && best.maxError <= kReparameterizeGate * params_.tolerance) {
            for (int it = 0; it < params_.maxIterations && best.maxError > params_.tolerance; ++it) {
                reparameterize(current.piece, d, current.u);
                current.piece = leastSquaresCubic(d, current.u, s.t1, s.t2, length);
                measureAttempt(current, d, params_.tolerance);
                if (current.maxError < best.maxError) best = current;
            }
        }
        if (!(best.maxError <= params_.tolerance)) return s.first + best.worst;

        // The points are within tolerance; the whole piece and every source segment must be too
        // (a long segment between two points can lie far from a curve through both).
        // Stretches that cannot beat the largest distance of the curve's pieces so far are not
        // refined: the measure is then exact (within the precision) for the curve, and cheap.
        HausdorffParams dense;
        dense.precision = precision_;
        dense.giveUpAbove = params_.tolerance;
        dense.goodEnough = std::min(result_.maxError, params_.tolerance);
        const Hausdorff h = hausdorff(best.piece, d, dense);
        if (!(h.upper() <= params_.tolerance)) {
            const DistanceBound& worst = h.curveToSource.lower >= h.sourceToCurve.lower ? h.curveToSource : h.sourceToCurve;
            return s.first + nearestInterior(d, worst.where);
        }
        result_.vertices.push_back(Vertex{best.piece.p[1], false});
        result_.vertices.push_back(Vertex{best.piece.p[2], false});
        result_.vertices.push_back(Vertex{q_[s.last], true});
        result_.maxError = std::max(result_.maxError, h.upper());
        return std::nullopt;
    }

    // Index (in d) of the interior point nearest to p: where a span that strays is split.
    static std::size_t nearestInterior(std::span<const Vec2> d, Vec2 p) {
        std::size_t best = 1;
        double bestDistance = kInfinity;
        for (std::size_t i = 1; i + 1 < d.size(); ++i) {
            const double e = glm::length(d[i] - p);
            if (e < bestDistance) bestDistance = e, best = i;
        }
        return best;
    }

    // When a line piece can replace the cubic (end tangents along the chord, every point within
    // tolerance of it), the Hausdorff distance between the chord and the polyline: the largest
    // distance of a point to the chord. Segments between points are no farther (convexity), and
    // each chord point has a polyline point with the same projection on the chord's line, no
    // farther from it than that point is from the chord.
    std::optional<double> straightError(std::span<const Vec2> d, const Span& s) const {
        const Vec2 along = unitOrZero(d.back() - d.front());
        if (along == Vec2(0.0)) return std::nullopt;
        const auto aligned = [](Vec2 t, Vec2 dir) {
            return glm::dot(t, dir) > 0.0 && std::abs(cross(t, dir)) <= kStraightSine;
        };
        if (!aligned(s.t1, along) || !aligned(s.t2, -along)) return std::nullopt;
        double error = 0.0;
        for (std::size_t i = 1; i + 1 < d.size(); ++i) {
            error = std::max(error, distanceToSegment(d[i], d.front(), d.back()));
            if (!(error <= params_.tolerance)) return std::nullopt;
        }
        return error;
    }

    void emitLine(std::size_t last, double error) {
        result_.vertices.push_back(Vertex{q_[last], true});
        result_.maxError = std::max(result_.maxError, error);
    }

    std::span<const Vec2> q_;
    SplineFitParams params_;
    bool closed_;
    double reach_;
    double precision_;  // metres: of the dense Hausdorff measure
    SplineFitResult result_;
};

}  // namespace

SplineFitResult fitSpline(std::span<const Vec2> points, const SplineFitParams& params,
                          std::span<const std::size_t> keep) {
    if (!std::isfinite(params.tolerance) || params.tolerance < 0.0)
        throw std::invalid_argument("fitSpline: tolerance must be finite and >= 0");
    if (params.maxIterations < 0) throw std::invalid_argument("fitSpline: maxIterations must be >= 0");
    if (!(params.precision > 0.0) || !std::isfinite(params.precision))
        throw std::invalid_argument("fitSpline: precision must be finite and > 0");
    for (const Vec2& p : points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y))
            throw std::invalid_argument("fitSpline: non-finite coordinate");

    // Drop consecutive duplicates; index[i] is the kept point equal to points[i].
    std::vector<Vec2> q;
    std::vector<std::size_t> index(points.size());
    q.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (q.empty() || points[i] != q.back()) q.push_back(points[i]);
        index[i] = q.size() - 1;
    }
    if (q.size() < 2) throw std::invalid_argument("fitSpline: fewer than 2 distinct points");
    // The last point is the input's own (a run of equal points may differ in the sign of a zero).
    q.back() = points.back();
    const bool closed = q.front() == q.back();

    std::vector<std::size_t> breaks{0, q.size() - 1};
    for (std::size_t k : keep) {
        if (k >= points.size())
            throw std::invalid_argument("fitSpline: keep index " + std::to_string(k) + " out of range (" +
                                        std::to_string(points.size()) + " points)");
        breaks.push_back(index[k]);
    }
    // Corners stay corners: split there, each side with its own tangent.
    const double reach = kTangentReachTolerances * params.tolerance;
    for (std::size_t i = 1; i + 1 < q.size(); ++i)
        if (isCorner(q, i, closed, reach)) breaks.push_back(i);
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());

    Fitter fitter(q, params, closed);
    for (std::size_t b = 0; b + 1 < breaks.size(); ++b) fitter.fit(breaks[b], breaks[b + 1]);
    SplineFitResult result = fitter.take();
    // Every piece was proven within tolerance of its stretch (a measure that ran out of
    // evaluations leaves a looser bound, but the proof holds).
    result.maxError = std::min(result.maxError, params.tolerance);
    return result;
}

}  // namespace lacet
