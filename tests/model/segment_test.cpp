// The nearest point on a segment (model/segment.h): its documented rule (clamping at the ends,
// the degenerate segment), and its distance against a long-double reference that measures the
// other way (the least of the two end distances and, where the foot of the perpendicular falls
// inside, the perpendicular distance), for random segments near and far from the origin.
#include "model/segment.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace lacet {
namespace {

// Distance from p to a-b in long double, by cases rather than by the clamped parameter.
long double referenceDistance(Vec2 p, Vec2 a, Vec2 b) {
    const long double px = p.x, py = p.y, ax = a.x, ay = a.y, bx = b.x, by = b.y;
    const long double dx = bx - ax, dy = by - ay;
    long double best = std::min(std::hypot(px - ax, py - ay), std::hypot(px - bx, py - by));
    const long double len = std::hypot(dx, dy);
    if (len > 0.0L) {
        const long double along = ((px - ax) * dx + (py - ay) * dy) / len;
        if (along > 0.0L && along < len) best = std::min(best, std::abs((px - ax) * dy - (py - ay) * dx) / len);
    }
    return best;
}

TEST(Segment, EndsAndClamping) {
    const Vec2 a(1.0, 2.0), b(5.0, 2.0);
    SegmentNearest n = nearestOnSegment(a, a, b);
    EXPECT_EQ(n.t, 0.0);
    EXPECT_EQ(n.point, a);
    EXPECT_EQ(n.distance2, 0.0);
    n = nearestOnSegment(b, a, b);
    EXPECT_EQ(n.t, 1.0);
    EXPECT_EQ(n.distance2, 0.0);
    n = nearestOnSegment(Vec2(-3.0, 5.0), a, b);  // beyond a
    EXPECT_EQ(n.t, 0.0);
    EXPECT_EQ(n.point, a);
    EXPECT_EQ(n.distance2, 16.0 + 9.0);
    n = nearestOnSegment(Vec2(9.0, -1.0), a, b);  // beyond b
    EXPECT_EQ(n.t, 1.0);
    EXPECT_EQ(n.point, b);
    EXPECT_EQ(n.distance2, 16.0 + 9.0);
    n = nearestOnSegment(Vec2(2.0, 7.0), a, b);  // the perpendicular foot inside
    EXPECT_EQ(n.t, 0.25);
    EXPECT_EQ(n.point, Vec2(2.0, 2.0));
    EXPECT_EQ(distanceToSegment(Vec2(2.0, 7.0), a, b), 5.0);
    EXPECT_EQ(nearestParameter(Vec2(2.0, 7.0), a, b), 0.25);
}

TEST(Segment, DegenerateSegmentIsItsPoint) {
    const Vec2 a(3.0, -4.0);
    const SegmentNearest n = nearestOnSegment(Vec2(0.0, 0.0), a, a);
    EXPECT_EQ(n.t, 0.0);
    EXPECT_EQ(n.point, a);
    EXPECT_EQ(n.distance2, 25.0);
    // So short that its squared length underflows: still its start point.
    const Vec2 start(0.0, -4.0), tiny(1e-170, -4.0);
    EXPECT_EQ(nearestOnSegment(Vec2(3.0, 0.0), start, tiny).t, 0.0);
    EXPECT_EQ(distanceToSegment(Vec2(3.0, 0.0), start, tiny), 5.0);
    // A non-finite segment gives t = 0 and no distance (not a wrong finite one).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(nearestParameter(Vec2(0.0), a, Vec2(nan, 0.0)), 0.0);
    EXPECT_TRUE(std::isnan(distanceToSegment(Vec2(0.0), a, Vec2(nan, 0.0))));
}

TEST(Segment, AgreesWithALongDoubleReference) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    constexpr double eps = std::numeric_limits<double>::epsilon();
    // Origins from 0 to 4000 km (the scene's range) and 1e100 (far beyond it; squares still fit).
    const double offsets[] = {0.0, 1e3, 4e6, 1e100};
    const double scales[] = {1e-3, 1.0, 1e4};
    for (int trial = 0; trial < 20000; ++trial) {
        const double offset = offsets[trial % 4], scale = scales[(trial / 4) % 3];
        const double spread = offset == 1e100 ? 1e98 : scale;
        const Vec2 o(offset * u(rng), offset * u(rng));
        const Vec2 a = o + spread * Vec2(u(rng), u(rng));
        Vec2 b = o + spread * Vec2(u(rng), u(rng));
        if (trial % 10 == 0) b = a;  // degenerate
        Vec2 p = o + 2.0 * spread * Vec2(u(rng), u(rng));
        if (trial % 10 == 1) p = a;
        if (trial % 10 == 2) p = b;
        if (trial % 10 == 3) p = a + (b - a) * (0.5 + 0.5 * u(rng));  // on the segment, up to rounding
        const SegmentNearest n = nearestOnSegment(p, a, b);
        ASSERT_GE(n.t, 0.0);
        ASSERT_LE(n.t, 1.0);
        ASSERT_EQ(n.point, a + (b - a) * n.t);
        ASSERT_EQ(std::sqrt(n.distance2), distanceToSegment(p, a, b));
        // The inputs' differences are exact or rounded once; the result is a few roundings in
        // the magnitude of the coordinates away from the exact distance.
        const double magnitude = std::max({std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y), std::abs(p.x), std::abs(p.y)});
        const long double reference = referenceDistance(p, a, b);
        ASSERT_NEAR(double(reference), distanceToSegment(p, a, b), 16.0 * eps * magnitude)
            << "trial " << trial << " p " << p.x << " " << p.y << " a " << a.x << " " << a.y << " b " << b.x << " " << b.y;
        if (trial % 10 == 1) {
            ASSERT_EQ(n.distance2, 0.0);  // p == a: exactly
        }
    }
}

TEST(Segment, DirectionDoesNotMatterBeyondRounding) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-100.0, 100.0);
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec2 a(u(rng), u(rng)), b(u(rng), u(rng)), p(u(rng), u(rng));
        ASSERT_NEAR(distanceToSegment(p, a, b), distanceToSegment(p, b, a), 1e-12);
        const SegmentNearest ab = nearestOnSegment(p, a, b), ba = nearestOnSegment(p, b, a);
        ASSERT_NEAR(ab.t, 1.0 - ba.t, 1e-9);
    }
}

}  // namespace
}  // namespace lacet
