// The 4-wide float twin of the segment primitive (raster/segment4.h) against the scalar double
// one (model/segment.h), on random segments and pixel rows in block-local frames near the origin
// and thousands of kilometres from it, with degenerate segments, points on the ends and on the
// segment, and points far along it.
#include "raster/segment4.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "model/segment.h"

namespace lacet {
namespace {

TEST(Segment4, AgreesWithTheScalarPrimitive) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    constexpr double floatEps = 0x1p-24;
    const double origins[] = {0.0, 5e3, 4e6};
    const double scales[] = {0.01, 1.0, 300.0};
    double worst = 0.0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double scale = scales[trial % 3];
        // The frame's origin: a pixel centre of some block, anywhere in the scene.
        const Vec2 origin = origins[(trial / 3) % 3] * Vec2(u(rng), u(rng));
        const Vec2 a = origin + scale * Vec2(u(rng), u(rng));
        Vec2 b = a + scale * Vec2(u(rng), u(rng));
        if (trial % 7 == 0) b = a;                           // degenerate
        if (trial % 7 == 1) b = a + Vec2(scale * u(rng), 0.0);  // axis-aligned
        const Float4 qx = {float(scale * u(rng)), float(scale * u(rng)), float(scale * u(rng)), float(scale * u(rng))};
        const float qy = float(scale * u(rng));
        const LocalSegment l = localSegment(a, b, origin);
        Float4 local = qx;
        if (trial % 5 == 0) local = Float4{l.x0, l.x0 + l.dx, l.x0 + 0.5f * l.dx, l.x0 + 3.0f * l.dx};
        const float y = trial % 5 == 0 ? l.y0 : qy;
        const Float4 d2 = distanceSquared4(l, local, y);
        for (int lane = 0; lane < 4; ++lane) {
            const Vec2 p = origin + Vec2(double(local[lane]), double(y));
            const double scalar = distanceToSegment(p, a, b);
            // The local coordinates are rounded to float once: the error scales with them.
            const double bound = 16.0 * floatEps * (glm::length(a - origin) + glm::length(p - a) + glm::length(b - a)) + 1e-30;
            const double error = std::abs(std::sqrt(double(d2[lane])) - scalar);
            worst = std::max(worst, error / bound);
            ASSERT_LE(error, bound) << "trial " << trial << " lane " << lane << ": " << std::sqrt(double(d2[lane])) << " vs " << scalar;
        }
        // The start point itself, in the local frame: exactly 0.
        if (trial % 5 == 0) {
            ASSERT_EQ(d2[0], 0.0f) << "trial " << trial;
        }
        if (trial % 7 == 0) {  // degenerate: the distance to a, from the same float offsets
            const Float4 rx = local - l.x0;
            const float ry = y - l.y0;
            for (int lane = 0; lane < 4; ++lane) {
                ASSERT_EQ(d2[lane], rx[lane] * rx[lane] + ry * ry);
            }
        }
    }
    // The bound is not loose by orders of magnitude (a wrong clamp or sign would be far off).
    EXPECT_GT(worst, 1e-3);
}

TEST(Segment4, LanesAreIndependent) {
    const LocalSegment l = localSegment({10.0, 0.0}, {20.0, 0.0}, {0.0, 0.0});
    const Float4 d2 = distanceSquared4(l, Float4{0.0f, 15.0f, 30.0f, 10.0f}, 3.0f);
    EXPECT_EQ(d2[0], 100.0f + 9.0f);
    EXPECT_EQ(d2[1], 9.0f);
    EXPECT_EQ(d2[2], 100.0f + 9.0f);
    EXPECT_EQ(d2[3], 9.0f);
}

}  // namespace
}  // namespace lacet
