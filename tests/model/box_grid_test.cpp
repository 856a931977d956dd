// The nearest-item grid (model/box_grid.h) against brute force: for random segments of very
// different sizes and query points near, among and far from them (and non-finite), the nearest
// segment found through visitNear is the brute-force nearest.
#include "model/box_grid.h"

#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "model/bezier.h"

namespace lacet {
namespace {

TEST(BoxGrid, VisitNearFindsTheBruteForceNearestSegment) {
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 40; ++trial) {
        const double spread = trial % 2 ? 1000.0 : 5.0;
        std::vector<Vec2> a, b;
        std::vector<Box> boxes;
        const int n = 1 + int(rng() % 300);
        for (int i = 0; i < n; ++i) {
            const Vec2 p(u(rng) * spread, u(rng) * spread);
            // Mostly short segments, some as long as the whole set.
            const double length = u(rng) < 0.05 ? spread : 0.01 * spread * u(rng);
            const double angle = 6.283185307179586 * u(rng);
            const Vec2 q = p + length * Vec2(std::cos(angle), std::sin(angle));
            a.push_back(p);
            b.push_back(q);
            boxes.push_back({glm::min(p, q), glm::max(p, q)});
        }
        const BoxGrid grid(boxes);
        for (int k = 0; k < 200; ++k) {
            const double reach = k % 4 == 0 ? 100.0 : 1.2;  // among the segments, or far away
            const Vec2 q(u(rng) * spread * reach - spread * (reach - 1.0) / 2.0, u(rng) * spread * reach - spread * (reach - 1.0) / 2.0);
            double brute = std::numeric_limits<double>::infinity();
            for (int i = 0; i < n; ++i) brute = std::min(brute, distanceToSegment(q, a[std::size_t(i)], b[std::size_t(i)]));
            double best = std::numeric_limits<double>::infinity();
            grid.visitNear(q, best, [&](std::size_t i) { best = std::min(best, distanceToSegment(q, a[i], b[i])); });
            ASSERT_EQ(best, brute) << "trial " << trial << ", query " << k;
        }
        // A query beyond any int's range is clamped, not overflowed.
        double best = std::numeric_limits<double>::infinity();
        grid.visitNear(Vec2(1e300, -1e300), best, [&](std::size_t i) { best = std::min(best, distanceToSegment(Vec2(1e300, -1e300), a[i], b[i])); });
        EXPECT_GT(best, 1e299);
    }
}

TEST(BoxGrid, AnEmptyGridVisitsNothing) {
    const BoxGrid grid(std::span<const Box>{});
    const double best = std::numeric_limits<double>::infinity();
    bool visited = false;
    grid.visitNear(Vec2(0.0), best, [&](std::size_t) { visited = true; });
    EXPECT_FALSE(visited);
}

}  // namespace
}  // namespace lacet
