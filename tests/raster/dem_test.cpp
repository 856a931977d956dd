#include "raster/dem.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/bezier.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

// A small grid with non-square cells (10 m x 7.5 m) away from the origin, random heights.
Dem randomDem(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<float> h(8 * 6);
    for (float& v : h) v = float(rng() % 20000) * 0.01f - 50.0f;
    return Dem(Box{Vec2(100.0, -50.0), Vec2(180.0, -5.0)}, 8, 6, std::move(h));
}

// Uniformly random points of the box.
std::vector<Vec2> randomPoints(const Box& b, std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    const auto unit = [&] { return double(rng() >> 11) * 0x1.0p-53; };
    std::vector<Vec2> p(static_cast<std::size_t>(n));
    for (Vec2& q : p) q = b.min + Vec2(unit(), unit()) * b.size();
    return p;
}

// The message of the std::invalid_argument thrown by f, or "" if none was thrown.
template <class F>
std::string invalidArgumentMessage(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(Dem, SampleReproducesGridValuesAtSampleCentres) {
    const Dem dem = randomDem(1);
    EXPECT_EQ(dem.cellSize(), Vec2(10.0, 7.5));
    for (int j = 0; j < dem.height(); ++j)
        for (int i = 0; i < dem.width(); ++i)
            EXPECT_NEAR(dem.sample(dem.samplePosition(i, j)), dem.at(i, j), 1e-9) << i << ", " << j;
}

TEST(Dem, AtClampsIndices) {
    const Dem dem = randomDem(2);
    EXPECT_EQ(dem.at(-1, 0), dem.at(0, 0));
    EXPECT_EQ(dem.at(3, -7), dem.at(3, 0));
    EXPECT_EQ(dem.at(100, 100), dem.at(dem.width() - 1, dem.height() - 1));
}

// Across the lines through sample centres, where the interpolating cell changes (including
// the outermost ones, where the extrapolated border takes over), value and gradient agree
// from both sides.
TEST(Dem, InterpolationIsC1AcrossCells) {
    constexpr double kEpsilon = 1e-7;  // m on each side of the line
    const Dem dem = randomDem(3);
    const Box e = dem.extent();
    for (const Vec2 q : randomPoints(e, 4, 20))
        for (int i = 0; i < dem.width(); ++i) {
            const double x = dem.samplePosition(i, 0).x;
            const Vec2 a(x - kEpsilon, q.y), b(x + kEpsilon, q.y);
            EXPECT_NEAR(dem.sample(a), dem.sample(b), 1e-5) << "column " << i;
            EXPECT_NEAR(dem.gradient(a).x, dem.gradient(b).x, 1e-4) << "column " << i;
            EXPECT_NEAR(dem.gradient(a).y, dem.gradient(b).y, 1e-4) << "column " << i;
        }
    for (const Vec2 q : randomPoints(e, 5, 20))
        for (int j = 0; j < dem.height(); ++j) {
            const double y = dem.samplePosition(0, j).y;
            const Vec2 a(q.x, y - kEpsilon), b(q.x, y + kEpsilon);
            EXPECT_NEAR(dem.sample(a), dem.sample(b), 1e-5) << "row " << j;
            EXPECT_NEAR(dem.gradient(a).x, dem.gradient(b).x, 1e-4) << "row " << j;
            EXPECT_NEAR(dem.gradient(a).y, dem.gradient(b).y, 1e-4) << "row " << j;
        }
}

TEST(Dem, GradientMatchesFiniteDifferences) {
    constexpr double kStep = 1e-4;  // m
    const Dem dem = randomDem(6);
    for (const Vec2 p : randomPoints(dem.extent().dilated(-kStep), 7, 500)) {
        const Vec2 g = dem.gradient(p);
        const double dx = (dem.sample(p + Vec2(kStep, 0.0)) - dem.sample(p - Vec2(kStep, 0.0))) / (2.0 * kStep);
        const double dy = (dem.sample(p + Vec2(0.0, kStep)) - dem.sample(p - Vec2(0.0, kStep))) / (2.0 * kStep);
        EXPECT_NEAR(g.x, dx, 1e-5);
        EXPECT_NEAR(g.y, dy, 1e-5);
    }
}

// Catmull-Rom reproduces linear functions; the linear extrapolation of the border keeps that
// true up to the extent border.
TEST(Dem, LinearHeightFieldIsReproducedOverTheWholeExtent) {
    const Box extent{Vec2(-300.0, 40.0), Vec2(-220.0, 85.0)};
    const int w = 8, h = 6;
    std::vector<float> z(std::size_t(w * h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) z[std::size_t(j * w + i)] = float(100 + 2 * i - 3 * j);
    const Dem dem(extent, w, h, z);
    const Vec2 cell = dem.cellSize();
    const auto linear = [&](Vec2 p) {
        const Vec2 s = (p - extent.min) / cell - 0.5;
        return 100.0 + 2.0 * s.x - 3.0 * s.y;
    };
    std::vector<Vec2> points = randomPoints(extent, 8, 500);
    points.insert(points.end(), {extent.min, extent.max, Vec2(extent.min.x, extent.max.y), extent.center()});
    for (const Vec2 p : points) {
        EXPECT_NEAR(dem.sample(p), linear(p), 1e-9) << p.x << ", " << p.y;
        EXPECT_NEAR(dem.gradient(p).x, 2.0 / cell.x, 1e-12);
        EXPECT_NEAR(dem.gradient(p).y, -3.0 / cell.y, 1e-12);
    }
}

TEST(Dem, OutsideTheExtentTheBorderIsContinued) {
    const Dem dem = randomDem(9);
    const Box e = dem.extent();
    for (const Vec2 q : randomPoints(e, 10, 50)) {
        for (const Vec2 outside : {Vec2(e.min.x - 25.0, q.y), Vec2(e.max.x + 1e6, q.y)}) {
            const Vec2 border = glm::clamp(outside, e.min, e.max);
            EXPECT_EQ(dem.sample(outside), dem.sample(border));
            EXPECT_EQ(dem.gradient(outside).x, 0.0);
            EXPECT_EQ(dem.gradient(outside).y, dem.gradient(border).y);
        }
        for (const Vec2 outside : {Vec2(q.x, e.min.y - 3.0), Vec2(q.x, e.max.y + 70.0)}) {
            const Vec2 border = glm::clamp(outside, e.min, e.max);
            EXPECT_EQ(dem.sample(outside), dem.sample(border));
            EXPECT_EQ(dem.gradient(outside).x, dem.gradient(border).x);
            EXPECT_EQ(dem.gradient(outside).y, 0.0);
        }
    }
    const Vec2 far = e.max + 1e9;
    EXPECT_EQ(dem.sample(far), dem.sample(e.max));
    EXPECT_EQ(dem.sample(Vec2(-INFINITY, INFINITY)), dem.sample(Vec2(e.min.x, e.max.y)));
    EXPECT_TRUE(std::isnan(dem.sample(Vec2(NAN, 0.0))));
    EXPECT_TRUE(std::isnan(dem.gradient(Vec2(0.0, NAN)).x));
}

TEST(Dem, OneSampleWideGridIsConstantAcross) {
    const Dem dem(Box{Vec2(0.0), Vec2(10.0, 30.0)}, 1, 3, {1.0f, 4.0f, 2.0f});
    for (const Vec2 p : randomPoints(dem.extent(), 11, 50)) {
        EXPECT_NEAR(dem.sample(p), dem.sample(Vec2(5.0, p.y)), 1e-12);
        EXPECT_NEAR(dem.gradient(p).x, 0.0, 1e-12);
    }
    EXPECT_NEAR(dem.sample(Vec2(5.0, 15.0)), 4.0, 1e-12);
}

TEST(Dem, ConstructorRejectsBadInput) {
    const Box box{Vec2(0.0), Vec2(30.0, 20.0)};
    std::vector<float> h(6, 1.0f);
    h[5] = NAN;  // cell (2, 1) of a 3 x 2 grid
    std::string message = invalidArgumentMessage([&] { Dem(box, 3, 2, h); });
    EXPECT_NE(message.find("(2, 1)"), std::string::npos) << message;
    EXPECT_NE(message.find("NaN"), std::string::npos) << message;
    h[5] = 1.0f;
    h[1] = -INFINITY;
    message = invalidArgumentMessage([&] { Dem(box, 3, 2, h); });
    EXPECT_NE(message.find("(1, 0)"), std::string::npos) << message;
    h[1] = 1.0f;
    EXPECT_NE(invalidArgumentMessage([&] { Dem(box, 2, 2, h); }), "");                 // wrong count
    EXPECT_NE(invalidArgumentMessage([&] { Dem(box, 0, 2, {}); }), "");                // no sample
    EXPECT_NE(invalidArgumentMessage([&] { Dem(Box{Vec2(0.0), Vec2(30.0, 0.0)}, 3, 2, h); }), "");  // flat box
    EXPECT_EQ(invalidArgumentMessage([&] { Dem(box, 3, 2, h); }), "");
}

// --- Synthetic DEM ---------------------------------------------------------------------------

TEST(SyntheticDem, DeterministicAndSeeded) {
    const Scene scene = makeSyntheticScene({1, 5000});
    const Dem a = makeSyntheticDem(scene, {7, 2500});
    const Dem b = makeSyntheticDem(scene, {7, 2500});
    const Dem c = makeSyntheticDem(scene, {8, 2500});
    EXPECT_EQ(a.extent(), scene.extent);
    EXPECT_TRUE(a.heights() == b.heights());  // bit for bit (no NaN in a Dem)
    EXPECT_FALSE(a.heights() == c.heights());
}

TEST(SyntheticDem, ResolutionKeepsTheCellSize) {
    const Scene scene = makeSyntheticScene({1, 100});
    EXPECT_NEAR(makeSyntheticDem(scene, {}).cellSize().x, 20.0, 0.2);
    EXPECT_NEAR(makeSyntheticDem(scene, {1, 2500}).cellSize().y, 40.0, 0.8);
    EXPECT_EQ(makeSyntheticDem(scene, {1, 1}).width(), 2);  // at least 2 samples per side
    EXPECT_NE(invalidArgumentMessage([&] { makeSyntheticDem(scene, {1, 0}); }), "");
}

TEST(SyntheticDem, SceneWithoutRiversGivesTerrain) {
    const Scene scene = makeSyntheticScene({3, 30});
    ASSERT_TRUE(scene.layers[kRiversLayer].curves.empty());
    const Dem dem = makeSyntheticDem(scene, {});
    const auto [lo, hi] = std::minmax_element(dem.heights().begin(), dem.heights().end());
    EXPECT_GT(*lo, 0.0f);
    EXPECT_LT(*hi, 3000.0f);
}

// Dense samples of a curve from its start (upstream) to its end, about `step` metres apart.
std::vector<Vec2> denseSamples(const Curve& c, double step) {
    std::vector<Vec2> out{c.vertices.front().p};
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
        const int n = std::max(1, int(std::ceil(arcLength(b, 0.01) / step)));
        for (int k = 1; k <= n; ++k) out.push_back(evaluate(b, double(k) / double(n)));
    });
    return out;
}

// The rivers of synthetic scenes run downhill on their synthetic DEM, in valleys: walked
// downstream, the DEM never rises above the lowest height upstream on the same curve by more
// than kRiseTolerance (the Catmull-Rom interpolant overshoots a little where the bed's slope
// changes), and the river lies below the median of the DEM around it.
TEST(SyntheticDem, RiversRunDownhillInValleys) {
    constexpr double kRiseTolerance = 0.5;   // m
    constexpr double kStep = 5.0;            // m between samples along a river
    constexpr double kRingRadius = 300.0;    // m: surroundings, beyond the valley floor
    constexpr int kRingSamples = 16;
    constexpr double kMinBelowMedian = 0.95;  // fraction of samples
    for (const std::uint64_t seed : {1, 2, 3})
        for (const int resolution : {5000, 2500}) {  // 20 m and 40 m cells
            const Scene scene = makeSyntheticScene({seed, 5000});
            const Dem dem = makeSyntheticDem(scene, {seed, resolution});
            const Layer& rivers = scene.layers[kRiversLayer];
            ASSERT_FALSE(rivers.curves.empty());
            std::size_t samples = 0, monotone = 0, below = 0;
            double worstRise = 0.0;
            for (const Curve& c : rivers.curves) {
                double lowest = INFINITY;
                for (const Vec2 p : denseSamples(c, kStep)) {
                    const double z = dem.sample(p);
                    worstRise = std::max(worstRise, z - lowest);
                    monotone += z <= lowest + kRiseTolerance;
                    lowest = std::min(lowest, z);
                    std::array<double, kRingSamples> ring;
                    for (int k = 0; k < kRingSamples; ++k) {
                        const double a = 2.0 * std::numbers::pi * k / kRingSamples;
                        ring[std::size_t(k)] = dem.sample(p + kRingRadius * Vec2(std::cos(a), std::sin(a)));
                    }
                    std::nth_element(ring.begin(), ring.begin() + kRingSamples / 2, ring.end());
                    below += z < ring[kRingSamples / 2];
                    ++samples;
                }
            }
            const double belowFraction = double(below) / double(samples);
            std::printf("[   info   ] seed %d, %.0f m cells: %zu samples on %zu rivers, worst rise %.3f m, "
                        "%.4f within tolerance, %.4f below the median of their surroundings\n",
                        int(seed), dem.cellSize().x, samples, rivers.curves.size(), worstRise,
                        double(monotone) / double(samples), belowFraction);
            EXPECT_EQ(monotone, samples) << "seed " << seed << ", resolution " << resolution;
            EXPECT_GE(belowFraction, kMinBelowMedian) << "seed " << seed << ", resolution " << resolution;
        }
}

}  // namespace
}  // namespace lacet
