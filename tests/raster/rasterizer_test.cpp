#include "raster/rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <gtest/gtest.h>

namespace lacet {
namespace {

using Triangle = std::array<RasterVertex, 3>;

RasterVertex vertex(double x, double y) { return RasterVertex{{x, y}, {}}; }

// How many times each pixel of a width x height tile is shaded.
struct Counts {
    int width, height;
    std::vector<int> n;
    Counts(int w, int h) : width(w), height(h), n(std::size_t(w * h), 0) {}
    void add(const Triangle& t) {
        rasterizeTriangle(t[0], t[1], t[2], 0, width, height, [this](int x, int y, const float*) {
            ASSERT_TRUE(x >= 0 && x < width && y >= 0 && y < height);
            ++n[std::size_t(y * width + x)];
        });
    }
    int at(int x, int y) const { return n[std::size_t(y * width + x)]; }
    long total() const {
        long s = 0;
        for (int c : n) s += c;
        return s;
    }
};

void expectEveryPixelOnce(const Counts& c, const char* what) {
    int bad = 0;
    for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x)
            if (c.at(x, y) != 1 && bad++ < 5)
                ADD_FAILURE() << what << ": pixel " << x << "," << y << " covered " << c.at(x, y) << " times";
    EXPECT_EQ(bad, 0) << what;
}

// Vertex placements that make edges pass exactly through pixel centres.
enum class Placement { Continuous, PixelCentres, PixelCorners, Mixed };

double place(double v, Placement placement, std::mt19937_64& rng) {
    if (placement == Placement::Mixed) placement = Placement(rng() % 3);
    switch (placement) {
        case Placement::PixelCentres: return std::floor(v) + 0.5;
        case Placement::PixelCorners: return std::round(v);
        default: return v;
    }
}

// A jittered grid over [x0, x1] x [y0, y1] (border vertices stay on the border), each cell split
// along a random diagonal, each triangle given a random winding. Jitter <= a quarter cell keeps
// the cells convex, so the triangles tile the rectangle.
std::vector<Triangle> gridMesh(std::uint64_t seed, double x0, double y0, double x1, double y1, int nx, int ny,
                               Placement placement) {
    std::mt19937_64 rng(seed);
    const double sx = (x1 - x0) / nx, sy = (y1 - y0) / ny;
    std::uniform_real_distribution<double> jitter(-0.18, 0.18);
    std::vector<glm::dvec2> p;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            double x = x0 + i * sx, y = y0 + j * sy;
            if (i > 0 && i < nx) x = place(x + jitter(rng) * sx, placement, rng);
            if (j > 0 && j < ny) y = place(y + jitter(rng) * sy, placement, rng);
            p.push_back({x, y});
        }
    std::vector<Triangle> mesh;
    const auto add = [&](glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
        if (rng() % 2) std::swap(b, c);
        mesh.push_back({vertex(a.x, a.y), vertex(b.x, b.y), vertex(c.x, c.y)});
    };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const glm::dvec2 a = p[std::size_t(j * (nx + 1) + i)], b = p[std::size_t(j * (nx + 1) + i + 1)];
            const glm::dvec2 c = p[std::size_t((j + 1) * (nx + 1) + i + 1)], d = p[std::size_t((j + 1) * (nx + 1) + i)];
            if (rng() % 2) { add(a, b, c); add(a, c, d); }
            else { add(a, b, d); add(b, c, d); }
        }
    return mesh;
}

TEST(Rasterizer, FullTileQuadCoversEveryPixelOnce) {
    for (auto [w, h] : {std::pair{1, 1}, {37, 23}, {256, 256}}) {
        Counts c(w, h);
        c.add({vertex(0, 0), vertex(w, 0), vertex(w, h)});
        c.add({vertex(0, 0), vertex(w, h), vertex(0, h)});
        expectEveryPixelOnce(c, "full-tile quad");
        EXPECT_EQ(c.total(), long(w) * h);
    }
}

TEST(Rasterizer, SharedEdgeMeshesCoverEachPixelCentreOnce) {
    const Placement placements[] = {Placement::Continuous, Placement::PixelCentres, Placement::PixelCorners,
                                    Placement::Mixed};
    for (std::uint64_t seed = 1; seed <= 12; ++seed)
        for (Placement placement : placements) {
            // The mesh overhangs the 61 x 47 tile, so its border triangles are clipped by the tile.
            Counts c(61, 47);
            for (const Triangle& t : gridMesh(seed, -6.0, -5.0, 67.0, 51.0, 9, 7, placement)) c.add(t);
            expectEveryPixelOnce(c, "grid mesh");
        }
    // Vertices on the pixel-centre lattice with cells one pixel wide: every edge is horizontal,
    // vertical or diagonal through a row of pixel centres, and every vertex is a pixel centre.
    Counts c(20, 20);
    for (const Triangle& t : gridMesh(99, -1.5, -1.5, 22.5, 22.5, 24, 24, Placement::PixelCentres)) c.add(t);
    expectEveryPixelOnce(c, "pixel-centre lattice");
}

TEST(Rasterizer, FanAroundAPixelCentreCoversEachPixelOnce) {
    // Every spoke points along an integer direction from a pixel centre, so it runs through a
    // row of pixel centres; the fan's apex is itself a pixel centre.
    const glm::dvec2 centre(20.5, 13.5);
    std::vector<glm::dvec2> directions = {{1, 0}, {2, 1}, {1, 1}, {1, 3}, {0, 1}, {-1, 2}, {-1, 1}, {-3, 1}, {-1, 0},
                                          {-2, -1}, {-1, -1}, {0, -1}, {1, -2}, {1, -1}, {3, -1}};
    for (int rotate = 0; rotate < 3; ++rotate) {
        Counts c(48, 32);
        for (std::size_t i = 0; i < directions.size(); ++i) {
            const glm::dvec2 a = centre + 100.0 * directions[i];
            const glm::dvec2 b = centre + 100.0 * directions[(i + 1) % directions.size()];
            c.add({vertex(centre.x, centre.y), vertex(a.x, a.y), vertex(b.x, b.y)});
        }
        expectEveryPixelOnce(c, "fan");
        std::rotate(directions.begin(), directions.begin() + 1, directions.end());
    }
}

TEST(Rasterizer, StripCoversItsRectangleOnce) {
    std::mt19937_64 rng(5);
    std::vector<RasterVertex> strip = {vertex(-4, -2), vertex(-4, 34)};
    for (double x = -2.0; x < 44.0; x += 0.5 + double(rng() % 700) / 100.0)
        strip.push_back(vertex(x, strip.size() % 2 ? 34.0 : -2.0));
    strip.push_back(vertex(45, strip.size() % 2 ? 34.0 : -2.0));
    strip.push_back(vertex(45, strip.size() % 2 ? 34.0 : -2.0));
    std::vector<int> n(40 * 30, 0);
    rasterizeStrip(strip, 0, 40, 30, [&](int x, int y, const float*) { ++n[std::size_t(y * 40 + x)]; });
    for (int count : n) ASSERT_EQ(count, 1);

    int calls = 0;
    rasterizeStrip(std::span<const RasterVertex>(strip.data(), 2), 0, 40, 30, [&](int, int, const float*) { ++calls; });
    EXPECT_EQ(calls, 0);
}

TEST(Rasterizer, InterpolationReproducesLinearFunctions) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-20.0, 84.0), slope(-0.05, 0.05), offset(-1.0, 1.0);
    std::array<double, kMaxAttributes> c{}, gx{}, gy{};
    const auto f = [&](int k, glm::dvec2 p) { return c[k] + gx[k] * p.x + gy[k] * p.y; };
    const auto check = [&](Triangle t, int width, int height) {
        for (RasterVertex& v : t)
            for (int k = 0; k < kMaxAttributes; ++k) v.a[k] = float(f(k, v.p));
        int shaded = 0;
        rasterizeTriangle(t[0], t[1], t[2], kMaxAttributes, width, height, [&](int x, int y, const float* a) {
            ++shaded;
            for (int k = 0; k < kMaxAttributes; ++k) ASSERT_NEAR(a[k], f(k, {x + 0.5, y + 0.5}), 1e-5) << k;
        });
        return shaded;
    };
    int shaded = 0;
    for (int i = 0; i < 300; ++i) {
        for (int k = 0; k < kMaxAttributes; ++k) c[k] = offset(rng), gx[k] = slope(rng), gy[k] = slope(rng);
        Triangle t;  // on the snapping grid, so that the snapped triangle is the given one
        for (RasterVertex& v : t) v.p = glm::round(glm::dvec2(coord(rng), coord(rng)) * 256.0) / 256.0;
        shaded += check(t, 64, 64);
    }
    EXPECT_GT(shaded, 100000);
    // Through the guard-band clipping: a triangle with vertices 10^7 pixels away.
    for (int k = 0; k < kMaxAttributes; ++k) c[k] = offset(rng), gx[k] = 1e-7 * k, gy[k] = -2e-7;
    EXPECT_EQ(check({vertex(-1e7, -1e7), vertex(3e7, -1e7), vertex(-1e7, 3e7)}, 32, 32), 32 * 32);
}

TEST(Rasterizer, SameOutputOnEveryRunAndThread) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> coord(-30.0, 150.0);
    std::uniform_real_distribution<float> value(-10.0f, 10.0f);
    std::vector<Triangle> triangles(600);
    for (Triangle& t : triangles)
        for (RasterVertex& v : t) {
            v.p = {coord(rng), coord(rng)};
            for (float& a : v.a) a = value(rng);
        }
    const auto render = [&triangles] {
        std::vector<float> out;
        for (const Triangle& t : triangles)
            rasterizeTriangle(t[0], t[1], t[2], 5, 128, 128, [&out](int x, int y, const float* a) {
                out.push_back(float(x));
                out.push_back(float(y));
                out.insert(out.end(), a, a + 5);
            });
        return out;
    };
    const std::vector<float> reference = render();
    EXPECT_GT(reference.size(), 200000u);
    EXPECT_EQ(render(), reference);
    std::vector<std::vector<float>> results(4);
    std::vector<std::thread> threads;
    for (auto& r : results) threads.emplace_back([&r, &render] { r = render(); });
    for (auto& t : threads) t.join();
    for (const auto& r : results) EXPECT_EQ(r, reference);
}

TEST(Rasterizer, DegenerateTrianglesCoverNothing) {
    const std::vector<Triangle> degenerate = {
        {vertex(0, 0), vertex(10, 10), vertex(20, 20)},           // collinear
        {vertex(3.5, 3.5), vertex(3.5, 3.5), vertex(3.5, 3.5)},   // one point, a pixel centre
        {vertex(0.5, 3.5), vertex(60.5, 3.5), vertex(30.5, 3.5)}, // along a row of pixel centres
        {vertex(4.5, 0), vertex(4.5, 9), vertex(4.5, 30)},        // along a column of pixel centres
        {vertex(0.5, 0.5), vertex(40.5, 0.5 + 1e-4), vertex(20.5, 0.5)},  // collinear once snapped
        {vertex(-1e9, 2.5), vertex(1e9, 2.5), vertex(5, 2.5)},    // collinear and clipped
        {vertex(1, 1), vertex(NAN, 5), vertex(9, 1)},             // not finite
        {vertex(1, 1), vertex(INFINITY, 5), vertex(9, 1)},
    };
    for (const Triangle& t : degenerate) {
        Counts c(32, 32);
        c.add(t);
        EXPECT_EQ(c.total(), 0) << t[0].p.x << "," << t[0].p.y << " " << t[1].p.x << "," << t[1].p.y;
    }
}

TEST(Rasterizer, HugeTrianglesFillTheTile) {
    for (double r : {1e3, 1e6, 5e6, 1e9, 1e15, 1e30}) {
        Counts c(40, 30);
        c.add({vertex(-r, -r), vertex(3 * r, -r), vertex(-r, 3 * r)});
        expectEveryPixelOnce(c, "huge triangle");
    }
    // Huge quads split along a diagonal that crosses the tile: the shared edge is clipped by the
    // guard band in both triangles, and must still cover each pixel once.
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> logRadius(std::log(2e6), std::log(1e16)), unit(-1.0, 1.0);
    for (int i = 0; i < 400; ++i) {
        const glm::dvec2 c(20.0 + 20.0 * unit(rng), 15.0 + 15.0 * unit(rng));
        const double angle = std::numbers::pi * unit(rng);
        const glm::dvec2 along(std::cos(angle), std::sin(angle)), across(-along.y, along.x);
        const auto far = [&](glm::dvec2 d) {
            const glm::dvec2 p = c + std::exp(logRadius(rng)) * d;
            return vertex(p.x, p.y);
        };
        const RasterVertex q0 = far(along), q1 = far(across + 0.8 * unit(rng) * along);
        const RasterVertex q2 = far(-along), q3 = far(-across + 0.8 * unit(rng) * along);
        Counts counts(40, 30);
        counts.add({q0, q1, q2});
        counts.add({q2, q3, q0});
        expectEveryPixelOnce(counts, "huge quad");
    }
    // The largest tile with vertices at the guard band's corners: the extreme int64 edge values.
    {
        const double g = kGuardBandPixels, w = kMaxTileSize;
        Counts c(kMaxTileSize, 2);
        c.add({vertex(-g, -g), vertex(w + g, -g), vertex(w + g, 2 + g)});
        c.add({vertex(-g, -g), vertex(w + g, 2 + g), vertex(-g, 2 + g)});
        expectEveryPixelOnce(c, "guard-band quad");
    }
    // A diagonal exactly through the pixel centres (k + 0.5, k + 0.5).
    Counts c(32, 32);
    c.add({vertex(-1e9 + 0.5, -1e9 + 0.5), vertex(1e9 + 0.5, -1e9 + 0.5), vertex(1e9 + 0.5, 1e9 + 0.5)});
    c.add({vertex(-1e9 + 0.5, -1e9 + 0.5), vertex(1e9 + 0.5, 1e9 + 0.5), vertex(-1e9 + 0.5, 1e9 + 0.5)});
    expectEveryPixelOnce(c, "huge quad through pixel centres");
}

// The covered pixel centres by direct evaluation of the fill rule's definition at each pixel:
// centre strictly inside after an infinitesimal move by (e, e^2).
bool referenceCovers(const Triangle& t, int x, int y) {
    std::array<std::int64_t, 3> px, py;
    for (int i = 0; i < 3; ++i) {
        px[i] = std::int64_t(std::floor(t[i].p.x * 256 + 0.5));
        py[i] = std::int64_t(std::floor(t[i].p.y * 256 + 0.5));
    }
    const std::int64_t sx = 256 * x + 128, sy = 256 * y + 128;
    const std::int64_t area = (px[1] - px[0]) * (py[2] - py[0]) - (py[1] - py[0]) * (px[2] - px[0]);
    if (area == 0) return false;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        std::int64_t dx = px[j] - px[i], dy = py[j] - py[i];
        if (area < 0) dx = -dx, dy = -dy;
        const std::int64_t e = dx * (sy - py[i]) - dy * (sx - px[i]);
        // d/de of the edge function along (e, e^2): -dy first, then dx.
        if (e < 0 || (e == 0 && (dy > 0 || (dy == 0 && dx < 0)))) return false;
    }
    return true;
}

TEST(Rasterizer, TrianglesPartlyOutsideTheTileAreClipped) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> coord(-40.0, 80.0);
    long covered = 0;
    for (int i = 0; i < 400; ++i) {
        Triangle t;
        for (RasterVertex& v : t) v.p = {coord(rng), coord(rng)};
        // Also edges from a pixel centre, and horizontal and vertical ones through pixel centres.
        if (i % 4 != 3) t[0].p = glm::floor(t[0].p) + 0.5;
        if (i % 4 == 1) t[1].p.y = t[0].p.y;
        if (i % 4 == 2) t[1].p.x = t[0].p.x;
        Counts c(41, 37);
        c.add(t);
        for (int y = 0; y < c.height; ++y)
            for (int x = 0; x < c.width; ++x)
                ASSERT_EQ(c.at(x, y), referenceCovers(t, x, y) ? 1 : 0) << i << " " << x << "," << y;
        covered += c.total();
    }
    EXPECT_GT(covered, 50000);
}

TEST(Rasterizer, CoverageMatchesAnalyticArea) {
    std::mt19937_64 rng(19);
    std::uniform_real_distribution<double> coord(0.0, 512.0);
    for (int i = 0; i < 200; ++i) {
        Triangle t;
        for (RasterVertex& v : t) v.p = {coord(rng), coord(rng)};
        const glm::dvec2 e1 = t[1].p - t[0].p, e2 = t[2].p - t[0].p;
        const double area = 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x);
        const glm::dvec2 lo = glm::min(t[0].p, glm::min(t[1].p, t[2].p));
        const glm::dvec2 hi = glm::max(t[0].p, glm::max(t[1].p, t[2].p));
        // Each covered centre's pixel lies in the triangle dilated by half a pixel in x and y, and
        // the triangle eroded likewise lies in the covered pixels: the difference is at most the
        // box's width + height (+ a pixel for the corners), itself at most the perimeter.
        const double bound = (hi.x - lo.x) + (hi.y - lo.y) + 1.0;
        Counts c(512, 512);
        c.add(t);
        EXPECT_LE(std::abs(double(c.total()) - area), bound) << i;
    }
}

TEST(Rasterizer, RowRunBoundsMatchExactIntegerDivision) {
    // The row runs come from a double estimate corrected with exact integer tests; compare with
    // floor/ceil integer division over the whole range of edge values the rasterizer can meet.
    using raster_detail::ceilDiv, raster_detail::firstInside, raster_detail::floorDiv, raster_detail::lastInside;
    std::mt19937_64 rng(23);
    for (int i = 0; i < 300000; ++i) {
        const int valueBits = 1 + int(rng() % 59), stepBits = 1 + int(rng() % 40);
        std::int64_t c = std::int64_t(rng() >> (64 - valueBits)) * (rng() % 2 ? 1 : -1);
        const std::int64_t step = std::int64_t(rng() >> (64 - stepBits)) + 1;
        const std::int64_t width = 1 + std::int64_t(rng() % kMaxTileSize);
        if (i % 2) c = -step * (std::int64_t(rng() % 70000) - 2000) + std::int64_t(rng() % 3) - 1;  // near a pixel
        ASSERT_EQ(firstInside(c, step, width), std::clamp<std::int64_t>(ceilDiv(-c, step), 0, width))
            << c << " " << step;
        ASSERT_EQ(lastInside(c, -step, width), std::clamp<std::int64_t>(floorDiv(c, step), -1, width - 1))
            << c << " " << step;
    }
}

TEST(Rasterizer, EdgeCoverageIsABoxFilterAcrossTheEdge) {
    EXPECT_EQ(edgeCoverage(0.0f), 0.5f);
    EXPECT_EQ(edgeCoverage(-0.5f), 0.0f);
    EXPECT_EQ(edgeCoverage(0.5f), 1.0f);
    EXPECT_EQ(edgeCoverage(-3.0f), 0.0f);
    EXPECT_EQ(edgeCoverage(7.0f), 1.0f);
    for (int i = -100; i <= 100; ++i) {
        const float d = float(i) / 80.0f;
        EXPECT_FLOAT_EQ(edgeCoverage(d) + edgeCoverage(-d), 1.0f);
        // A vertical edge at distance d left of the centre, inside to its right: the covered
        // part of the pixel [-0.5, 0.5]^2, by sampling.
        int inside = 0;
        for (int s = 0; s < 1000; ++s) inside += (-0.5 + (s + 0.5) / 1000.0) >= -d ? 1 : 0;
        EXPECT_NEAR(edgeCoverage(d), inside / 1000.0, 1.1e-3) << d;
        for (float halfWidth : {0.05f, 0.3f, 0.5f, 2.0f}) {
            int band = 0;
            for (int s = 0; s < 1000; ++s) band += std::abs(d + (-0.5 + (s + 0.5) / 1000.0)) <= halfWidth ? 1 : 0;
            EXPECT_NEAR(bandCoverage(d, halfWidth), band / 1000.0, 1.1e-3) << d << " " << halfWidth;
        }
    }
}

TEST(Rasterizer, MisuseThrows) {
    const RasterVertex a = vertex(0, 0), b = vertex(4, 0), c = vertex(0, 4);
    const auto nothing = [](int, int, const float*) {};
    EXPECT_THROW(rasterizeTriangle(a, b, c, kMaxAttributes + 1, 8, 8, nothing), std::invalid_argument);
    EXPECT_THROW(rasterizeTriangle(a, b, c, -1, 8, 8, nothing), std::invalid_argument);
    EXPECT_THROW(rasterizeTriangle(a, b, c, 0, kMaxTileSize + 1, 8, nothing), std::invalid_argument);
    EXPECT_THROW(rasterizeTriangle(a, b, c, 0, 8, -1, nothing), std::invalid_argument);
    int calls = 0;
    rasterizeTriangle(a, b, c, 0, 0, 8, [&](int, int, const float*) { ++calls; });
    EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace lacet
