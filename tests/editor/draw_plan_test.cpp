// The draw plan against a walk of the tree: after frames whose budget leaves tiles pending (so
// that ancestors stand in), every leaf has the tile of its nearest ancestor-or-self the cache
// holds, the counts and skirts follow, and the plan's lookup and the displayed height agree with
// the deepest tile over a point, for random points.
#include "editor/draw_plan.h"

#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include "model/work_clock.h"

#include "editor/edit_session.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

// The reference: down the current tree to the leaf over p, keeping the deepest quad with a tile.
std::pair<const Quad*, const CachedTile*> deepestTileOver(const EditSession& s, Vec2 p) {
    std::pair<const Quad*, const CachedTile*> best{nullptr, nullptr};
    const Quad* q = &s.quadtree().root();
    while (q) {
        if (const CachedTile* t = s.tile(keyOf(*q))) best = {q, t};
        if (q->isLeaf()) break;
        const Vec2 c = q->bounds.center();
        q = q->children[std::size_t(int(p.x >= c.x) | (int(p.y >= c.y) << 1))].get();
    }
    return best;
}

TEST(DrawPlan, EveryLeafDrawsItsNearestTiledAncestorAndLookupsAgreeWithTheTree) {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = 10;
    // The budget is read on a stepped clock: it leaves the same quads pending on any machine.
    params.clock = steppedClockMs(0.05);
    SceneDocument doc;
    doc.scene = makeSyntheticScene({21, 1500});
    doc.dem = makeSyntheticDem(doc.scene, {21, 1000});
    EditSession session(std::move(doc), params);
    const Box ext = session.document().scene.extent;
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    session.frame({ext.center().x, ext.center().y, 1e6}, 0.0);  // the root's tile
    std::size_t fallbacks = 0;
    for (int step = 0; step < 6; ++step) {
        const glm::dvec3 viewer(ext.min.x + u(rng) * ext.size().x, ext.min.y + u(rng) * ext.size().y, 5.0 + 50.0 * u(rng));
        // Half the view's leaves culled, and a budget that leaves most of the view pending.
        const QuadVisibility visible = [&](const Quad& q) { return q.bounds.center().x < viewer.x + 200.0; };
        session.frame(viewer, 1.0, visible);
        const DrawPlan& plan = session.plan();
        std::size_t leaves = 0, drawn = 0, fallback = 0, missing = 0, culled = 0;
        double coarsest = 0.0;
        session.quadtree().forEachQuad([&](const Quad& leaf) {
            if (!leaf.isLeaf()) return;
            const DrawItem* item = plan.itemAt(leaf.bounds.center());
            ASSERT_NE(item, nullptr);
            EXPECT_EQ(item->leaf, keyOf(leaf));
            const Quad* q = &leaf;
            while (!session.tile(keyOf(*q)) && q->parent) q = q->parent;
            const CachedTile* t = session.tile(keyOf(*q));
            EXPECT_EQ(item->tile, t);
            if (t) {
                EXPECT_EQ(item->tileKey, keyOf(*q));
            }
            EXPECT_EQ(item->visible, visible(leaf));
            ++leaves;
            if (!item->visible) ++culled;
            else if (!t) ++missing;
            else {
                ++drawn;
                if (q != &leaf) ++fallback, coarsest = std::max(coarsest, t->elevation.delta);
            }
        });
        EXPECT_EQ(plan.items.size(), leaves);
        EXPECT_EQ(plan.gridCells, params.refine.elevationResolution);
        EXPECT_EQ(plan.drawn, drawn);
        EXPECT_EQ(plan.fallback, fallback);
        EXPECT_EQ(plan.missing, missing);
        EXPECT_EQ(plan.culled, culled);
        EXPECT_EQ(plan.coarsestAncestorDelta, coarsest);
        for (const DrawItem& item : plan.items)
            EXPECT_EQ(item.skirt, item.bounds.size().x * params.skirt.sizeFraction + params.skirt.slope * coarsest);
        fallbacks += fallback;
        // Random points, inside and a little outside the scene: the plan's tile is the deepest
        // tile over the point, and the displayed height is that tile's.
        for (int i = 0; i < 300; ++i) {
            const Vec2 p(ext.min.x + (1.1 * u(rng) - 0.05) * ext.size().x, ext.min.y + (1.1 * u(rng) - 0.05) * ext.size().y);
            const auto [q, t] = deepestTileOver(session, p);
            const auto [pq, pt] = session.tileAt(p);
            EXPECT_EQ(pt, t);
            EXPECT_EQ(pq, q);
        }
    }
    EXPECT_GT(fallbacks, 0u);  // the budget left leaves drawn with an ancestor's tile
}

TEST(DrawPlan, AFullCacheDrawsAncestorsAndAnEditChangesNothingShownUntilTheNextFrame) {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = 10;
    params.cacheTiles = 30;  // far fewer than the view's leaves: ancestors stand in (editor/cache_fit.h)
    SceneDocument doc;
    doc.scene = makeSyntheticScene({22, 1500});
    doc.dem = makeSyntheticDem(doc.scene, {22, 1000});
    EditSession session(std::move(doc), params);
    const Box ext = session.document().scene.extent;
    const Vec2 c = ext.center();
    session.frame({c.x, c.y, 5.0}, 0.0);
    const DrawPlan& plan = session.plan();
    EXPECT_GT(plan.fallback, 0u);
    EXPECT_EQ(plan.missing, 0u);
    // Heights shown over a grid of points, then a node near the centre moved by 20 m.
    std::vector<Vec2> points;
    std::vector<double> shown;
    for (int j = 0; j <= 40; ++j)
        for (int i = 0; i <= 40; ++i) {
            points.push_back(ext.min + ext.size() * Vec2(i / 40.0, j / 40.0));
            shown.push_back(session.displayedHeight(points.back()));
        }
    const Layer& roads = session.document().scene.layers[kRoadsLayer];
    ElementId node = kNoElement;
    for (ElementId n = 0; n < roads.nodes.size(); ++n)
        if (roads.nodes[n].alive && (node == kNoElement || glm::length(roads.nodes[n].p - c) < glm::length(roads.nodes[node].p - c))) node = n;
    ASSERT_NE(node, kNoElement);
    const CommandReport r = session.execute(MoveNodeCmd{kRoadsLayer, node, roads.nodes[node].p + Vec2(20.0, 0.0)});
    EXPECT_GT(r.dirtyTiles, 0u);
    for (std::size_t k = 0; k < points.size(); ++k) {
        EXPECT_EQ(session.displayedHeight(points[k]), shown[k]);
        const auto [q, t] = session.tileAt(points[k]);
        EXPECT_EQ(t, deepestTileOver(session, points[k]).second);
    }
}

TEST(DrawPlan, AnEmptyPlanFindsNothingAndTheDisplayedHeightIsTheDem) {
    DrawPlan plan;
    EXPECT_EQ(plan.itemAt({0.0, 0.0}), nullptr);
    SceneDocument doc;
    doc.scene = makeSyntheticScene({3, 300});
    doc.dem = makeSyntheticDem(doc.scene, {3, 500});
    EditSession session(std::move(doc), {});
    const Vec2 c = session.document().scene.extent.center();
    EXPECT_TRUE(session.plan().items.empty());
    EXPECT_EQ(session.displayedHeight(c), session.document().dem->sample(c));
}

}  // namespace
}  // namespace lacet
