// Dense Hausdorff measure (model/hausdorff.h) against a brute-force reference: uniform sampling of
// both sides, far finer than the branch and bound evaluates.
#include "model/hausdorff.h"

#include <random>

#include <gtest/gtest.h>

namespace lacet {
namespace {

// Largest distance from samples of the piece to the polyline and from samples of the polyline to
// the piece (distanceTo, within 1e-7 m): a lower bound of each directed distance.
std::pair<double, double> bruteForce(const BezierPiece& b, const std::vector<Vec2>& polyline, int samples) {
    double toPolyline = 0.0, toCurve = 0.0;
    for (int k = 0; k <= samples; ++k) {
        const Vec2 q = evaluate(b, double(k) / samples);
        double d = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i + 1 < polyline.size(); ++i) d = std::min(d, distanceToSegment(q, polyline[i], polyline[i + 1]));
        toPolyline = std::max(toPolyline, d);
    }
    for (std::size_t i = 0; i + 1 < polyline.size(); ++i)
        for (int k = 0; k <= samples; ++k)
            toCurve = std::max(toCurve, distanceTo(b, polyline[i] + (polyline[i + 1] - polyline[i]) * (double(k) / samples), 1e-7));
    return {toPolyline, toCurve};
}

TEST(Hausdorff, BoundsBracketABruteForceReferenceOnRandomPiecesAndPolylines) {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-50.0, 50.0);
#ifdef LACET_SANITIZED
    constexpr int kTrials = 20;  // ten times slower there; the Release suite runs all 60
#else
    constexpr int kTrials = 60;
#endif
    for (int trial = 0; trial < kTrials; ++trial) {
        BezierPiece b;
        b.degree = 1 + int(rng() % 3);
        for (int i = 0; i <= b.degree; ++i) b.p[std::size_t(i)] = Vec2(u(rng), u(rng));
        std::vector<Vec2> polyline{b.start()};
        // Few segments (the brute-force loop) or many (found through the BoxGrid, past 16).
        const int interior = trial % 2 ? int(rng() % 6) : 20 + int(rng() % 30);
        for (int i = interior; i > 0; --i) polyline.push_back(Vec2(u(rng), u(rng)));
        polyline.push_back(b.end());
        HausdorffParams params;
        params.precision = 1e-3;
        const Hausdorff h = hausdorff(b, polyline, params);
        const int samples = trial % 2 ? 1000 : 300;
        const auto [toPolyline, toCurve] = bruteForce(b, polyline, samples);
        SCOPED_TRACE(trial);
        // The reference samples lie on the sides: no sample can be farther than the upper bound,
        // and the lower bound is attained, so the finest sampling gets within its spacing of it.
        EXPECT_LE(toPolyline, h.curveToSource.upper + 1e-9);
        EXPECT_LE(toCurve, h.sourceToCurve.upper + 1e-7);
        EXPECT_LE(h.curveToSource.upper - h.curveToSource.lower, params.precision + 1e-12);
        EXPECT_LE(h.sourceToCurve.upper - h.sourceToCurve.lower, params.precision + 1e-12);
        const double spacing = 4.0 * speedBound(b) / samples;  // generous: sampling of a piece in t
        EXPECT_LE(h.curveToSource.lower, toPolyline + spacing);
        EXPECT_FALSE(h.curveToSource.exhausted || h.sourceToCurve.exhausted);
    }
}

TEST(Hausdorff, DecisionModeStopsAtAProvenExcess) {
    // A semicircle-like cubic against its chord: far more than 1 m away in the middle.
    BezierPiece b;
    b.degree = 3;
    b.p = {Vec2(0.0), Vec2(0.0, 40.0), Vec2(100.0, 40.0), Vec2(100.0, 0.0)};
    const std::vector<Vec2> chord{Vec2(0.0), Vec2(100.0, 0.0)};
    HausdorffParams decide;
    decide.giveUpAbove = 1.0;
    const Hausdorff h = hausdorff(b, chord, decide);
    EXPECT_GT(h.lower(), 1.0);
    EXPECT_GE(h.upper(), 30.0);  // the true distance is 30 m (at t = 1/2), and upper is a bound
    const Hausdorff exact = hausdorff(b, chord, HausdorffParams{});
    EXPECT_NEAR(exact.curveToSource.upper, 30.0, 0.011);
    EXPECT_NEAR(exact.sourceToCurve.lower, 30.0, 0.011);  // the chord's midpoint is 30 m from the curve
}

TEST(Hausdorff, DistanceUpperBoundIsAttainedAndWithinPrecision) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    for (int trial = 0; trial < 500; ++trial) {
        BezierPiece b;
        b.degree = 3;
        for (auto& p : b.p) p = Vec2(u(rng), u(rng));
        const Vec2 q(u(rng), u(rng));
        const double exact = distanceTo(b, q, 1e-10);
        const double ub = distanceUpperBound(b, q, 1e-4);
        EXPECT_GE(ub, exact - 2e-10);
        EXPECT_LE(ub, exact + 1e-4 + 2e-10);
    }
}

}  // namespace
}  // namespace lacet
