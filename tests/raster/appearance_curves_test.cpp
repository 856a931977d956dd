// The distance field of roads and rivers (distanceFieldReference, raster/appearance_curves.h),
// block-pruned, against every segment measured at every pixel: for random polylines (short and long segments,
// degenerate and repeated ones, capped ends, some far outside the tile) and reaches, each pixel's
// distance, signed distance, u, cap flag and touched mark equal those of the exhaustive search,
// which takes, like the field, the first segment among equally near ones; the producer's 4-wide
// float field (distanceField) against that reference within float rounding. Yield lines (drawMarkings).
#include "raster/appearance_curves.h"

#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "model/segment.h"
#include "tests/raster/appearance_tile_fixture.h"

namespace lacet::appearance {
namespace {

// A random trial: a tile (3 m or 400 m wide, some near huge coordinates) and polylines over and
// around it (short and long segments, degenerate and repeated ones, capped ends).
struct FieldTrial {
    AppearanceTile tile;
    std::vector<Segment> segments;
    double reach = 0.0;
    double size = 0.0;
};

FieldTrial randomFieldTrial(std::mt19937_64& rng, int trial) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    FieldTrial f;
    f.size = trial % 2 ? 400.0 : 3.0;
    const double size = f.size;
    const Vec2 origin = trial % 3 == 0 ? Vec2(3e6, -2e6) : Vec2(0.0);
    f.tile = test::bareTile(origin, size, 24 + int(rng() % 16), 2, 1 + int(rng() % 2));
    std::vector<Segment>& segments = f.segments;
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
    f.reach = size * 0.1 * u(rng);
    return f;
}

#ifdef LACET_SANITIZED
constexpr int kFieldTrials = 8;
#else
constexpr int kFieldTrials = 40;
#endif

TEST(DistanceFieldReference, EqualsTheExhaustiveSearch) {
    std::mt19937_64 rng(67);
    std::size_t touched = 0, pixels = 0;
    for (int trial = 0; trial < kFieldTrials; ++trial) {
        const FieldTrial f = randomFieldTrial(rng, trial);
        const std::vector<Segment>& segments = f.segments;
        Scratch s;
        Canvas canvas(f.tile, s);
        distanceFieldReference(canvas, segments, f.reach);

        const double within = f.reach + canvas.pixelSize();
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
        ASSERT_EQ(s.touched.size(), std::size_t(std::count_if(s.flags.begin(), s.flags.end(), [](std::uint8_t flag) { return flag & kTouched; })));
        canvas.clearTouched();
    }
    EXPECT_GT(touched, pixels / 50);  // the field covered a fair part of the tiles
}

// The producer's 4-wide float field against the reference on the same trials: the same pixels
// and the same values within `eps` (1e-5 of the tile's size, 1/800 of a pixel or less), except
// where the float rounding may change the outcome: a distance within eps of the reach; a second
// segment within 2 eps of the nearest (it may take that one: the sign of v, the cap flag, and u
// unless both are nearest at a vertex they share); a pixel within eps of a segment's end along it
// (the cap flag).
TEST(DistanceField, AgreesWithTheReferenceWithinFloatRounding) {
    std::mt19937_64 rng(67);
    std::size_t touched = 0, unambiguous = 0;
    float worst = 0.0f;
    for (int trial = 0; trial < kFieldTrials; ++trial) {
        const FieldTrial f = randomFieldTrial(rng, trial);
        Scratch ref, fast;
        Canvas a(f.tile, ref), b(f.tile, fast);
        distanceFieldReference(a, f.segments, f.reach);
        distanceField(b, f.segments, f.reach);
        const double eps = 1e-5 * f.size, within = f.reach + a.pixelSize();
        ASSERT_LT(eps, a.pixelSize() / 500.0);
        const int side = a.side();
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                const std::size_t k = std::size_t(y) * std::size_t(side) + std::size_t(x);
                const std::string where = "trial " + std::to_string(trial) + " pixel " + std::to_string(x) + " " + std::to_string(y);
                const bool inRef = ref.flags[k] & kTouched, inFast = fast.flags[k] & kTouched;
                if (inRef != inFast) {
                    const float d = inRef ? ref.dist[k] : fast.dist[k];
                    ASSERT_NEAR(double(d), within, eps) << where;
                    continue;
                }
                if (!inRef) continue;
                ++touched;
                worst = std::max(worst, std::abs(fast.dist[k] - ref.dist[k]));
                ASSERT_NEAR(fast.dist[k], ref.dist[k], eps) << where;
                // The reference's nearest segment; whether another one is within 2 eps of it, and
                // whether all those are nearest at the same place (a vertex they share: the same u).
                const Vec2 q = a.world(x, y);
                double best = kInf;
                const Segment* nearest = nullptr;
                for (const Segment& sg : f.segments) {
                    const double d = distanceToSegment(q, sg.p0, sg.p1);
                    if (d < best) best = d, nearest = &sg;
                }
                const Vec2 place = nearestOnSegment(q, nearest->p0, nearest->p1).point;
                bool tie = false, samePlace = true;
                for (const Segment& sg : f.segments) {
                    if (&sg == nearest || distanceToSegment(q, sg.p0, sg.p1) > best + 2.0 * eps) continue;
                    if (sg.p0 == nearest->p0 && sg.p1 == nearest->p1) continue;  // a repetition
                    tie = true;
                    samePlace = samePlace && glm::length(nearestOnSegment(q, sg.p0, sg.p1).point - place) <= eps;
                }
                ASSERT_NEAR(std::abs(fast.v[k]), std::abs(ref.v[k]), eps) << where;
                if (tie && !samePlace) continue;
                ++unambiguous;
                ASSERT_NEAR(fast.u[k], ref.u[k], eps + 1e-6 * std::abs(double(ref.u[k]))) << where;
                if (tie) continue;
                if (std::abs(ref.v[k]) > eps) {
                    ASSERT_EQ(fast.v[k] > 0.0f, ref.v[k] > 0.0f) << where;
                }
                const double length = glm::length(nearest->p1 - nearest->p0);
                const double t = nearestParameter(q, nearest->p0, nearest->p1);
                if (t * length > eps && (1.0 - t) * length > eps) {
                    ASSERT_EQ(fast.flags[k] & kCap, ref.flags[k] & kCap) << where;
                }
            }
        ASSERT_EQ(fast.touched.size(), std::size_t(std::count_if(fast.flags.begin(), fast.flags.end(), [](std::uint8_t flag) { return flag & kTouched; })));
    }
    EXPECT_GT(unambiguous, touched * 9 / 10);  // the bounds were checked almost everywhere
    RecordProperty("largest_distance_difference_m_of_400m_tile", std::to_string(worst));
}

// A road entering a roundabout's ring at its start (and one at its end): the yield line is drawn
// only across the entering lane, just beyond the ring's edge (the end's radius), in dashes.
TEST(Markings, YieldLinesAreDashedAcrossTheEnteringLaneOutsideTheRing) {
    const AppearanceTile t = test::bareTile({0.0, 40.0}, 20.0, 200, 2, 1);  // 0.1 m pixels
    Curve road;
    road.w = 8.0f;  // lanes of 0.5 (4 - 0.3) = 1.85 m on either side of the centre line
    road.wf = 10.0f;
    road.cls = 1;
    const std::vector<Segment> segments = {{{0.0, 50.0}, {20.0, 50.0}, 0.0, 20.0}};
    const YieldLineGeometry y;
    for (const bool atStart : {true, false}) {
        SCOPED_TRACE(atStart);
        RoadEnds ends;
        ends.length = 20.0;
        (atStart ? ends.startRadius : ends.endRadius) = 4.0;  // the ring's half width
        Scratch plain, yielding;
        Canvas a(t, plain), b(t, yielding);
        drawMarkings(a, segments, road, ends);
        (atStart ? ends.startYield : ends.endYield) = true;
        drawMarkings(b, segments, road, ends);
        const double px = a.pixelSize();
        const double first = 4.0 + y.gap, last = first + y.width;  // from the node, along the road
        std::size_t changed = 0;
        for (int py = 0; py < a.side(); ++py)
            for (int x = 0; x < a.side(); ++x) {
                const std::size_t k = std::size_t(py) * std::size_t(a.side()) + std::size_t(x);
                if (plain.colour[k] == yielding.colour[k]) continue;
                ++changed;
                const Vec2 q = a.world(x, py);
                const double fromNode = atStart ? q.x : 20.0 - q.x;
                const double across = atStart ? q.y - 50.0 : 50.0 - q.y;  // into the entering lane
                EXPECT_GE(fromNode, first - px);
                EXPECT_LE(fromNode, last + px);
                EXPECT_GE(across, -px);
                EXPECT_LE(across, 3.7 + px);
            }
        EXPECT_GT(changed, 20u);
        // Dashes: marked at the middle of each period across the lane, bare between them.
        const double along = 0.5 * (first + last);
        auto at = [&](double across) {
            const glm::dvec2 p = a.pixel({atStart ? along : 20.0 - along, atStart ? 50.0 + across : 50.0 - across});
            const std::size_t k = std::size_t(p.y) * std::size_t(a.side()) + std::size_t(p.x);
            return plain.colour[k] != yielding.colour[k];
        };
        for (double k : {0.0, 1.0, 2.0}) {
            EXPECT_TRUE(at(k + 0.5 * y.dashPeriod + 0.01)) << k;
            EXPECT_FALSE(at(k + y.dashPeriod + 0.01)) << k;
        }
    }
}


// drawMarkings skips the texels RoadMarkings::beyondLines names: there the coverage must be exactly
// 0, for every width, pixel size and end (junction radius, stop and yield lines), or the skip
// would change the image. Random points, dense near the lines' edges, the ends' radii where the
// lines stop, and the stop and yield lines' edges (fixed seed).
TEST(Markings, TheTexelsSkippedBeyondTheLinesHaveNoCoverage) {
    std::mt19937_64 rng(41);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t skipped = 0, covered = 0;
    for (int road = 0; road < 400; ++road) {
        Curve c;
        c.w = float(0.5 + 24.0 * unit(rng) * unit(rng));  // narrower than the side inset too
        RoadEnds ends;
        ends.length = 5.0 + 400.0 * unit(rng);
        ends.startRadius = unit(rng) < 0.5 ? 0.0 : 12.0 * unit(rng);
        ends.endRadius = unit(rng) < 0.5 ? 0.0 : 12.0 * unit(rng);
        ends.startStop = unit(rng) < 0.4;
        ends.endStop = unit(rng) < 0.4;
        ends.startYield = !ends.startStop && unit(rng) < 0.4;
        ends.endYield = !ends.endStop && unit(rng) < 0.4;
        const double px = std::exp2(-6.0 + 12.0 * unit(rng));  // 1.6 cm .. 64 m a pixel
        const RoadMarkings m(c, ends, px);
        const MarkingGeometry g;
        const YieldLineGeometry y;
        for (int k = 0; k < 2000; ++k) {
            const double hw = 0.5 * double(c.w);
            // Half the points near a line's edge (side line, centre line), half anywhere on the road.
            double d = hw * unit(rng);
            if (k % 4 == 1) d = std::max(0.0, double(m.sideAxis) * px + (double(m.halfLine) + 1.5) * px * (2.0 * unit(rng) - 1.0) * 1.02);
            if (k % 4 == 2) d = std::min(hw, (double(m.halfLine) + 1.5) * px * unit(rng) * 1.02);
            const double v = unit(rng) < 0.5 ? d : -d;
            // Some near the ends' radii (the lines cut there, either side) and near the stop and
            // yield lines' edges.
            const double across = 2.0 * unit(rng) - 1.0;
            const double lineEdge = (k % 3 ? g.stopLineGap + (k % 5 ? g.stopLineWidth : 0.0) : y.gap + (k % 5 ? y.width : 0.0)) +
                                    3.0 * px * across;  // from the end's radius
            const double u = k % 8 == 3   ? ends.startRadius + 3.0 * across
                             : k % 8 == 5 ? ends.length - ends.endRadius - 3.0 * across
                             : k % 8 == 6 ? ends.startRadius + lineEdge
                             : k % 8 == 7 ? ends.length - ends.endRadius - lineEdge
                                          : ends.length * unit(rng);
            const float cov = m.coverage(d, v, u);
            // Where no stop or yield line reaches u, beyondLines depends on d alone (the producer
            // skips pixels by d, four at a time, there).
            if (!m.endLinesWithin(u, u)) {
                const bool byDistance = std::abs(d / px - double(m.sideAxis)) >= m.lineReach && d / px >= m.lineReach;
                if (byDistance) {
                    ASSERT_TRUE(m.beyondLines(d, v, u)) << "w " << c.w << " px " << px << " d " << d << " u " << u;
                }
            }
            if (m.beyondLines(d, v, u)) {
                ++skipped;
                ASSERT_EQ(cov, 0.0f) << "w " << c.w << " px " << px << " d " << d << " v " << v << " u " << u;
            } else {
                covered += cov > 0.0f;
            }
        }
    }
    EXPECT_GT(skipped, 50000u);  // the skip is taken...
    EXPECT_GT(covered, 50000u);  // ...and the lines are drawn
}


// The producer finds a road's markings as it draws its surface, from the markings' segments (u,
// ring caps), instead of measuring the field again: the pixels are those of the plain surface
// (segments of the same pieces, u 0 and no ring caps) under the reference's markings
// (drawMarkings measuring its own field), bit for bit. Random polylines (fixed seed).
TEST(Markings, FoundWithTheSurfaceAreTheReferencesBitForBit) {
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t drawn = 0;
    for (int trial = 0; trial < 60; ++trial) {
        const double size = trial % 2 ? 60.0 : 400.0 * unit(rng) + 10.0;
        const Vec2 origin = trial % 3 == 0 ? Vec2(3e6, -2e6) : Vec2(0.0);
        const AppearanceTile t = test::bareTile(origin, size, 24 + int(rng() % 16), 2, 1 + int(rng() % 2));
        std::vector<Segment> surface, markings;
        const int runs = 1 + int(rng() % 3);
        for (int r = 0; r < runs; ++r) {
            Vec2 p = origin + size * Vec2(1.4 * unit(rng) - 0.2, 1.4 * unit(rng) - 0.2);
            double along = 0.0;
            const int n = 1 + int(rng() % 20);
            const std::size_t first = markings.size();
            for (int i = 0; i < n; ++i) {
                const double length = size * 0.15 * unit(rng);
                const double angle = 6.283185307179586 * unit(rng);
                const Vec2 q = i % 7 == 3 ? p : p + length * Vec2(std::cos(angle), std::sin(angle));  // some degenerate
                const double next = along + glm::length(q - p);
                surface.push_back({p, q, 0.0, 0.0});
                markings.push_back({p, q, along, next});
                p = q;
                along = next;
            }
            surface[first].startCap = markings[first].startCap = rng() % 2 == 0;
            surface.back().endCap = markings.back().endCap = rng() % 2 == 0;
            if (rng() % 3 == 0) markings[first].startCap = true;  // a ring's end (capRingEnds)
            if (rng() % 3 == 0) markings.back().endCap = true;
        }
        Curve c;
        c.w = float(1.0 + 0.2 * size * unit(rng));
        RoadEnds ends;
        ends.length = markings.back().u1;
        ends.startRadius = unit(rng) < 0.5 ? 0.0 : 0.3 * ends.length * unit(rng);
        ends.endRadius = unit(rng) < 0.5 ? 0.0 : 0.3 * ends.length * unit(rng);
        ends.startStop = unit(rng) < 0.5;
        ends.endYield = unit(rng) < 0.5;
        Scratch kept, reference;
        Canvas a(t, kept), b(t, reference);
        std::fill(kept.colour.begin(), kept.colour.end(), Rgbm(0.0f));
        std::fill(reference.colour.begin(), reference.colour.end(), Rgbm(0.0f));
        std::vector<MarkingTexel> marks;
        const RoadMarkings m(c, ends, a.pixelSize());
        drawRoadSurface(a, markings, c, &m, &marks);
        drawMarkings(a, marks);
        drawRoadSurface(b, surface, c);
        drawMarkings(b, markings, c, ends);
        ASSERT_EQ(kept.colour.size(), reference.colour.size());
        EXPECT_EQ(std::memcmp(kept.colour.data(), reference.colour.data(), kept.colour.size() * sizeof(Rgbm)), 0) << "trial " << trial;
        drawn += marks.size();
    }
    EXPECT_GT(drawn, 1500u);  // marking pixels (about 3000)
}

}  // namespace
}  // namespace lacet::appearance
