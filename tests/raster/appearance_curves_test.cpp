// The distance field of roads and rivers (distanceField, raster/appearance_curves.h), block-pruned,
// against every segment measured at every pixel: for random polylines (short and long segments,
// degenerate and repeated ones, capped ends, some far outside the tile) and reaches, each pixel's
// distance, signed distance, u, cap flag and touched mark equal those of the exhaustive search,
// which takes, like the field, the first segment among equally near ones.
#include "raster/appearance_curves.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "model/segment.h"
#include "tests/raster/appearance_tile_fixture.h"

namespace lacet::appearance {
namespace {

TEST(DistanceField, EqualsTheExhaustiveSearch) {
    std::mt19937_64 rng(67);
    std::uniform_real_distribution<double> u(0.0, 1.0);
#ifdef LACET_SANITIZED
    const int trials = 8;
#else
    const int trials = 40;
#endif
    std::size_t touched = 0, pixels = 0;
    for (int trial = 0; trial < trials; ++trial) {
        const double size = trial % 2 ? 400.0 : 3.0;
        const Vec2 origin = trial % 3 == 0 ? Vec2(3e6, -2e6) : Vec2(0.0);
        const AppearanceTile t = test::bareTile(origin, size, 24 + int(rng() % 16), 2, 1 + int(rng() % 2));
        Scratch s;
        Canvas canvas(t, s);
        std::vector<Segment> segments;
        const int runs = 1 + int(rng() % 4);
        for (int r = 0; r < runs; ++r) {
            Vec2 p = origin + size * Vec2(1.6 * u(rng) - 0.3, 1.6 * u(rng) - 0.3);
            double along = 0.0;
            const int n = 1 + int(rng() % 25);
            const std::size_t first = segments.size();
            for (int i = 0; i < n; ++i) {
                const double length = size * (u(rng) < 0.1 ? 0.8 : 0.08 * u(rng));
                const double angle = 6.283185307179586 * u(rng);
                Vec2 q = p + length * Vec2(std::cos(angle), std::sin(angle));
                if (i % 7 == 3) q = p;  // degenerate
                const double next = along + glm::length(q - p);
                segments.push_back({p, q, along, next});
                if (i % 9 == 5) segments.push_back({p, q, along, next});  // repeated: the first must win
                p = q;
                along = next;
            }
            segments[first].startCap = rng() % 2 == 0;
            segments.back().endCap = rng() % 2 == 0;
        }
        const double reach = size * 0.1 * u(rng);
        distanceField(canvas, segments, reach);

        const double within = reach + canvas.pixelSize();
        const int side = canvas.side();
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                const std::size_t k = std::size_t(y) * std::size_t(side) + std::size_t(x);
                const Vec2 q = canvas.world(x, y);
                // Every segment, in order, with the field's arithmetic.
                float best = kInf;
                const Segment* nearest = nullptr;
                double bestT = 0.0;
                for (const Segment& sg : segments) {
                    const Vec2 seg = sg.p1 - sg.p0, r = q - sg.p0;
                    const double tt = nearestParameter(q, sg.p0, sg.p1);
                    const float d = float(glm::length(r - seg * tt));
                    if (d < best) best = d, nearest = &sg, bestT = tt;
                }
                ++pixels;
                if (!nearest || double(best) > within) {
                    ASSERT_EQ(s.dist[k], kInf) << "trial " << trial << " pixel " << x << " " << y;
                    ASSERT_FALSE(s.flags[k] & kTouched);
                    continue;
                }
                ++touched;
                ASSERT_TRUE(s.flags[k] & kTouched) << "trial " << trial << " pixel " << x << " " << y;
                ASSERT_EQ(s.dist[k], best) << "trial " << trial << " pixel " << x << " " << y;
                const Vec2 seg = nearest->p1 - nearest->p0, r = q - nearest->p0;
                const float v = float(seg.x * r.y - seg.y * r.x >= 0.0 ? double(best) : -double(best));
                ASSERT_EQ(s.v[k], v) << "trial " << trial << " pixel " << x << " " << y;
                ASSERT_EQ(s.u[k], float(nearest->u0 + (nearest->u1 - nearest->u0) * bestT)) << "trial " << trial << " pixel " << x << " " << y;
                const bool cap = (bestT == 0.0 && nearest->startCap) || (bestT == 1.0 && nearest->endCap);
                ASSERT_EQ(bool(s.flags[k] & kCap), cap) << "trial " << trial << " pixel " << x << " " << y;
            }
        ASSERT_EQ(s.touched.size(), std::size_t(std::count_if(s.flags.begin(), s.flags.end(), [](std::uint8_t f) { return f & kTouched; })));
        canvas.clearTouched();
    }
    EXPECT_GT(touched, pixels / 50);  // the field covered a fair part of the tiles
}

}  // namespace
}  // namespace lacet::appearance
