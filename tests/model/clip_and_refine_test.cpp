// Hard cases of CLIPANDREFINE (§4.2): each checks the result, not only that nothing crashes.
#include "model/clip_and_refine.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "tests/model/test_geometry.h"

namespace lacet {
namespace {

using test::sample;

const Box kQuad{{0.0, 0.0}, {100.0, 100.0}};
const Box kRight{{100.0, 0.0}, {200.0, 100.0}};

ClippedCurve curveOf(std::vector<Vertex> v) {
    ClippedCurve c;
    for (const Vertex& x : v)
        if (x.onCurve) c.s.push_back(double(c.s.size()));
    c.vertices = std::move(v);
    c.startsAtNode = c.endsAtNode = true;
    return c;
}

std::vector<ClippedCurve> clip(const ClippedCurve& c, const Box& quad, double margin, double tol) {
    std::vector<ClippedCurve> out;
    clipAndRefineCurve(c, 0, quad, margin, tol, out);
    return out;
}

// Largest distance between the drawn chord polyline (on-curve vertices) of each kept piece and the
// exact Bezier piece, both ways, measured by dense sampling.
double refinementError(const std::vector<ClippedCurve>& pieces) {
    double err = 0.0;
    for (const auto& c : pieces)
        forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
            for (int i = 0; i <= 64; ++i) {
                err = std::max(err, distanceToSegment(evaluate(b, i / 64.0), b.start(), b.end()));
                const Vec2 onChord = b.start() + (b.end() - b.start()) * (i / 64.0);
                err = std::max(err, distanceTo(b, onChord, 1e-7));
            }
        });
    return err;
}

TEST(ClipAndRefine, CurveLyingExactlyOnAQuadBorderIsKeptOnBothSides) {
    const auto c = curveOf({{{100.0, -50.0}}, {{100.0, 150.0}}});
    const auto left = clip(c, kQuad, 0.0, 0.1);
    const auto right = clip(c, kRight, 0.0, 0.1);
    ASSERT_EQ(left.size(), 1u);
    ASSERT_EQ(right.size(), 1u);
    // The kept pieces are on the border and cover the quad's side.
    for (const auto* run : {&left[0], &right[0]}) {
        for (const auto& v : run->vertices) EXPECT_EQ(v.p.x, 100.0);
        EXPECT_LE(run->vertices.front().p.y, 0.0);
        EXPECT_GE(run->vertices.back().p.y, 100.0);
        EXPECT_EQ(run->startsAtNode, run->vertices.front().p == Vec2(100.0, -50.0));
    }
}

TEST(ClipAndRefine, CurveThroughAQuadCornerReachesEveryQuadAtTheCorner) {
    const auto c = curveOf({{{-300.0, -300.0}}, {{300.0, 300.0}}});
    for (const Box& q : {kQuad, Box{{100, 100}, {200, 200}}}) {
        const auto pieces = clip(c, q, 0.0, 0.1);
        ASSERT_EQ(pieces.size(), 1u);
        // The diagonal inside q is covered by the kept run.
        EXPECT_LE(pieces[0].vertices.front().p.x, q.min.x);
        EXPECT_GE(pieces[0].vertices.back().p.x, q.max.x);
    }
    // The two quads that only touch the corner keep (conservatively) the piece through it.
    for (const Box& q : {kRight, Box{{0, 100}, {100, 200}}}) {
        const auto pieces = clip(c, q, 0.0, 0.1);
        ASSERT_EQ(pieces.size(), 1u);
        bool throughCorner = false;
        forEachPiece(pieces[0].vertices, [&](const BezierPiece& b, std::size_t) {
            throughCorner |= distanceToSegment(Vec2(100.0, 100.0), b.start(), b.end()) == 0.0;
        });
        EXPECT_TRUE(throughCorner);
    }
}

TEST(ClipAndRefine, CurveTangentToABorderTouchesTheNeighbour) {
    // A parabola whose apex touches y = 100 from below at x = 50.
    const auto c = curveOf({{{0.0, 50.0}}, {{50.0, 150.0}, false}, {{100.0, 50.0}}});
    const Box above{{0.0, 100.0}, {100.0, 200.0}};
    const auto pieces = clip(c, above, 0.0, 0.01);
    ASSERT_FALSE(pieces.empty());
    double top = -1e300;
    for (const auto& run : pieces)
        for (const Vec2& p : sample(run.vertices)) top = std::max(top, p.y);
    EXPECT_NEAR(top, 100.0, 1e-9);  // only the touching apex is kept
    // A hair lower and it is dropped.
    const auto lower = curveOf({{{0.0, 50.0}}, {{50.0, 149.9}, false}, {{100.0, 50.0}}});
    EXPECT_TRUE(clip(lower, above, 0.0, 0.01).empty());
}

TEST(ClipAndRefine, DegeneratePiecesTerminateAndKeepTheirPoint) {
    const Vec2 p(30.0, 40.0);
    const auto allEqual = curveOf({{p}, {p, false}, {p, false}, {p}});
    const auto kept = clip(allEqual, kQuad, 1.0, 1e-6);
    ASSERT_EQ(kept.size(), 1u);
    for (const auto& v : kept[0].vertices) EXPECT_EQ(v.p, p);
    EXPECT_TRUE(clip(allEqual, kRight, 1.0, 1e-6).empty());
    const auto zeroLength = curveOf({{p}, {p}});
    EXPECT_EQ(clip(zeroLength, kQuad, 0.0, 1e-6).size(), 1u);
    const auto cusp = curveOf({{{0, 0}}, {{100, 100}, false}, {{0, 100}, false}, {{100, 0}}});
    const auto pieces = clip(cusp, kQuad, 0.0, 0.05);
    ASSERT_EQ(pieces.size(), 1u);
    EXPECT_LE(refinementError(pieces), 0.05);
}

TEST(ClipAndRefine, HairpinWiderThanItsRadiusIsRefinedWithinTolerance) {
    // A U-turn of radius ~5 m on a road of footprint 30 m.
    const auto c = curveOf({{{10.0, 10.0}}, {{90.0, 10.0}, false}, {{90.0, 20.0}, false}, {{10.0, 20.0}}});
    for (double tol : {1.0, 0.1, 0.01}) {
        const auto pieces = clip(c, kQuad, 15.0, tol);
        ASSERT_EQ(pieces.size(), 1u);
        EXPECT_LE(refinementError(pieces), tol);
        EXPECT_TRUE(pieces[0].startsAtNode && pieces[0].endsAtNode);
    }
    // The bend reaches x = 70: a quad starting at x = 80 is reached by the footprint (wf/2 = 15 m)
    // only: the bend is kept there, the arms are not.
    const Box right{{80.0, 0.0}, {180.0, 100.0}};
    const auto near = clip(c, right, 15.0, 0.1);
    ASSERT_EQ(near.size(), 1u);
    for (const auto& v : near[0].vertices) EXPECT_GT(v.p.x, 40.0);
    EXPECT_FALSE(near[0].startsAtNode || near[0].endsAtNode);
    EXPECT_TRUE(clip(c, right, 5.0, 0.1).empty());  // a narrow road does not reach it
}

TEST(ClipAndRefine, RefinementErrorIsWithinToleranceAgainstDenseSampling) {
    std::mt19937_64 rng(7);
    for (int n = 0; n < 100; ++n) {
        std::vector<Vertex> v{{{double(rng() % 300) - 100.0, double(rng() % 300) - 100.0}}};
        for (int k = 0; k < 3; ++k) {
            const int controls = int(rng() % 3);
            for (int j = 0; j < controls; ++j) v.push_back({{double(rng() % 300) - 100.0, double(rng() % 300) - 100.0}, false});
            v.push_back({{double(rng() % 300) - 100.0, double(rng() % 300) - 100.0}});
        }
        for (double tol : {2.0, 0.25, 0.02}) EXPECT_LE(refinementError(clip(curveOf(v), kQuad, 3.0, tol)), tol);
    }
}

// The point of the ancestor at parameter s (k + t on its k-th piece).
Vec2 ancestorAt(const std::vector<Vertex>& v, double s) {
    Vec2 p = v.back().p;
    std::size_t k = 0;
    forEachPiece(v, [&](const BezierPiece& b, std::size_t) {
        if (s >= double(k) && s <= double(k + 1)) p = evaluate(b, s - double(k));
        ++k;
    });
    return p;
}

TEST(ClipAndRefine, AncestorParametersLocateEveryOnCurveVertex) {
    std::mt19937_64 rng(5);
    for (int n = 0; n < 50; ++n) {
        std::vector<Vertex> v{{{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}}};
        for (int k = 0; k < 4; ++k) {
            for (int j = int(rng() % 3); j > 0; --j) v.push_back({{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}, false});
            v.push_back({{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}});
        }
        // Two levels: clip into a quad, then into its child, as the quadtree does.
        for (const auto& run : clip(curveOf(v), kQuad, 4.0, 0.5)) {
            ASSERT_EQ(run.s.size(), std::size_t(std::count_if(run.vertices.begin(), run.vertices.end(), [](const Vertex& x) { return x.onCurve; })));
            for (const auto& child : clip(run, Box{{50, 50}, {100, 100}}, 4.0, 0.1)) {
                std::size_t i = 0;
                for (const Vertex& x : child.vertices) {
                    if (x.onCurve) {
                        EXPECT_LT(glm::length(ancestorAt(v, child.s[i++]) - x.p), 1e-9);
                    }
                }
                EXPECT_TRUE(std::is_sorted(child.s.begin(), child.s.end()));
            }
        }
    }
}

TEST(ClipAndRefine, AdjacentQuadsRefineASharedPieceIdentically) {
    // Seams: what both quads keep near their shared border is the same sub-pieces, bit for bit.
    std::mt19937_64 rng(9);
    for (int n = 0; n < 100; ++n) {
        std::vector<Vertex> v{{{double(rng() % 300) - 50.0, double(rng() % 300) - 100.0}},
                              {{double(rng() % 300) - 50.0, double(rng() % 300) - 100.0}, false},
                              {{double(rng() % 300) - 50.0, double(rng() % 300) - 100.0}, false},
                              {{double(rng() % 300) - 50.0, double(rng() % 300) - 100.0}}};
        const double margin = 3.0;
        auto piecesOf = [&](const Box& q) {
            std::vector<BezierPiece> out;
            for (const auto& run : clip(curveOf(v), q, margin, 0.2))
                forEachPiece(run.vertices, [&](const BezierPiece& b, std::size_t) { out.push_back(b); });
            return out;
        };
        const auto a = piecesOf(kQuad), b = piecesOf(kRight);
        const Box shared = kQuad.dilated(margin);
        for (const BezierPiece& p : a) {
            if (!tightBounds(p).intersects(kRight.dilated(margin)) || !tightBounds(p).intersects(shared)) continue;
            const bool found = std::any_of(b.begin(), b.end(), [&](const BezierPiece& q) { return q.degree == p.degree && q.p == p.p; });
            EXPECT_TRUE(found) << "curve " << n;
        }
    }
}

TEST(ClipAndRefine, ConservativeClippingNeverLosesAPointOfTheCurveNearTheQuad) {
    std::mt19937_64 rng(11);
    for (int n = 0; n < 100; ++n) {
        std::vector<Vertex> v{{{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}},
                              {{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}, false},
                              {{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}, false},
                              {{double(rng() % 400) - 150.0, double(rng() % 400) - 150.0}}};
        const double margin = 5.0;
        const auto pieces = clip(curveOf(v), kQuad, margin, 0.5);
        for (const Vec2& p : sample(v, 400)) {
            if (!kQuad.dilated(margin).contains(p)) continue;
            double d = 1e300;
            for (const auto& run : pieces)
                forEachPiece(run.vertices, [&](const BezierPiece& b, std::size_t) { d = std::min(d, distanceTo(b, p, 1e-6)); });
            EXPECT_LT(d, 0.05);
        }
    }
}

// ---- areas ----------------------------------------------------------------------------------

ClippedLoop ring(std::vector<Vec2> pts, bool hole) {
    ClippedLoop l;
    l.hole = hole;
    for (Vec2 p : pts) l.vertices.push_back({p});
    l.vertices.push_back({pts.front()});
    return l;
}

// Inside a quad (away from borders by more than tol), the clipped area must classify every point
// exactly as the original area.
void expectSameInside(const ClippedArea& original, const std::vector<ClippedArea>& clipped, const Box& quad, double tol) {
    std::vector<std::vector<Vec2>> rings;
    for (const auto& l : original.loops) rings.push_back(sample(l.vertices, 64));
    int checked = 0;
    for (int i = 0; i <= 60; ++i)
        for (int j = 0; j <= 60; ++j) {
            const Vec2 q = quad.min + quad.size() * Vec2(i / 60.0, j / 60.0);
            if (test::distanceToRings(rings, q) < 2.0 * tol) continue;
            EXPECT_EQ(test::insideClipped(clipped, q), test::insidePolylines(rings, q)) << "at " << q.x << "," << q.y;
            ++checked;
        }
    EXPECT_GT(checked, 1000);
}

TEST(ClipAndRefineArea, HolesStraddlingBordersAndAHoleTouchingTheOuterRing) {
    ClippedArea a;
    a.loops.push_back(ring({{-50, -50}, {150, -50}, {150, 150}, {-50, 150}}, false));
    a.loops.push_back(ring({{80, 20}, {130, 20}, {130, 60}, {80, 60}}, true));       // straddles x = 100
    a.loops.push_back(ring({{20, 80}, {60, 80}, {60, 150}, {20, 150}}, true));       // touches the outer ring at y = 150
    a.loops.push_back(ring({{20, 20}, {40, 20}, {30, 40}}, true));                   // inside the quad
    for (const Box& q : {kQuad, kRight, Box{{0, 100}, {100, 200}}, Box{{-100, -100}, {0, 0}}}) {
        std::vector<ClippedArea> out;
        clipAndRefineArea(a, 0, q, 2.0, 0.1, out);
        ASSERT_EQ(out.size(), 1u);
        EXPECT_FALSE(out[0].coversQuad);
        for (const auto& l : out[0].loops) EXPECT_EQ(l.vertices.front().p, l.vertices.back().p) << "loops stay closed";
        expectSameInside(a, out, q, 0.1);
    }
}

TEST(ClipAndRefineArea, AreaCoveringTheWholeQuadIsKnownToCoverIt) {
    ClippedArea a;
    a.loops.push_back(ring({{-500, -500}, {600, -400}, {700, 700}, {-400, 600}}, false));
    std::vector<ClippedArea> out;
    clipAndRefineArea(a, 0, kQuad, 5.0, 0.1, out);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_TRUE(out[0].coversQuad);
    expectSameInside(a, out, kQuad, 0.1);
    // Its children know it too: the closing border of the parent is not a real border.
    std::vector<ClippedArea> child;
    clipAndRefineArea(out[0], 0, Box{{50, 50}, {100, 100}}, 5.0, 0.05, child);
    ASSERT_EQ(child.size(), 1u);
    EXPECT_TRUE(child[0].coversQuad);
}

TEST(ClipAndRefineArea, QuadInsideAHoleOrOutsideHasNoArea) {
    ClippedArea a;
    a.loops.push_back(ring({{-500, -500}, {600, -500}, {600, 600}, {-500, 600}}, false));
    a.loops.push_back(ring({{-200, -200}, {300, -200}, {300, 300}, {-200, 300}}, true));
    std::vector<ClippedArea> out;
    clipAndRefineArea(a, 0, kQuad, 5.0, 0.1, out);
    EXPECT_TRUE(out.empty());
    ClippedArea far;
    far.loops.push_back(ring({{1000, 1000}, {1100, 1000}, {1100, 1100}}, false));
    clipAndRefineArea(far, 0, kQuad, 5.0, 0.1, out);
    EXPECT_TRUE(out.empty());
}

TEST(ClipAndRefineArea, WindingAroundTheQuadIsKept) {
    // A C-shaped area wrapping around the quad on three sides: its dropped runs turn around it.
    ClippedArea a;
    a.loops.push_back(ring({{-100, -100}, {300, -100}, {300, -20}, {-20, -20}, {-20, 120}, {300, 120}, {300, 200}, {-100, 200}}, false));
    for (const Box& q : {kQuad, Box{{-60, -60}, {40, 40}}, Box{{-60, 60}, {40, 160}}}) {
        std::vector<ClippedArea> out;
        clipAndRefineArea(a, 0, q, 1.0, 0.1, out);
        expectSameInside(a, out, q, 0.1);
    }
}

TEST(ClipAndRefineArea, HugeCoordinatesGiveTheSameShapeAsNearTheOrigin) {
    const Vec2 offset(1.0e7, 1.0e7);  // 10,000 km
    auto build = [](Vec2 o) {
        ClippedArea a;
        ClippedLoop l;
        l.vertices = {{o + Vec2(-30, -30)}, {o + Vec2(50, -80), false}, {o + Vec2(130, -30)}, {o + Vec2(130, 130)},
                      {o + Vec2(50, 60), false}, {o + Vec2(-30, 130)}, {o + Vec2(-30, -30)}};
        a.loops.push_back(l);
        return a;
    };
    const ClippedArea near = build(Vec2(0.0)), far = build(offset);
    std::vector<ClippedArea> outNear, outFar;
    const Box quadFar{kQuad.min + offset, kQuad.max + offset};
    clipAndRefineArea(near, 0, kQuad, 2.0, 0.01, outNear);
    clipAndRefineArea(far, 0, quadFar, 2.0, 0.01, outFar);
    ASSERT_EQ(outNear.size(), 1u);
    ASSERT_EQ(outFar.size(), 1u);
    expectSameInside(far, outFar, quadFar, 0.01);
    ASSERT_EQ(outNear[0].loops.size(), outFar[0].loops.size());
    const auto& vn = outNear[0].loops[0].vertices;
    const auto& vf = outFar[0].loops[0].vertices;
    ASSERT_EQ(vn.size(), vf.size());
    for (std::size_t i = 0; i < vn.size(); ++i) EXPECT_LT(glm::length((vf[i].p - offset) - vn[i].p), 1e-6);
}

TEST(ClipAndRefineArea, SharedBorderIsRefinedIdenticallyByBothAreas) {
    // Two fields share a curved border, walked in opposite directions.
    const std::vector<Vertex> border{{{50, -20}}, {{80, 30}, false}, {{20, 70}, false}, {{50, 120}}};
    auto field = [&](bool left) {
        ClippedArea a;
        ClippedLoop l;
        l.vertices = border;
        if (left) {
            l.vertices.push_back({{-40, 120}});
            l.vertices.push_back({{-40, -20}});
        } else {
            std::reverse(l.vertices.begin(), l.vertices.end());
            l.vertices.push_back({{140, -20}});
            l.vertices.push_back({{140, 120}});
        }
        l.vertices.push_back(l.vertices.front());
        a.loops.push_back(l);
        return a;
    };
    std::vector<ClippedArea> left, right;
    clipAndRefineArea(field(true), 0, kQuad, 2.0, 0.05, left);
    clipAndRefineArea(field(false), 0, kQuad, 2.0, 0.05, right);
    ASSERT_EQ(left.size(), 1u);
    ASSERT_EQ(right.size(), 1u);
    // Every on-curve vertex of the left field's border part appears in the right field's loop.
    std::vector<Vec2> rightPts;
    for (const auto& v : right[0].loops[0].vertices) rightPts.push_back(v.p);
    int shared = 0;
    for (const auto& v : left[0].loops[0].vertices)
        if (v.p.x > 0.0 && v.p.x < 100.0 && v.p.y > 0.0 && v.p.y < 100.0) {
            EXPECT_NE(std::find(rightPts.begin(), rightPts.end(), v.p), rightPts.end());
            ++shared;
        }
    EXPECT_GT(shared, 4);
}

}  // namespace
}  // namespace lacet
