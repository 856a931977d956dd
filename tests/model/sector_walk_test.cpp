// The sector walk around a box (model/sector_walk.h) against an exact integer reference: boxes
// and points with integer coordinates (up to 2^51, where a double still holds them and the box
// centre exactly), so the reference's orientations are exact in 128-bit integers. sector() is
// checked against the angular order of the corner rays, steps() against a count of the corner
// rays the chord sweeps, and appendCorners() by walking the polyline it makes: its edges turn
// around the box by the chord's steps. Points are drawn on and next to the corner rays, where an
// inexact orientation would go wrong, as well as anywhere.
#include "model/sector_walk.h"

#include <random>

#include <gtest/gtest.h>

namespace lacet {
namespace {

__extension__ typedef __int128 I;  // exact products of coordinates up to 2^53

struct IVec {
    I x, y;
};
IVec iv(Vec2 p) { return {I(static_cast<long long>(p.x)), I(static_cast<long long>(p.y))}; }
IVec operator-(IVec a, IVec b) { return {a.x - b.x, a.y - b.y}; }
I cross(IVec a, IVec b) { return a.x * b.y - a.y * b.x; }
I dot(IVec a, IVec b) { return a.x * b.x + a.y * b.y; }
int sign(I v) { return v > 0 ? 1 : v < 0 ? -1 : 0; }

// Angular order from the positive x axis, [0, 2 pi): whether u comes strictly before v.
int half(IVec v) { return v.y < 0 || (v.y == 0 && v.x < 0) ? 1 : 0; }
bool angleLess(IVec u, IVec v) { return half(u) != half(v) ? half(u) < half(v) : cross(u, v) > 0; }
bool sameAngle(IVec u, IVec v) { return cross(u, v) == 0 && dot(u, v) > 0; }

struct Reference {
    IVec c, corner[4];
    explicit Reference(const Box& box) {
        c = iv(box.center());
        const Vec2 b[4] = {box.min, {box.max.x, box.min.y}, box.max, {box.min.x, box.max.y}};
        for (int k = 0; k < 4; ++k) corner[k] = iv(b[k]);
    }
    IVec ray(int k) const { return corner[((k % 4) + 4) % 4] - c; }
    // Sector j: the angle of p - c in [angle j, angle j+1), cyclically.
    int sector(Vec2 p) const {
        const IVec v = iv(p) - c;
        for (int j = 0; j < 4; ++j) {
            const IVec lo = ray(j), hi = ray(j + 1);
            const bool atLeastLo = !angleLess(v, lo) || sameAngle(v, lo);
            const bool belowHi = angleLess(v, hi) && !sameAngle(v, hi);
            const bool wraps = angleLess(hi, lo);
            if (wraps ? (atLeastLo || belowHi) : (atLeastLo && belowHi)) return j;
        }
        ADD_FAILURE() << "no sector";
        return -1;
    }
    // The corner rays swept going from p to q the short way round c (less than half a turn):
    // counter-clockwise, those at an angle in (p, q]; clockwise, those in (q, p], negative.
    int steps(Vec2 p, Vec2 q) const {
        const IVec vp = iv(p) - c, vq = iv(q) - c;
        const int turn = sign(cross(vp, vq));
        int count = 0;
        for (int k = 0; k < 4; ++k) {
            const IVec r = ray(k);
            if (turn > 0 && cross(vp, r) > 0 && cross(r, vq) >= 0) ++count;
            if (turn < 0 && cross(vq, r) > 0 && cross(r, vp) >= 0) --count;
        }
        return count;
    }
};

// A point outside the box whose chord with `other` stays in a half-plane that excludes the
// centre: both on the far side of a line through the centre.
bool excludesCentre(const Reference& ref, Vec2 p, Vec2 q, IVec normal) {
    return dot(iv(p) - ref.c, normal) > 0 && dot(iv(q) - ref.c, normal) > 0;
}

TEST(SectorWalk, SectorsOfTheCornersAndAxes) {
    const SectorWalk walk({{0.0, 0.0}, {4.0, 2.0}});
    for (int k = 0; k < 4; ++k) EXPECT_EQ(walk.sector(walk.corner(k)), k) << k;  // a ray belongs to its sector
    EXPECT_EQ(walk.sector({2.0, -5.0}), 0);
    EXPECT_EQ(walk.sector({9.0, 1.0}), 1);
    EXPECT_EQ(walk.sector({2.0, 7.0}), 2);
    EXPECT_EQ(walk.sector({-9.0, 1.0}), 3);
    EXPECT_EQ(walk.corner(-1), walk.corner(3));
    EXPECT_EQ(walk.corner(6), walk.corner(2));
    // Around the box: a quarter turn each way, a chord along a ray, a chord within a sector.
    EXPECT_EQ(walk.steps({2.0, -5.0}, {9.0, 1.0}), 1);
    EXPECT_EQ(walk.steps({9.0, 1.0}, {2.0, -5.0}), -1);
    EXPECT_EQ(walk.steps({6.0, 3.0}, {8.0, 4.0}), 0);  // both on ray 2
    EXPECT_EQ(walk.steps({1.0, -5.0}, {3.0, -5.0}), 0);
    // From a point on ray 2 counter-clockwise the ray is not crossed; clockwise it is.
    EXPECT_EQ(walk.steps({6.0, 3.0}, {0.0, 9.0}), 0);
    EXPECT_EQ(walk.steps({6.0, 3.0}, {9.0, 0.0}), -1);
    std::vector<Vec2> out;
    walk.appendCorners(0, 2, out);
    EXPECT_EQ(out, (std::vector<Vec2>{walk.corner(1), walk.corner(2)}));
    out.clear();
    walk.appendCorners(0, -2, out);
    EXPECT_EQ(out, (std::vector<Vec2>{walk.corner(0), walk.corner(3)}));
    out.clear();
    walk.appendCorners(3, 0, out);
    EXPECT_TRUE(out.empty());
}

TEST(SectorWalk, AgreesWithAnExactReference) {
    std::mt19937_64 rng(47);
#ifdef LACET_SANITIZED
    const int trials = 400;
#else
    const int trials = 2000;
#endif
    for (int trial = 0; trial < trials; ++trial) {
        // Boxes from a few units to 2^50 across, near the origin or up to 2^50 from it.
        const int bits = 2 + int(rng() % 49);
        const long long span = 1LL << bits;
        const long long shift = trial % 2 ? (long long)(rng() % (1ULL << 50)) - (1LL << 49) : 0;
        auto coord = [&](long long range) { return (long long)(rng() % (unsigned long long)(2 * range + 1)) - range; };
        const long long x0 = shift + coord(span), y0 = shift + coord(span);
        const long long w = 2 * (1 + (long long)(rng() % (unsigned long long)span)), h = 2 * (1 + (long long)(rng() % (unsigned long long)span));
        const Box box{{double(x0), double(y0)}, {double(x0 + w), double(y0 + h)}};
        const SectorWalk walk(box);
        const Reference ref(box);
        auto point = [&]() -> Vec2 {
            const long long cx = x0 + w / 2, cy = y0 + h / 2;
            switch (rng() % 3) {
                case 0: {  // on a corner ray, or one unit off it, beyond the corner
                    const IVec r = ref.ray(int(rng() % 4));
                    const long long k = 1 + (long long)(rng() % 3);
                    return {double(cx + (long long)(r.x) * k + (long long)(rng() % 3) - 1),
                            double(cy + (long long)(r.y) * k + (long long)(rng() % 3) - 1)};
                }
                default:  // anywhere within a few box sizes
                    return {double(cx + coord(3 * span)), double(cy + coord(3 * span))};
            }
        };
        for (int k = 0; k < 20; ++k) {
            const Vec2 p = point(), q = point();
            if (iv(p).x == ref.c.x && iv(p).y == ref.c.y) continue;
            ASSERT_EQ(walk.sector(p), ref.sector(p)) << "trial " << trial << " p " << p.x << " " << p.y;
            const IVec normal = iv(p) - ref.c;
            if (!excludesCentre(ref, p, q, normal) || box.contains(p) || box.contains(q)) continue;
            const int steps = walk.steps(p, q);
            ASSERT_EQ(steps, ref.steps(p, q)) << "trial " << trial;
            // The polyline p, corners..., q turns around the box as the chord does, edge by edge.
            std::vector<Vec2> path{p};
            walk.appendCorners(walk.sector(p), steps, path);
            path.push_back(q);
            int total = 0;
            for (std::size_t i = 0; i + 1 < path.size(); ++i) total += ref.steps(path[i], path[i + 1]);
            ASSERT_EQ(total, steps) << "trial " << trial;
        }
    }
}

}  // namespace
}  // namespace lacet
