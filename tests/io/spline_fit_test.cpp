// Fitting polylines with cubic Bezier chains (io/spline_fit.h): every check measures the result
// independently (branch-and-bound distance from each input point to the fitted curve).
#include "io/spline_fit.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/bezier.h"
#include "model/graph.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

// Random polylines of the property test: fewer under the sanitizers, which run it ten times slower
// (the same code paths; the Release suite runs them all).
constexpr int kRandomTrials = test::sanitizedOr(400, 60);

// Accuracy of the independent distance measurement (metres).
constexpr double kMeasureTolerance = 1e-7;

bool bitwiseEqual(Vec2 a, Vec2 b) {
    return std::bit_cast<std::uint64_t>(a.x) == std::bit_cast<std::uint64_t>(b.x) &&
           std::bit_cast<std::uint64_t>(a.y) == std::bit_cast<std::uint64_t>(b.y);
}

std::size_t onCurveCount(const SplineFitResult& r) {
    return std::size_t(std::count_if(r.vertices.begin(), r.vertices.end(), [](const Vertex& v) { return v.onCurve; }));
}

// Structure of the result: finite, on-curve ends bitwise equal to the input's ends, and 0 or 2
// controls between on-curve vertices.
void expectWellFormed(const SplineFitResult& r, const std::vector<Vec2>& points) {
    ASSERT_GE(r.vertices.size(), 2u);
    EXPECT_TRUE(r.vertices.front().onCurve);
    EXPECT_TRUE(r.vertices.back().onCurve);
    EXPECT_TRUE(bitwiseEqual(r.vertices.front().p, points.front()));
    EXPECT_TRUE(bitwiseEqual(r.vertices.back().p, points.back()));
    EXPECT_TRUE(std::isfinite(r.maxError));
    int controls = 0;
    for (const Vertex& v : r.vertices) {
        ASSERT_TRUE(std::isfinite(v.p.x) && std::isfinite(v.p.y));
        EXPECT_FALSE(v.closing);
        if (v.onCurve) {
            EXPECT_TRUE(controls == 0 || controls == 2) << controls << " controls between on-curve vertices";
            controls = 0;
        } else {
            ++controls;
        }
    }
}

// Samples per Bezier piece and per input segment of the independent dense measure.
constexpr int kDenseSamples = 16;

// The Hausdorff distance between the fitted curve and the input polyline, both ways, measured
// independently of the fitter and of model/hausdorff.h: every piece and every input segment
// sampled at kDenseSamples + 1 points, each measured against the whole other side (segment
// distances exactly, curve distances by branch and bound). A lower bound of the true distance.
double measuredError(const SplineFitResult& r, const std::vector<Vec2>& points) {
    std::vector<BezierPiece> pieces;
    forEachPiece(r.vertices, [&](const BezierPiece& b, std::size_t) { pieces.push_back(b); });
    auto toCurve = [&](Vec2 q) {
        double d = std::numeric_limits<double>::infinity();
        for (const BezierPiece& b : pieces) d = std::min(d, distanceTo(b, q, kMeasureTolerance));
        return d;
    };
    auto toPolyline = [&](Vec2 q) {
        double d = glm::length(q - points.front());
        for (std::size_t i = 0; i + 1 < points.size(); ++i) d = std::min(d, distanceToSegment(q, points[i], points[i + 1]));
        return d;
    };
    double worst = 0.0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
        for (int k = 0; k <= kDenseSamples; ++k)
            worst = std::max(worst, toCurve(points[i] + (points[i + 1] - points[i]) * (double(k) / kDenseSamples)));
    if (points.size() == 1) worst = toCurve(points.front());
    for (const BezierPiece& b : pieces)
        for (int k = 0; k <= kDenseSamples; ++k) worst = std::max(worst, toPolyline(evaluate(b, double(k) / kDenseSamples)));
    return worst;
}

// Fits, checks structure and error, and returns the result.
SplineFitResult fitAndCheck(const std::vector<Vec2>& points, const SplineFitParams& params,
                            const std::vector<std::size_t>& keep = {}) {
    SplineFitResult r = fitSpline(points, params, keep);
    expectWellFormed(r, points);
    EXPECT_LE(r.maxError, params.tolerance);
    const double measured = measuredError(r, points);
    EXPECT_LE(measured, params.tolerance + kMeasureTolerance);
    // The reported error bounds the whole curve's distance to the polyline, both ways.
    EXPECT_LE(measured, r.maxError + kMeasureTolerance);
    return r;
}

// The keep points appear, in order, among the on-curve vertices.
void expectKept(const SplineFitResult& r, const std::vector<Vec2>& points, std::vector<std::size_t> keep) {
    std::sort(keep.begin(), keep.end());
    std::size_t pos = 0;
    for (std::size_t k : keep) {
        while (pos < r.vertices.size() && !(r.vertices[pos].onCurve && r.vertices[pos].p == points[k])) ++pos;
        ASSERT_LT(pos, r.vertices.size()) << "keep index " << k << " is not an on-curve vertex";
    }
}

// Largest angle (radians) between the incoming and outgoing handles at interior on-curve vertices
// joining two cubics.
double worstHandleKink(const std::vector<Vertex>& v) {
    double worst = 0.0;
    for (std::size_t i = 1; i + 1 < v.size(); ++i) {
        if (!v[i].onCurve || v[i - 1].onCurve || v[i + 1].onCurve) continue;
        const Vec2 a = glm::normalize(v[i].p - v[i - 1].p);
        const Vec2 b = glm::normalize(v[i + 1].p - v[i].p);
        worst = std::max(worst, std::abs(std::atan2(a.x * b.y - a.y * b.x, glm::dot(a, b))));
    }
    return worst;
}

std::vector<Vec2> arc(Vec2 centre, double radius, double from, double to, std::size_t n) {
    std::vector<Vec2> out;
    for (std::size_t i = 0; i < n; ++i) {
        const double a = from + (to - from) * double(i) / double(n - 1);
        out.push_back(centre + radius * Vec2(std::cos(a), std::sin(a)));
    }
    return out;
}

std::vector<Vec2> sine(Vec2 origin, double amplitude, double wavelength, double length, double step) {
    std::vector<Vec2> out;
    const auto n = std::size_t(std::llround(length / step));
    for (std::size_t i = 0; i <= n; ++i) {
        const double x = double(i) * step;
        out.push_back(origin + Vec2(x, amplitude * std::sin(2.0 * std::numbers::pi * x / wavelength)));
    }
    return out;
}

void report(const char* what, const std::vector<Vec2>& points, const SplineFitResult& r, double tolerance) {
    std::cout << "[ figures  ] " << what << ": " << points.size() << " points -> " << onCurveCount(r)
              << " on-curve vertices (" << r.vertices.size() << " with controls), "
              << double(points.size()) / double(onCurveCount(r)) << "x fewer on-curve, max error " << r.maxError
              << " m for tolerance " << tolerance << " m\n";
}

TEST(SplineFit, StraightLineGivesOnePieceWithNoError) {
    std::vector<Vec2> points;
    for (int i = 0; i <= 50; ++i) points.push_back(Vec2(3.0 + 1.5 * i, -2.0 + 0.7 * i));
    const SplineFitResult r = fitAndCheck(points, {});
    EXPECT_EQ(onCurveCount(r), 2u);
    EXPECT_TRUE(r.vertices.size() == 2 || r.vertices.size() == 4);
    // On the line: the measure's upper bound is within its precision of 0.
    EXPECT_LE(r.maxError, SplineFitParams{}.precision);
    EXPECT_EQ(r.inputPoints, points.size());

    // Two points: one line piece.
    const std::vector<Vec2> two{{1.0, 2.0}, {4.0, 6.0}};
    const SplineFitResult r2 = fitAndCheck(two, {});
    EXPECT_EQ(r2.vertices.size(), 2u);
    EXPECT_EQ(r2.maxError, 0.0);
}

TEST(SplineFit, CircleArcFitsWithFarFewerVertices) {
    const SplineFitParams params{0.05, 4};
    // 270 degrees of a 100 m radius, a point every ~0.5 m.
    const auto points = arc({0.0, 0.0}, 100.0, 0.0, 1.5 * std::numbers::pi, 943);
    const SplineFitResult r = fitAndCheck(points, params);
    report("circle arc r=100 m, 270 deg", points, r, params.tolerance);
    EXPECT_LE(onCurveCount(r), points.size() / 50);
    EXPECT_LT(worstHandleKink(r.vertices), 1e-9);  // C1 at every joint
}

TEST(SplineFit, SineWaveFitsWithFarFewerVertices) {
    const SplineFitParams params{0.1, 4};
    const auto points = sine({0.0, 0.0}, 20.0, 100.0, 500.0, 0.25);
    const SplineFitResult r = fitAndCheck(points, params);
    report("sine wave (amplitude 20 m, wavelength 100 m, 500 m)", points, r, params.tolerance);
    EXPECT_LE(onCurveCount(r), points.size() / 40);
    EXPECT_LT(worstHandleKink(r.vertices), 1e-9);
}

TEST(SplineFit, HairpinFitsWithinToleranceWithoutNaN) {
    // Up x = 0, a 1 m wide turn at the top, back down x = 1 (the legs 1 m apart).
    std::vector<Vec2> points;
    for (int i = 0; i <= 60; ++i) points.push_back(Vec2(0.0, 0.5 * i));
    points.push_back(Vec2(0.5, 30.4));
    for (int i = 60; i >= 0; --i) points.push_back(Vec2(1.0, 0.5 * i));
    for (double tolerance : {0.05, 0.5, 2.0}) {
        const SplineFitResult r = fitAndCheck(points, {tolerance, 4});
        report("hairpin 1 m wide", points, r, tolerance);
    }

    // The same way back along the same line (the tangent reverses), ending short of the start or
    // exactly on it (closed).
    std::vector<Vec2> reversal;
    for (int i = 0; i <= 40; ++i) reversal.push_back(Vec2(0.25 * i, 0.5 * i));
    for (int i = 39; i >= 1; --i) reversal.push_back(Vec2(0.25 * i, 0.5 * i));
    for (const Vec2& end : {Vec2(0.0, 0.0), Vec2(0.125, 0.25)}) {
        std::vector<Vec2> p = reversal;
        p.push_back(end);
        for (double tolerance : {0.01, 0.5, 5.0}) fitAndCheck(p, {tolerance, 4});
    }

    // A, B, A and A, B, A, B.
    fitAndCheck({{0.0, 0.0}, {10.0, 0.0}, {0.0, 0.0}}, {});
    fitAndCheck({{0.0, 0.0}, {10.0, 0.0}, {0.0, 0.0}, {10.0, 0.0}}, {});
}

TEST(SplineFit, KeepIndicesBecomeOnCurveVertices) {
    const SplineFitParams params{0.1, 4};
    const auto points = sine({0.0, 0.0}, 20.0, 100.0, 300.0, 0.5);
    const std::vector<std::size_t> keep{450, 100, 237, 100, 0, points.size() - 1, 101};
    const SplineFitResult r = fitAndCheck(points, params, keep);
    expectKept(r, points, keep);
    // Smooth there: the curve stays C1 through the kept points.
    EXPECT_LT(worstHandleKink(r.vertices), 1e-9);
    const SplineFitResult unconstrained = fitSpline(points, params);
    std::cout << "[ figures  ] sine with 4 kept interior points: " << onCurveCount(r) << " on-curve vertices ("
              << onCurveCount(unconstrained) << " without)\n";

    // A kept point in a run of duplicates, and kept corners of an L.
    std::vector<Vec2> l;
    for (int i = 0; i <= 40; ++i) l.push_back(Vec2(i, 0.0));
    l.push_back(Vec2(40.0, 0.0));
    for (int i = 1; i <= 40; ++i) l.push_back(Vec2(40.0, i));
    const std::vector<std::size_t> keepL{41, 20};
    const SplineFitResult rl = fitAndCheck(l, params, keepL);
    expectKept(rl, l, keepL);
    EXPECT_EQ(rl.inputPoints, l.size() - 1);
}

TEST(SplineFit, CornersAndClosedPolylines) {
    // An L without kept points: still within tolerance (the corner is a cusp, not rounded).
    std::vector<Vec2> l;
    for (int i = 0; i <= 40; ++i) l.push_back(Vec2(i, 0.0));
    for (int i = 1; i <= 40; ++i) l.push_back(Vec2(40.0, i));
    const SplineFitResult rl = fitAndCheck(l, {0.1, 4});
    EXPECT_LE(onCurveCount(rl), 4u);

    // A closed circle: the closing point is kept and the curve is C1 there too.
    auto circle = arc({5.0, -3.0}, 50.0, 0.0, 2.0 * std::numbers::pi, 400);
    circle.back() = circle.front();
    const SplineFitResult rc = fitAndCheck(circle, {0.05, 4});
    report("closed circle r=50 m", circle, rc, 0.05);
    EXPECT_EQ(rc.vertices.front().p, rc.vertices.back().p);
    EXPECT_LT(worstHandleKink(rc.vertices), 1e-9);
    const auto& v = rc.vertices;
    ASSERT_GE(v.size(), 4u);
    const Vec2 out = glm::normalize(v[1].p - v[0].p);
    const Vec2 in = glm::normalize(v[v.size() - 1].p - v[v.size() - 2].p);
    EXPECT_GT(glm::dot(out, in), 1.0 - 1e-12);

    // A closed square: four corners, fitted by line pieces.
    std::vector<Vec2> square;
    for (int i = 0; i < 10; ++i) square.push_back(Vec2(i, 0.0));
    for (int i = 0; i < 10; ++i) square.push_back(Vec2(10.0, i));
    for (int i = 10; i > 0; --i) square.push_back(Vec2(i, 10.0));
    for (int i = 10; i >= 0; --i) square.push_back(Vec2(0.0, i));
    const SplineFitResult rs = fitAndCheck(square, {0.01, 4});
    EXPECT_EQ(rs.vertices.size(), 5u);
    EXPECT_LE(rs.maxError, 0.01 / 20.0);  // 0, measured within min(precision, tolerance / 20)
}

TEST(SplineFit, HugeCoordinatesKeepTheErrorWithinTolerance) {
    // Under the sanitizers, the largest offset only.
    const std::vector<Vec2> offsets = test::kSanitized ? std::vector<Vec2>{Vec2(1e7, -1e7)}
                                                       : std::vector<Vec2>{Vec2(1e6, 1e6), Vec2(-3e6, 5e6), Vec2(1e7, -1e7)};
    for (const Vec2 offset : offsets) {
        const SplineFitParams params{0.02, 4};
        const auto circle = arc(offset, 100.0, 0.3, 0.3 + 1.5 * std::numbers::pi, 943);
        const SplineFitResult rc = fitAndCheck(circle, params);
        const auto wave = sine(offset, 20.0, 100.0, 500.0, 0.25);
        const SplineFitResult rw = fitAndCheck(wave, params);
        // The fit does not lose accuracy to the offset: about as many vertices as near the origin.
        const SplineFitResult near = fitSpline(sine({0.0, 0.0}, 20.0, 100.0, 500.0, 0.25), params);
        EXPECT_LE(onCurveCount(rw), onCurveCount(near) + 4);
        std::cout << "[ figures  ] offset (" << offset.x << ", " << offset.y << "): arc " << onCurveCount(rc)
                  << " on-curve vertices, error " << rc.maxError << " m; sine " << onCurveCount(rw) << " (" << onCurveCount(near)
                  << " at the origin), error " << rw.maxError << " m\n";
    }
}

TEST(SplineFit, RandomPolylinesStayWithinToleranceWithExactEnds) {
    std::mt19937_64 rng(20240607);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto logUniform = [&](double lo, double hi) { return lo * std::pow(hi / lo, unit(rng)); };
    std::size_t totalPoints = 0, totalOnCurve = 0;
    double worstRatio = 0.0;
    for (int trial = 0; trial < kRandomTrials; ++trial) {
        const int n = 2 + int(rng() % 120);
        const double maxTurn = std::array{0.02, 0.3, 1.5, 3.2}[rng() % 4];
        const Vec2 offset = unit(rng) < 0.3 ? Vec2(1e6 * unit(rng), -2e6 * unit(rng)) : Vec2(0.0);
        std::vector<Vec2> points{offset + Vec2(unit(rng), unit(rng)) * 100.0};
        double heading = unit(rng) * 2.0 * std::numbers::pi;
        while (int(points.size()) < n) {
            const double r = unit(rng);
            if (r < 0.08 && points.size() > 1) {
                points.push_back(points.back());  // duplicate
            } else if (r < 0.12 && points.size() > 1) {
                points.push_back(points[points.size() - 2]);  // straight back
            } else {
                heading += (2.0 * unit(rng) - 1.0) * maxTurn;
                // Mostly short steps, and now and then a long straight one (a track's 400 m
                // between two bends became a 43 m arc when only the points were checked).
                const double step = unit(rng) < 0.1 ? logUniform(50.0, 500.0) : logUniform(0.01, 20.0);
                points.push_back(points.back() + step * Vec2(std::cos(heading), std::sin(heading)));
            }
        }
        if (points.size() > 3 && unit(rng) < 0.2) points.push_back(points.front());  // closed
        const SplineFitParams params{unit(rng) < 0.05 ? 0.0 : logUniform(0.001, 5.0), int(rng() % 7)};
        std::vector<std::size_t> keep;
        for (int k = int(rng() % 4); k > 0; --k) keep.push_back(rng() % points.size());

        SCOPED_TRACE(testing::Message() << "trial " << trial << ", " << points.size() << " points, tolerance "
                                        << params.tolerance);
        if (std::all_of(points.begin(), points.end(), [&](Vec2 p) { return p == points.front(); })) continue;
        const SplineFitResult r = fitAndCheck(points, params, keep);
        expectKept(r, points, keep);
        const SplineFitResult again = fitSpline(points, params, keep);
        EXPECT_EQ(r.vertices, again.vertices);  // deterministic
        EXPECT_EQ(r.maxError, again.maxError);
        totalPoints += points.size();
        totalOnCurve += onCurveCount(r);
        worstRatio = std::max(worstRatio, r.maxError / params.tolerance);
    }
    std::cout << "[ figures  ] random polylines: " << totalPoints << " points -> " << totalOnCurve
              << " on-curve vertices, worst error " << worstRatio << " of the tolerance\n";
}

TEST(SplineFit, RejectsInvalidInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const SplineFitParams params;
    const auto fit = [&](std::vector<Vec2> p) { return fitSpline(p, params); };
    EXPECT_THROW(fit({}), std::invalid_argument);
    EXPECT_THROW(fit({{1.0, 2.0}}), std::invalid_argument);
    EXPECT_THROW(fit({{1.0, 2.0}, {1.0, 2.0}, {1.0, 2.0}}), std::invalid_argument);
    EXPECT_THROW(fit({{0.0, 0.0}, {nan, 1.0}, {2.0, 2.0}}), std::invalid_argument);
    EXPECT_THROW(fit({{0.0, 0.0}, {1.0, 1.0}, {2.0, nan}}), std::invalid_argument);
    EXPECT_THROW(fit({{0.0, 0.0}, {inf, 1.0}}), std::invalid_argument);
    const std::vector<Vec2> ok{{0.0, 0.0}, {1.0, 1.0}, {2.0, 0.0}};
    const std::vector<std::size_t> badKeep{3};
    EXPECT_THROW(fitSpline(ok, params, badKeep), std::invalid_argument);
    EXPECT_THROW(fitSpline(ok, {-1.0, 4}), std::invalid_argument);
    EXPECT_THROW(fitSpline(ok, {nan, 4}), std::invalid_argument);
    EXPECT_THROW(fitSpline(ok, {0.5, -1}), std::invalid_argument);
    // A zero tolerance is valid: the polyline itself (line pieces) where no cubic is exact.
    const SplineFitResult r = fitAndCheck(ok, {0.0, 4});
    EXPECT_EQ(r.maxError, 0.0);
}

TEST(SplineFit, EndsAreBitwiseTheInputs) {
    // A run of equal points at the end whose last differs only in the sign of a zero.
    const std::vector<Vec2> points{{-0.0, 1.0}, {3.0, 4.0}, {7.0, 2.0}, {9.0, 0.0}, {9.0, -0.0}};
    const SplineFitResult r = fitAndCheck(points, {});
    EXPECT_EQ(r.inputPoints, 4u);
    EXPECT_TRUE(std::signbit(r.vertices.front().p.x));
    EXPECT_TRUE(std::signbit(r.vertices.back().p.y));
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Issue 12: a 429 m straight stretch of two points between curvy parts became an arc 43 m off its
// line (the fit was checked at the points only). Every long segment now stays within tolerance.
TEST(SplineFit, LongStraightSegmentsBetweenBendsStayOnTheirLine) {
    for (const double tolerance : {0.5, 2.0, 5.0}) {
        std::vector<Vec2> points = arc(Vec2(0.0), 60.0, 0.0, 1.2, 12);
        const Vec2 end = points.back();
        const Vec2 dir = glm::normalize(Vec2(-std::sin(1.2), std::cos(1.2)));
        points.push_back(end + 429.0 * dir);  // one long straight segment, tangent to the arc
        const std::vector<Vec2> bend = arc(points.back() + 40.0 * Vec2(dir.y, -dir.x), 40.0, 1.2 + std::numbers::pi, 2.2 + std::numbers::pi, 10);
        points.insert(points.end(), bend.begin() + 1, bend.end());
        SCOPED_TRACE(tolerance);
        fitAndCheck(points, {tolerance});
    }
}

// Chains merged at a junction meet at an angle: the corner is kept as an on-curve vertex with
// one-sided tangents, neither cut nor bulged beyond the tolerance.
TEST(SplineFit, CornersOfMergedChainsAreVerticesWithinTolerance) {
    std::vector<Vec2> points;
    for (int i = 0; i <= 20; ++i) points.push_back(Vec2(10.0 * i, 0.0));                    // east, 200 m
    for (int i = 1; i <= 20; ++i) points.push_back(Vec2(200.0 + 7.0 * i, 7.0 * i));         // then 45 deg left
    for (int i = 1; i <= 20; ++i) points.push_back(Vec2(340.0 - 8.0 * i, 140.0 + 3.0 * i));  // then back, sharply
    const SplineFitResult r = fitAndCheck(points, {0.5});
    for (const std::size_t corner : {std::size_t(20), std::size_t(40)}) {
        const bool vertex = std::any_of(r.vertices.begin(), r.vertices.end(),
                                        [&](const Vertex& v) { return v.onCurve && v.p == points[corner]; });
        EXPECT_TRUE(vertex) << "corner " << corner;
    }
}

}  // namespace
}  // namespace lacet
