#include "model/quadtree.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <iterator>
#include <map>
#include <set>
#include <span>
#include <stdexcept>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/quadtree_compare.h"
#include "model/work_clock.h"
#include "synth/synthetic_scene.h"
#include "tests/model/small_scene.h"
#include "tests/model/split_roads.h"
#include "tests/model/test_geometry.h"

namespace lacet {
namespace {

using test::smallScene;

using test::SplitRoadsInTwo;

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
            Quad* next = nullptr;
            for (auto& c : q->children)
                if (!next && c->bounds.contains(target)) next = c.get();
            ASSERT_NE(next, nullptr) << "no child of level " << q->level << " contains the target";
            q = next;
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
    qt.refineForViewer({300.0, 600.0, 1.0}, ViewParams{.maxLevel = 8});  // inside the left field
    int covered = 0;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty() || q.level < 4) return;
        const auto it = q.layers[1].areas.find(0);
        if (it == q.layers[1].areas.end()) return;
        const double m = qt.params().areaMargin(2.0, q.bounds.size().x);
        const bool inside = Box{{200 + m, 500 + m}, {400 - m, 700 - m}}.contains(q.bounds);
        EXPECT_EQ(it->second[0].coversQuad, inside) << "L" << q.level << " " << q.tx << "," << q.ty;
        covered += inside;
    });
    EXPECT_GT(covered, 10);
}

TEST(Quadtree, ProceduralStepRunsAtTheRootAndItsCurvesAreAncestors) {
    Scene s = smallScene();
    SplitRoadsInTwo step;
    Quadtree qt(s, {}, &step);
    qt.refineForViewer({500.0, 150.0, 5.0}, ViewParams{.maxLevel = 7});
    std::set<AncestorId> ancestors;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;
        for (const auto& [a, pieces] : q.layers[0].curves) ancestors.insert(a);
    });
    EXPECT_EQ(ancestors, (std::set<AncestorId>{proceduralId(0, 0), proceduralId(0, 1)}));
    EXPECT_EQ(qt.ancestorCurve(0, proceduralId(0, 1)).end, 1u);
    // Editing the root road updates its procedural curves everywhere, as a rebuild would.
    const auto cs = moveVertex(s, 0, 0, 2, {650.0, 300.0});
    qt.update(cs);
    Quadtree rebuilt(s, {}, &step);
    rebuilt.copyStructureOf(qt);
    const auto diff = compareQuadtrees(qt, rebuilt);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details[0]);
}

// Issue 13 item 3: proceduralId threw for root curve ids from 2^23 on (and for k >= 256), so a
// layer of more than 8 million curves could not take a procedural step.
TEST(Quadtree, ProceduralIdsOfEveryRootCurveIdAreDistinctOrderedAndGiveBackRootAndIndex) {
    const ElementId roots[] = {0, 1, (1u << 23) - 1, 1u << 23, (1u << 23) + 1, 0x7fffffffu, 0x80000000u, kNoElement - 1};
    const std::size_t ks[] = {0, 1, 255, 256, 65535, 65536, kMaxProceduralCurves - 1};
    std::vector<AncestorId> ids;
    for (ElementId root : roots) {
        EXPECT_EQ(AncestorId(root) & kProceduralBit, 0u);
        EXPECT_EQ(rootCurveOf(root), root);
        EXPECT_EQ(proceduralIndex(root), 0u);
        for (std::size_t k : ks) {
            const AncestorId pid = proceduralId(root, k);
            EXPECT_NE(pid & kProceduralBit, 0u) << root << " " << k;
            EXPECT_EQ(rootCurveOf(pid), root) << k;
            EXPECT_EQ(proceduralIndex(pid), k) << root;
            ids.push_back(pid);
        }
    }
    // By root, then k: the ids of one root are one range, apart from every other root's.
    EXPECT_EQ(std::adjacent_find(ids.begin(), ids.end(), std::greater_equal<>()), ids.end());
    EXPECT_THROW(proceduralId(0, kMaxProceduralCurves), std::length_error);
}

TEST(Quadtree, UpdateMarksExactlyTheQuadsWhoseGraphChanged) {
    Scene s = smallScene();
    Quadtree qt(s);
    qt.refineForViewer({500.0, 500.0, 1.0}, ViewParams{.maxLevel = 9});
    // Snapshot every quad's road pieces, edit, and compare.
    std::map<const Quad*, std::vector<ClippedCurve>> before;
    qt.forEachQuad([&](const Quad& q) {
        if (q.layers.empty()) return;
        const auto it = q.layers[0].curves.find(0);
        before[&q] = it == q.layers[0].curves.end() ? std::vector<ClippedCurve>{} : it->second;
    });
    const auto stats = qt.update(moveVertex(s, 0, 0, 1, {320.0, 380.0}));
    const std::set<const Quad*> changed(stats.changedQuads.begin(), stats.changedQuads.end());
    EXPECT_EQ(changed.size(), stats.changedQuads.size());
    std::size_t withRoad = 0;
    for (const auto& [q, pieces] : before) {
        const auto it = q->layers[0].curves.find(0);
        const bool hasNow = it != q->layers[0].curves.end();
        // Alg. 6.1 rebuilds every piece made from the edited road: a quad is changed exactly when
        // it held or now holds some.
        EXPECT_EQ(changed.count(q) > 0, hasNow || !pieces.empty()) << "L" << q->level << " " << q->tx << "," << q->ty;
        withRoad += hasNow || !pieces.empty();
    }
    EXPECT_GT(withRoad, 10u);
    EXPECT_LT(changed.size(), qt.quadCount() / 2);
}

// The leaves the viewers want subdivided, by (level, tx, ty), with the key the refinement orders
// them by: 0 and the first viewer's distance over size, or 1 and the others' smallest.
using LeafKey = std::tuple<int, std::uint32_t, std::uint32_t>;
std::map<LeafKey, std::pair<int, double>> wantedLeaves(const Quadtree& qt, std::span<const glm::dvec3> viewers, const ViewParams& view) {
    std::map<LeafKey, std::pair<int, double>> out;
    qt.forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        const double size = q.bounds.size().x;
        if (Quadtree::wantsSubdivision(q, viewers[0], view)) {
            out[{q.level, q.tx, q.ty}] = {0, Quadtree::viewDistance(q, viewers[0]) / size};
            return;
        }
        for (std::size_t i = 1; i < viewers.size(); ++i)
            if (Quadtree::wantsSubdivision(q, viewers[i], view)) {
                const double r = Quadtree::viewDistance(q, viewers[i]) / size;
                const auto it = out.find({q.level, q.tx, q.ty});
                if (it == out.end() || r < it->second.second) out[{q.level, q.tx, q.ty}] = {1, r};
            }
    });
    return out;
}

std::set<LeafKey> innerQuads(const Quadtree& qt) {
    std::set<LeafKey> out;
    qt.forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) out.insert({q.level, q.tx, q.ty});
    });
    return out;
}

// Issue 28: a call under a deadline that passed before its first subdivision used to subdivide
// nothing, so that a slow machine could leave the view coarse forever. Now every call makes the
// most wanted subdivision whatever the deadline: with a deadline already passed, exactly one a
// call, so the calls reach the complete tree in as many calls as it has subdivisions.
TEST(Quadtree, APassedDeadlineStillMakesTheMostWantedSubdivisionAndTheCallsReachTheCompleteTree) {
    const Scene scene = makeSyntheticScene({7, 800});
    const Vec2 c = scene.extent.center();
    const glm::dvec3 viewers[1] = {{c.x + 37.0, c.y - 11.0, 15.0}};
    const ViewParams view{.maxLevel = 12};
    Quadtree complete(scene), stepwise(scene);
    complete.refineForViewer(viewers[0], view);
    const std::size_t subdivisions = (complete.quadCount() - 1) / 4;
    ASSERT_GT(subdivisions, 20u);
    const WorkClock clock = steppedClock(std::chrono::microseconds(1));
    std::size_t calls = 0;
    for (bool done = false; !done;) {
        ASSERT_LT(calls, subdivisions) << "a call made no progress";
        const auto wanted = wantedLeaves(stepwise, viewers, view);
        ASSERT_FALSE(wanted.empty());
        const auto most = std::min_element(wanted.begin(), wanted.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
        const std::set<LeafKey> before = innerQuads(stepwise);
        done = stepwise.refineForViewers(viewers, view, Deadline{clock, clock()});  // passed when read
        ++calls;
        std::set<LeafKey> made;
        std::ranges::set_difference(innerQuads(stepwise), before, std::inserter(made, made.end()));
        ASSERT_EQ(made.size(), 1u) << "call " << calls;
        // The quad subdivided is one of the most wanted (ties are broken by level and position).
        EXPECT_EQ(wanted.at(*made.begin()), most->second) << "call " << calls;
    }
    EXPECT_EQ(calls, subdivisions);
    const QuadtreeDiff diff = compareQuadtrees(complete, stepwise);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details.front());
    EXPECT_EQ(complete.quadCount(), stepwise.quadCount());
    // With nothing left to do, a call with a passed deadline changes nothing and says so.
    EXPECT_TRUE(stepwise.refineForViewers(viewers, view, Deadline{clock, clock()}));
    EXPECT_EQ(complete.quadCount(), stepwise.quadCount());
}

// A deadline read on a stepped clock lets through the same work on any machine: each reading
// after the first subdivision advances the clock one step, so a deadline of ten steps makes ten
// subdivisions a call.
TEST(Quadtree, ADeadlineOnASteppedClockMakesTheSameSubdivisionsEveryRun) {
    const Scene scene = makeSyntheticScene({7, 800});
    const Vec2 c = scene.extent.center();
    const glm::dvec3 viewers[1] = {{c.x, c.y, 15.0}};
    const ViewParams view{.maxLevel = 12};
    Quadtree complete(scene), stepwise(scene);
    complete.refineForViewer(viewers[0], view);
    const std::size_t subdivisions = (complete.quadCount() - 1) / 4;
    const WorkClock clock = steppedClock(std::chrono::microseconds(1));
    std::size_t calls = 0;
    for (bool done = false; !done; ++calls) {
        ASSERT_LT(calls, subdivisions);
        const std::size_t before = stepwise.quadCount();
        done = stepwise.refineForViewers(viewers, view, Deadline::after(clock(), 0.010, clock));
        if (!done) {
            EXPECT_EQ(stepwise.quadCount(), before + 4 * 10) << "call " << calls;
        }
    }
    EXPECT_EQ(calls, (subdivisions + 9) / 10);
    EXPECT_EQ(compareQuadtrees(complete, stepwise).mismatches, 0u);
}

// Two viewers (the current one and the predicted one): what the first wants is done before what
// only the second wants, then the tree is the one both want.
TEST(Quadtree, UnderADeadlineTheFirstViewersSubdivisionsComeFirst) {
    const Scene scene = makeSyntheticScene({7, 800});
    const Box e = scene.extent;
    const glm::dvec3 viewers[2] = {{e.min.x + 0.3 * e.size().x, e.min.y + 0.4 * e.size().y, 20.0},
                                   {e.min.x + 0.7 * e.size().x, e.min.y + 0.6 * e.size().y, 20.0}};
    const ViewParams view{.maxLevel = 11};
    Quadtree first(scene), both(scene), stepwise(scene);
    first.refineForViewer(viewers[0], view);
    EXPECT_TRUE(both.refineForViewers(viewers, view));
    const std::set<LeafKey> firstInner = innerQuads(first);
    const WorkClock clock = steppedClock(std::chrono::microseconds(1));
    std::size_t calls = 0;
    bool done = false;
    for (; !done && calls < firstInner.size(); ++calls) done = stepwise.refineForViewers(viewers, view, Deadline{clock, clock()});
    EXPECT_FALSE(done);
    EXPECT_EQ(innerQuads(stepwise), firstInner);  // every one the first viewer wants, no other yet
    for (; !done; ++calls) {
        ASSERT_LT(calls, both.quadCount());
        done = stepwise.refineForViewers(viewers, view, Deadline{clock, clock()});
    }
    EXPECT_EQ(calls, (both.quadCount() - 1) / 4);
    EXPECT_EQ(compareQuadtrees(both, stepwise).mismatches, 0u);
}

// A viewer that moves away: the calls merge what it no longer wants, deadline or not.
TEST(Quadtree, UnderAPassedDeadlineQuadsNoLongerWantedAreStillMerged) {
    const Scene scene = makeSyntheticScene({7, 800});
    const Box e = scene.extent;
    const glm::dvec3 near[1] = {{e.center().x, e.center().y, 15.0}};
    const glm::dvec3 far[1] = {{e.center().x, e.center().y, 1e7}};
    const ViewParams view{.maxLevel = 12};
    Quadtree qt(scene);
    qt.refineForViewer(near[0], view);
    ASSERT_GT(qt.quadCount(), 1u);
    const WorkClock clock = steppedClock(std::chrono::microseconds(1));
    EXPECT_TRUE(qt.refineForViewers(far, view, Deadline{clock, clock()}));
    EXPECT_EQ(qt.quadCount(), 1u);
    EXPECT_THROW(qt.refineForViewers({}, view), std::invalid_argument);
}

// A ChildMaker that has no children for a leaf the first `delay` times it is asked (they are
// "being made"), then gives makeChildren's; it records what it was asked.
class DelayingMaker final : public ChildMaker {
public:
    explicit DelayingMaker(int delay) : delay_(delay) {}
    std::optional<QuadChildren> children(const Quadtree& tree, const Quad& q) override {
        ++asked;
        if (++seen_[{q.level, q.tx, q.ty}] <= delay_) return std::nullopt;
        ++given;
        return tree.makeChildren(q);
    }
    std::size_t asked = 0, given = 0;

private:
    int delay_;
    std::map<std::tuple<int, std::uint32_t, std::uint32_t>, int> seen_;
};

// Issue 24 (no slow frame): subdivisions whose children are made elsewhere (on a background
// thread in the editor) are deferred until they are given, without counting as the call's first
// subdivision; the calls reach the tree refineForViewer makes, piece for piece.
TEST(Quadtree, ARefinementWhoseChildrenComeLaterReachesTheSameTree) {
    const Scene scene = makeSyntheticScene({7, 800});
    const Vec2 c = scene.extent.center();
    const glm::dvec3 viewers[1] = {{c.x + 37.0, c.y - 11.0, 15.0}};
    const ViewParams view{.maxLevel = 12};
    Quadtree complete(scene), later(scene);
    complete.refineForViewer(viewers[0], view);
    DelayingMaker maker(2);
    const WorkClock clock = steppedClock(std::chrono::microseconds(1));
    std::size_t calls = 0, deferred = 0;
    for (bool done = false; !done && calls < 10000; ++calls) {
        done = later.refineForViewers(viewers, view, Deadline{clock, clock()}, &maker);
        deferred += !done;
    }
    EXPECT_GT(deferred, 0u);
    EXPECT_EQ(maker.given, (complete.quadCount() - 1) / 4);
    EXPECT_GE(maker.asked, 3 * maker.given);  // each leaf asked until its children came
    const QuadtreeDiff diff = compareQuadtrees(complete, later);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details.front());
    EXPECT_EQ(complete.quadCount(), later.quadCount());
}

// makeChildren leaves the leaf as it is, and attach() gives the graph subdivide() makes; a
// cancelled makeChildren throws WorkCancelled and a later one makes the same children.
TEST(Quadtree, ChildrenMadeApartAndAttachedAreSubdividesAndACancelledMakingThrows) {
    const Scene scene = makeSyntheticScene({9, 600});
    Quadtree a(scene), b(scene);
    a.subdivide(a.root());
    b.subdivide(b.root());
    Quad& leaf = *b.root().children[0];
    CancelFlag cancel{true};
    EXPECT_THROW((void)b.makeChildren(leaf, &cancel), WorkCancelled);
    EXPECT_TRUE(leaf.isLeaf());
    QuadChildren kids = b.makeChildren(leaf);
    EXPECT_TRUE(leaf.isLeaf());
    b.attach(leaf, std::move(kids));
    a.subdivide(*a.root().children[0]);
    const QuadtreeDiff diff = compareQuadtrees(a, b);
    EXPECT_EQ(diff.mismatches, 0u) << (diff.details.empty() ? "" : diff.details.front());
    EXPECT_EQ(a.quadCount(), b.quadCount());
    for (const auto& kid : leaf.children) EXPECT_EQ(kid->parent, &leaf);
    // Attaching to a quad that is no longer a leaf changes nothing.
    b.attach(leaf, b.makeChildren(leaf));
    EXPECT_EQ(a.quadCount(), b.quadCount());
}

}  // namespace
}  // namespace lacet
