// The quads a frame shows within the cache's capacity (editor/cache_fit.h).
#include "editor/cache_fit.h"

#include <random>
#include <set>

#include <gtest/gtest.h>

#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

std::vector<const Quad*> leavesOf(const Quadtree& qt) {
    std::vector<const Quad*> out;
    qt.forEachQuad([&](const Quad& q) {
        if (q.isLeaf()) out.push_back(&q);
    });
    return out;
}

std::size_t ancestorsOf(const std::vector<const Quad*>& quads) {
    std::set<const Quad*> a;
    for (const Quad* q : quads)
        for (const Quad* p = q->parent; p; p = p->parent) a.insert(p);
    return a.size();
}

TEST(CacheFit, AViewThatFitsShowsItsLeaves) {
    const Scene scene = makeSyntheticScene({3, 1500});
    Quadtree qt(scene, RefineParams{{.resolution = 32}});
    const Vec2 c = scene.extent.center();
    const glm::dvec3 viewer(c.x, c.y, 30.0);
    qt.refineForViewer(viewer, ViewParams{.maxLevel = 10});
    const auto leaves = leavesOf(qt);
    const std::size_t need = leaves.size() + ancestorsOf(leaves);
    const CacheFit fit = fitToCache(leaves, need, viewer, [](const Quad&) { return true; });
    EXPECT_EQ(fit.shown.size(), leaves.size());
    EXPECT_TRUE(fit.replaced.empty());
    EXPECT_EQ(fit.kept, need);
    // Ancestors without tiles are not kept, so they do not count.
    EXPECT_EQ(fitToCache(leaves, leaves.size(), viewer, [](const Quad&) { return false; }).shown.size(), leaves.size());
}

TEST(CacheFit, ASmallerCacheShowsTheFarthestQuadsInPlaceOfTheirChildren) {
    // Randomized: viewers and capacities with fixed seeds. Every leaf is shown by exactly one
    // quad (itself or an ancestor), no shown quad is above another, the tiles kept fit the
    // capacity, and the quads standing in are farther than the leaves kept near the viewer. Half
    // the trials take a random part of the leaves (a frustum leaves some parents one visible
    // child) and no ancestor has a tile yet (a session's first frame).
    const Scene scene = makeSyntheticScene({4, 3000});
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> at(0.0, 1.0);
    for (int trial = 0; trial < 12; ++trial) {
        Quadtree qt(scene, RefineParams{{.resolution = 32}});
        const Vec2 p = scene.extent.min + scene.extent.size() * Vec2(at(rng), at(rng));
        const glm::dvec3 viewer(p.x, p.y, 10.0 + 200.0 * at(rng));
        qt.refineForViewer(viewer, ViewParams{.maxLevel = 12});
        const bool part = trial % 2 == 1;
        std::vector<const Quad*> leaves;
        for (const Quad* q : leavesOf(qt))
            if (!part || at(rng) < 0.6 || q->bounds.contains(p)) leaves.push_back(q);
        const std::size_t need = leaves.size() + (part ? 0 : ancestorsOf(leaves));
        const std::size_t capacity = trial == 11 ? 1 : std::size_t(double(need) * (0.05 + 0.75 * at(rng)));
        const auto hasTile = [&](const Quad& q) { return !part && (q.tx + q.ty + std::uint32_t(q.level)) % 3 != 0; };
        const CacheFit fit = fitToCache(leaves, capacity, viewer, hasTile);
        ASSERT_LE(fit.kept, capacity) << trial;
        EXPECT_GT(fit.replaced.size(), 0u);
        const std::set<const Quad*> shown(fit.shown.begin(), fit.shown.end());
        // The kept count is what it says: shown quads and ancestors of them that have a tile.
        std::set<const Quad*> ancestors;
        for (const Quad* q : fit.shown)
            for (const Quad* a = q->parent; a; a = a->parent) {
                EXPECT_EQ(shown.count(a), 0u) << "a shown quad above another";
                ancestors.insert(a);
            }
        std::size_t kept = shown.size();
        for (const Quad* a : ancestors) kept += hasTile(*a);
        EXPECT_EQ(fit.kept, kept);
        double nearestStandIn = 1e300;
        std::size_t replaced = 0;
        for (const Quad* leaf : leaves) {
            std::size_t by = 0;
            for (const Quad* q = leaf; q; q = q->parent) by += shown.count(q);
            EXPECT_EQ(by, 1u) << "leaf shown by " << by << " quads";
            replaced += shown.count(leaf) == 0;
        }
        EXPECT_EQ(replaced, fit.replaced.size());
        for (const Quad* q : fit.shown)
            if (!q->isLeaf()) nearestStandIn = std::min(nearestStandIn, Quadtree::viewDistance(*q, viewer));
        // The leaf under the viewer keeps its own tile; no quad standing in is as near.
        const Quad* under = &qt.root();
        while (!under->isLeaf())
            for (const auto& child : under->children)
                if (child->bounds.contains(p)) {
                    under = child.get();
                    break;
                }
        if (capacity > 1) {
            EXPECT_EQ(shown.count(under), 1u) << trial;
            EXPECT_GT(nearestStandIn, Quadtree::viewDistance(*under, viewer)) << trial;
        } else {  // the root alone
            EXPECT_EQ(fit.shown, std::vector<const Quad*>{&qt.root()});
        }
        // Deterministic.
        const CacheFit again = fitToCache(leaves, capacity, viewer, hasTile);
        EXPECT_EQ(again.shown, fit.shown);
    }
}

}  // namespace
}  // namespace lacet
