// The block-pruned candidate search (candidatesNear, raster/appearance_segments.h) against an
// exhaustive search: for random segments (short and long, degenerate, repeated, far away) and
// random boxes, at points all over each box, the nearest of the kept candidates is exactly the
// nearest of all the segments whenever that is within reach, and the returned bound is below it.
#include "raster/appearance_segments.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "model/segment.h"

namespace lacet::appearance {
namespace {

TEST(CandidatesNear, KeepTheNearestSegmentOfEveryPointOfTheBox) {
    std::mt19937_64 rng(61);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    constexpr double inf = std::numeric_limits<double>::infinity();
#ifdef LACET_SANITIZED
    const int trials = 60;
#else
    const int trials = 300;
#endif
    int checked = 0, pruned = 0;
    for (int trial = 0; trial < trials; ++trial) {
        const Vec2 origin = trial % 3 == 0 ? Vec2(4e6 * u(rng), -4e6 * u(rng)) : Vec2(0.0);
        const double spread = trial % 2 ? 100.0 : 1.0;
        std::vector<Segment> segments;
        const int n = 1 + int(rng() % 60);
        for (int i = 0; i < n; ++i) {
            const Vec2 a = origin + spread * Vec2(3.0 * u(rng) - 1.0, 3.0 * u(rng) - 1.0);
            const double length = u(rng) < 0.1 ? 2.0 * spread : 0.1 * spread * u(rng);
            const double angle = 6.283185307179586 * u(rng);
            Vec2 b = a + length * Vec2(std::cos(angle), std::sin(angle));
            if (i % 9 == 4) b = a;                                           // degenerate
            segments.push_back({a, b});
            if (i % 11 == 5) segments.push_back({b, a});                     // the same, reversed
        }
        const Vec2 lo = origin + spread * Vec2(u(rng), u(rng));
        const Box box{lo, lo + spread * 0.3 * Vec2(u(rng), u(rng))};
        const double reach = spread * (u(rng) < 0.2 ? 10.0 : u(rng));
        std::vector<const Segment*> kept;
        const double nearest = candidatesNear(segments, box, reach, kept);
        pruned += int(segments.size() - kept.size());
        for (int k = 0; k < 200; ++k) {
            // Corners, edges and the inside of the box.
            const double fx = k < 4 ? double(k % 2) : k < 40 ? double(k % 5) / 4.0 : u(rng);
            const double fy = k < 4 ? double(k / 2) : k < 40 ? double(k % 7) / 6.0 : u(rng);
            const Vec2 q = box.min + box.size() * Vec2(fx, fy);
            double brute = inf;
            for (const Segment& sg : segments) brute = std::min(brute, distanceToSegment(q, sg.p0, sg.p1));
            double best = inf;
            for (const Segment* sg : kept) best = std::min(best, distanceToSegment(q, sg->p0, sg->p1));
            if (brute > reach) {
                ASSERT_GE(best, brute);
                continue;
            }
            ++checked;
            ASSERT_EQ(best, brute) << "trial " << trial << ", point " << k;
            ASSERT_LE(nearest, brute) << "trial " << trial << ", point " << k;
        }
        if (kept.empty()) {
            ASSERT_EQ(nearest, inf);
        }
    }
    // The test measured something, and the pruning pruned.
    EXPECT_GT(checked, trials * 20);
    EXPECT_GT(pruned, trials);
}

TEST(CandidatesNear, NonFiniteSegmentsAreNobodysCandidate) {
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<Segment> segments = {{{0.0, 0.0}, {inf, 0.0}}, {{nan, 1.0}, {1.0, 1.0}}, {{2.0, 2.0}, {3.0, 2.0}}};
    std::vector<const Segment*> kept;
    const double nearest = candidatesNear(segments, {{0.0, 0.0}, {1.0, 1.0}}, 100.0, kept);
    ASSERT_EQ(kept.size(), 1u);
    EXPECT_EQ(kept[0], &segments[2]);
    EXPECT_DOUBLE_EQ(nearest, std::sqrt(2.0));
}

}  // namespace
}  // namespace lacet::appearance
