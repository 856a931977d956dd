#include "model/bezier.h"

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace lacet {
namespace {

BezierPiece cubic(Vec2 a, Vec2 b, Vec2 c, Vec2 d) { return {3, {a, b, c, d}}; }

std::vector<BezierPiece> randomPieces(std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    std::vector<BezierPiece> out;
    for (int i = 0; i < n; ++i) {
        BezierPiece b;
        b.degree = 1 + int(rng() % 3);
        for (int k = 0; k <= b.degree; ++k) b.p[k] = Vec2(double(rng() % 2000) - 1000.0, double(rng() % 2000) - 1000.0);
        out.push_back(b);
    }
    return out;
}

TEST(Bezier, EvaluateHitsEndsAndSplitIsConsistent) {
    for (const auto& b : randomPieces(1, 200)) {
        EXPECT_EQ(evaluate(b, 0.0), b.start());
        EXPECT_EQ(evaluate(b, 1.0), b.end());
        const auto [l, r] = split(b, 0.3);
        for (double t : {0.0, 0.25, 0.5, 1.0}) {
            EXPECT_LT(glm::length(evaluate(l, t) - evaluate(b, 0.3 * t)), 1e-9);
            EXPECT_LT(glm::length(evaluate(r, t) - evaluate(b, 0.3 + 0.7 * t)), 1e-9);
        }
    }
}

TEST(Bezier, SplitHalfOfReversedPieceIsTheMirrorBitForBit) {
    for (const auto& b : randomPieces(2, 200)) {
        const auto [l, r] = splitHalf(b);
        const auto [rl, rr] = splitHalf(b.reversed());
        for (int k = 0; k <= b.degree; ++k) {
            EXPECT_EQ(l.p[k], rr.reversed().p[k]);
            EXPECT_EQ(r.p[k], rl.reversed().p[k]);
        }
    }
}

TEST(Bezier, TightBoundsContainTheCurveAndTouchIt) {
    for (const auto& b : randomPieces(3, 300)) {
        const Box box = tightBounds(b);
        Box sampled{b.start(), b.start()};
        for (int i = 0; i <= 4000; ++i) {
            const Vec2 p = evaluate(b, i / 4000.0);
            EXPECT_TRUE(box.contains(p));
            sampled.min = glm::min(sampled.min, p);
            sampled.max = glm::max(sampled.max, p);
        }
        // Tight: no farther from the sampled extremes than the sampling step allows.
        EXPECT_LT(glm::length(box.min - sampled.min), 1e-3);
        EXPECT_LT(glm::length(box.max - sampled.max), 1e-3);
    }
}

TEST(Bezier, FlatnessBoundsTheDistanceBetweenCurveAndChord) {
    for (const auto& b : randomPieces(4, 300)) {
        const double f = flatness(b);
        for (int i = 0; i <= 500; ++i) EXPECT_LE(distanceToSegment(evaluate(b, i / 500.0), b.start(), b.end()), f + 1e-9);
    }
}

TEST(Bezier, ArcLengthAndDistanceMatchDenseSampling) {
    for (const auto& b : randomPieces(5, 100)) {
        double dense = 0.0;
        Vec2 prev = b.start();
        for (int i = 1; i <= 20000; ++i) {
            const Vec2 p = evaluate(b, i / 20000.0);
            dense += glm::length(p - prev);
            prev = p;
        }
        EXPECT_NEAR(arcLength(b, 1e-6), dense, 1e-3 + dense * 1e-6);
        const Vec2 q(13.0, -7.0);
        double best = 1e300;
        for (int i = 0; i <= 20000; ++i) best = std::min(best, glm::length(evaluate(b, i / 20000.0) - q));
        EXPECT_NEAR(distanceTo(b, q, 1e-6), best, 1e-3);
        EXPECT_LE(distanceTo(b, q, 1e-6), best + 1e-6);
    }
}

TEST(Bezier, AllControlsEqual) {
    const Vec2 p(5.0, 5.0);
    const auto b = cubic(p, p, p, p);
    EXPECT_EQ(tightBounds(b), (Box{p, p}));
    EXPECT_EQ(flatness(b), 0.0);
    EXPECT_EQ(arcLength(b, 1e-9), 0.0);
    EXPECT_EQ(unitTangent(b, 0.5), Vec2(0.0));
    EXPECT_DOUBLE_EQ(distanceTo(b, Vec2(8.0, 9.0), 1e-9), 5.0);
}

TEST(Bezier, ZeroLengthChordLoop) {
    // Start and end coincide but the controls pull the curve away: flatness sees them.
    const auto b = cubic({0, 0}, {10, 0}, {10, 10}, {0, 0});
    EXPECT_GT(flatness(b), 9.0);
    EXPECT_GT(arcLength(b, 1e-6), 15.0);
    EXPECT_GT(tightBounds(b).max.x, 5.0);
}

TEST(Bezier, CuspHasALimitTangent) {
    const auto b = cubic({0, 0}, {1, 1}, {0, 1}, {1, 0});
    EXPECT_LT(glm::length(derivative(b, 0.5)), 1e-12);
    const Vec2 t = unitTangent(b, 0.5);
    EXPECT_NEAR(glm::length(t), 1.0, 1e-12);
    // Just after the cusp the curve moves along the limit tangent.
    const Vec2 step = evaluate(b, 0.5 + 1e-4) - evaluate(b, 0.5);
    EXPECT_GT(glm::dot(glm::normalize(step), t), 0.99);
}

TEST(Bezier, CoincidentEndControlsGiveTheArrivingAndLeavingDirections) {
    const auto b = cubic({0, 0}, {0, 0}, {10, 10}, {20, 0});  // B'(0) = 0
    const Vec2 t0 = unitTangent(b, 0.0);
    EXPECT_GT(glm::dot(t0, glm::normalize(evaluate(b, 1e-3) - b.start())), 0.99);
    const auto c = cubic({0, 0}, {10, 10}, {20, 0}, {20, 0});  // B'(1) = 0
    const Vec2 t1 = unitTangent(c, 1.0);
    EXPECT_GT(glm::dot(t1, glm::normalize(c.end() - evaluate(c, 1.0 - 1e-3))), 0.99);
}

TEST(Bezier, CollinearControlsStayOnTheLine) {
    const auto b = cubic({0, 0}, {40, 0}, {-20, 0}, {20, 0});  // runs back and forth on the x axis
    const Box box = tightBounds(b);
    EXPECT_EQ(box.min.y, 0.0);
    EXPECT_EQ(box.max.y, 0.0);
    EXPECT_GE(box.min.x, -1e-9);
    EXPECT_LE(box.max.x, 20.0 + 1e-9);
    EXPECT_EQ(flatness(b), 20.0);
    EXPECT_GT(arcLength(b, 1e-6), 20.0);  // it backtracks
}

}  // namespace
}  // namespace lacet
