#include "model/quadtree.h"

#include <set>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/quadtree_compare.h"
#include "tests/model/small_scene.h"
#include "tests/model/test_geometry.h"

namespace lacet {
namespace {

using test::smallScene;

// The procedural hook under test: every road becomes two procedural curves, split at its middle.
class SplitRoadsInTwo : public ProceduralStep {
public:
    bool expand(const Scene& s, LayerId l, ElementId id, std::vector<Curve>& out) const override {
        if (s.layers[l].kind != LayerKind::Roads) return false;
        const Curve& c = s.layers[l].curves[id];
        BezierPiece first;
        std::size_t firstEnd = 0;
        forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t i) {
            if (i == 0) {
                first = b;
                firstEnd = std::size_t(b.degree);
            }
        });
        const auto [a, b] = splitHalf(first);
        Curve left = c, right = c;
        left.vertices.clear();
        right.vertices.clear();
        for (int k = 0; k <= a.degree; ++k) left.vertices.push_back({a.p[k], k == 0 || k == a.degree});
        for (int k = 0; k <= b.degree; ++k) right.vertices.push_back({b.p[k], k == 0 || k == b.degree});
        right.vertices.insert(right.vertices.end(), c.vertices.begin() + std::ptrdiff_t(firstEnd) + 1, c.vertices.end());
        left.end = kNoElement;
        right.start = kNoElement;
        out = {left, right};
        return true;
    }
};

TEST(Quadtree, PiecesReferToTheirAncestorAndCreatedFromCoversThem) {
    const Scene s = smallScene();
    Quadtree qt(s);
    qt.subdivide(qt.root());
    for (auto& c : qt.root().children) qt.subdivide(*c);
    std::size_t roadQuads = 0;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;
        const auto it = q.layers[0].curves.find(0);
        if (it == q.layers[0].curves.end()) return;
        ++roadQuads;
        // CREATEDFROM partitions the bucket by parent piece.
        std::size_t total = 0;
        const std::size_t parentPieces = q.level == 1 ? 1 : q.parent->layers[0].curves.at(0).size();
        for (std::uint32_t i = 0; i < parentPieces; ++i) total += Quadtree::createdFrom(q, 0, 0, i).size();
        EXPECT_EQ(total, it->second.size());
    });
    EXPECT_GE(roadQuads, 6u);
    // The shared field border: both areas are in the quads around it.
    const Quad& q = *qt.root().children[2];  // upper-left, holds both fields
    EXPECT_EQ(q.layers[1].areas.size(), 2u);
}

TEST(Quadtree, QuadsAtDepth24KeepThePieceWithinTolerance) {
    for (const Vec2 offset : {Vec2(0.0), Vec2(1.0e7, -1.0e7)}) {
        Scene s = smallScene();
        s.extent = {s.extent.min + offset, s.extent.max + offset};
        for (auto& l : s.layers) {
            for (auto& n : l.nodes) n.p += offset;
            for (auto& c : l.curves)
                for (auto& v : c.vertices) v.p += offset;
        }
        Quadtree qt(s);
        BezierPiece road;
        forEachPiece(s.layers[0].curves[0].vertices, [&](const BezierPiece& b, std::size_t) { road = b; });
        const Vec2 target = evaluate(road, 0.37);
        Quad* q = &qt.root();
        while (q->level < 24) {
            qt.subdivide(*q);
            for (auto& c : q->children)
                if (c->bounds.contains(target)) q = c.get();
        }
        ASSERT_EQ(q->level, 24);
        const double size = q->bounds.size().x;
        EXPECT_NEAR(size, 1000.0 / (1 << 24), 1e-12);
        const auto it = q->layers[0].curves.find(0);
        ASSERT_NE(it, q->layers[0].curves.end());
        const double tol = qt.params().tolerance(size);
        for (const auto& c : it->second)
            forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
                for (int i = 0; i <= 50; ++i)
                    EXPECT_LE(distanceToSegment(evaluate(b, i / 50.0), b.start(), b.end()), tol);
            });
        // The road passes through the quad: some kept piece is within tolerance of the target.
        double d = 1e300;
        for (const auto& c : it->second)
            forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) { d = std::min(d, distanceTo(b, target, tol * 0.01)); });
        EXPECT_LE(d, 1e-6 + std::abs(offset.x) * 1e-15);
    }
}

TEST(Quadtree, AnAreaCoveringDeepQuadsIsKnownToCoverThem) {
    const Scene s = smallScene();
    Quadtree qt(s);
    qt.refineForViewer({300.0, 600.0, 1.0}, 2.8, 8);  // inside the left field
    int covered = 0;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty() || q.level < 4) return;
        const auto it = q.layers[1].areas.find(0);
        if (it == q.layers[1].areas.end()) return;
        const bool inside = Box{{200 + 3, 500 + 3}, {400 - 3, 700 - 3}}.contains(q.bounds);
        EXPECT_EQ(it->second[0].coversQuad, inside) << "L" << q.level << " " << q.tx << "," << q.ty;
        covered += inside;
    });
    EXPECT_GT(covered, 10);
}

TEST(Quadtree, ProceduralStepRunsAtTheRootAndItsCurvesAreAncestors) {
    Scene s = smallScene();
    const SplitRoadsInTwo step;
    Quadtree qt(s, {}, &step);
    qt.refineForViewer({500.0, 150.0, 5.0}, 2.8, 7);
    std::set<ElementId> ancestors;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;
        for (const auto& [a, pieces] : q.layers[0].curves) ancestors.insert(a);
    });
    EXPECT_EQ(ancestors, (std::set<ElementId>{proceduralId(0, 0), proceduralId(0, 1)}));
    EXPECT_EQ(qt.ancestorCurve(0, proceduralId(0, 1)).end, 1u);
    // Editing the root road updates its procedural curves everywhere, as a rebuild would.
    const auto cs = moveVertex(s, 0, 0, 2, {650.0, 300.0});
    qt.update(cs);
    Quadtree rebuilt(s, {}, &step);
    rebuilt.copyStructureOf(qt);
    const auto diff = compareQuadtrees(qt, rebuilt);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details[0]);
}

TEST(Quadtree, UpdateTouchesOnlyQuadsWhereTheElementIs) {
    Scene s = smallScene();
    Quadtree qt(s);
    qt.refineForViewer({500.0, 500.0, 1.0}, 2.8, 9);
    const auto stats = qt.update(moveVertex(s, 0, 0, 1, {320.0, 380.0}));
    EXPECT_GT(stats.changedQuads.size(), 0u);
    EXPECT_LT(stats.changedQuads.size(), qt.quadCount() / 2);
    for (const Quad* q : stats.changedQuads) {
        // Each changed quad holds the road now (or held it before the edit).
        const bool has = q->layers[0].curves.count(0) > 0;
        const bool hadParent = q->parent->parent == nullptr || q->parent->layers[0].curves.count(0) > 0;
        EXPECT_TRUE(has || hadParent);
    }
}

}  // namespace
}  // namespace lacet
