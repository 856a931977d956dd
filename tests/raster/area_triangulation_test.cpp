// Area interiors from CGAL's constrained Delaunay triangulation: holes, holes touching their
// ring, coincident closing paths, crossing constraints, far coordinates.
#include "raster/area_triangulation.h"

#include <gtest/gtest.h>

namespace lacet {
namespace {

double areaOf(const std::vector<Triangle>& t) {
    double a = 0.0;
    for (const Triangle& tr : t) {
        const Vec2 u = tr[1] - tr[0], v = tr[2] - tr[0];
        a += 0.5 * std::abs(u.x * v.y - u.y * v.x);
    }
    return a;
}

std::vector<Vec2> square(Vec2 min, Vec2 max, bool clockwise = false) {
    std::vector<Vec2> s = {min, {max.x, min.y}, max, {min.x, max.y}};
    if (clockwise) std::reverse(s.begin(), s.end());
    return s;
}

TEST(AreaTriangulation, RingWithAHoleCoversTheRingMinusTheHole) {
    std::vector<Triangle> t;
    triangulateArea({square({0, 0}, {10, 10}), square({2, 2}, {5, 6}, true)}, {5, 5}, t);
    EXPECT_NEAR(areaOf(t), 100.0 - 12.0, 1e-9);
    for (const Triangle& tr : t) EXPECT_FALSE(insideLoops({square({2, 2}, {5, 6})}, (tr[0] + tr[1] + tr[2]) / 3.0));
}

TEST(AreaTriangulation, HolesTouchingTheirRingAlongAnEdgeOrAtAVertex) {
    std::vector<Triangle> edge, vertex;
    // The hole shares part of the ring's left edge: the coincident constraint is one edge of
    // the triangulation but two borders of the area.
    triangulateArea({square({0, 0}, {10, 10}), square({0, 2}, {4, 6})}, {0, 0}, edge);
    EXPECT_NEAR(areaOf(edge), 100.0 - 16.0, 1e-9);
    // A triangular hole touching the ring at one vertex.
    triangulateArea({square({0, 0}, {10, 10}), {{0, 0}, {4, 1}, {1, 4}}}, {0, 0}, vertex);
    EXPECT_NEAR(areaOf(vertex), 100.0 - 7.5, 1e-9);
}

TEST(AreaTriangulation, CoincidentClosingPathsAndCrossingConstraints) {
    std::vector<Triangle> same, crossing;
    // A hole equal to its ring (two closing paths along the same quad border) encloses nothing.
    triangulateArea({square({0, 0}, {10, 10}), square({0, 0}, {10, 10})}, {0, 0}, same);
    EXPECT_NEAR(areaOf(same), 0.0, 1e-9);
    // Two overlapping squares under the even-odd rule: the union minus the intersection.
    triangulateArea({square({0, 0}, {10, 10}), square({5, 5}, {15, 15})}, {0, 0}, crossing);
    EXPECT_NEAR(areaOf(crossing), 200.0 - 2.0 * 25.0, 1e-6);
}

TEST(AreaTriangulation, DegenerateLoopsAndFarCoordinates) {
    std::vector<Triangle> t;
    triangulateArea({{{0, 0}, {0, 0}, {1, 1}}, {{3, 3}}, {}}, {0, 0}, t);
    EXPECT_TRUE(t.empty());
    const Vec2 far(4.0e8, -3.0e8);  // near the largest coordinate the model accepts
    std::vector<Vec2> ring;
    for (const Vec2& p : square({0, 0}, {0.5, 0.25})) ring.push_back(far + p);
    ring.insert(ring.begin() + 1, ring.front());  // a repeated point
    triangulateArea({ring}, far + Vec2(0.25, 0.125), t);
    EXPECT_NEAR(areaOf(t), 0.125, 1e-6);
}

}  // namespace
}  // namespace lacet
