#include "editor/draw_plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "editor/quad_forest.h"
#include "model/view_params.h"

namespace lacet {
namespace {

// x in the even bits, y in the odd ones: a child index (x | y << 1) per level, the root's first.
std::uint64_t interleave(std::uint32_t x, std::uint32_t y) {
    std::uint64_t z = 0;
    for (int b = 31; b >= 0; --b) z = (z << 2) | (std::uint64_t((y >> b) & 1u) << 1) | std::uint64_t((x >> b) & 1u);
    return z;
}

struct PlanWalk {
    DrawPlan& plan;
    const std::function<const CachedTile*(const QuadKey&)>& tileOf;
    const std::function<bool(const Quad&)>& visible;
    const QuadForest& forest;

    // `tiled`: the nearest ancestor of q that has a tile (nullptr: none).
    void visit(const Quad& q, const Quad* tiled, const CachedTile* tile) {
        if (const CachedTile* own = tileOf(keyOf(q))) tiled = &q, tile = own;
        if (!q.isLeaf()) {
            for (const auto& c : q.children) visit(forest.resolve(*c), tiled, tile);
            return;
        }
        DrawItem item;
        item.leaf = keyOf(q);
        item.bounds = q.bounds;
        item.visible = !visible || visible(q);
        item.tileKey = tiled ? keyOf(*tiled) : item.leaf;
        item.tile = tile;
        if (!item.visible) ++plan.culled;
        else if (!tile) ++plan.missing;
        else {
            ++plan.drawn;
            if (tiled != &q) {
                ++plan.fallback;
                plan.coarsestAncestorDelta = std::max(plan.coarsestAncestorDelta, tile->elevation.delta);
            }
        }
        plan.deepest = std::max(plan.deepest, q.level);
        plan.items.push_back(item);
    }
};

// A tree read as a forest for its plan (no curve data, no refinement).
class TreeOnly final : public QuadForest {
public:
    explicit TreeOnly(const Quadtree& tree) : tree_(tree) {}
    const Quad& root() const override { return tree_.root(); }
    const Quadtree& treeOf(const Quad&) const override { return tree_; }
    const CurveDataCache& dataOf(const Quad&) const override { throw std::logic_error("makeDrawPlan(): no curve data"); }
    bool refine(std::span<const glm::dvec3>, const ViewParams&, const std::optional<Deadline>&, ChildMaker*) override {
        throw std::logic_error("makeDrawPlan(): the plan does not refine");
    }

private:
    const Quadtree& tree_;
};

}  // namespace

QuadKey keyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

DrawPlan makeDrawPlan(const Quadtree& tree, const std::function<const CachedTile*(const QuadKey&)>& tileOf,
                      const std::function<bool(const Quad&)>& visible, const SkirtParams& skirt) {
    return makeDrawPlan(TreeOnly(tree), tileOf, visible, skirt);
}

DrawPlan makeDrawPlan(const QuadForest& forest, const std::function<const CachedTile*(const QuadKey&)>& tileOf,
                      const std::function<bool(const Quad&)>& visible, const SkirtParams& skirt) {
    DrawPlan plan;
    const Quad& root = forest.resolve(forest.root());
    plan.gridCells = forest.treeOf(root).params().elevationResolution;
    plan.rootBounds = root.bounds;
    PlanWalk{plan, tileOf, visible, forest}.visit(root, nullptr, nullptr);
    std::set<QuadKey> withObjects;  // tiles whose objects an earlier item draws
    for (DrawItem& item : plan.items) {
        item.skirt = item.bounds.size().x * skirt.sizeFraction + skirt.slope * plan.coarsestAncestorDelta;
        if (item.drawn() && !item.tile->objects.empty() && withObjects.insert(item.tileKey).second) item.objects = &item.tile->objects;
    }
    if (plan.deepest > ViewParams::kMaxLevel)
        throw std::invalid_argument("makeDrawPlan(): the tree is deeper than ViewParams::kMaxLevel");
    plan.zStart.reserve(plan.items.size());
    for (const DrawItem& item : plan.items) {
        const auto [level, x, y] = item.leaf;
        plan.zStart.push_back(interleave(x, y) << (2 * (plan.deepest - level)));
    }
    return plan;
}

const DrawItem* DrawPlan::itemAt(Vec2 p) const {
    if (items.empty()) return nullptr;
    // Down from the root as the tree splits (model/quadtree.cpp: children at the centre, the upper
    // half from the centre on) to the deepest level; a point outside the root goes to the quads
    // along its nearest edge.
    const auto inLeaf = [&](const DrawItem& item, std::uint32_t x, std::uint32_t y) {
        const auto [level, tx, ty] = item.leaf;
        const int up = deepest - level;
        return (x >> up) == tx && (y >> up) == ty;
    };
    Box b = rootBounds;
    std::uint32_t x = 0, y = 0;
    for (int level = 0; level < deepest; ++level) {
        const Vec2 mid = b.center();
        const bool right = p.x >= mid.x, upper = p.y >= mid.y;
        b = Box{Vec2(right ? mid.x : b.min.x, upper ? mid.y : b.min.y), Vec2(right ? b.max.x : mid.x, upper ? b.max.y : mid.y)};
        x = 2 * x + std::uint32_t(right), y = 2 * y + std::uint32_t(upper);
    }
    // The leaves tile the root in Z-order: the one over p is the last starting at or before p's code.
    const auto it = std::upper_bound(zStart.begin(), zStart.end(), interleave(x, y));
    const DrawItem& item = items[std::size_t(it - zStart.begin()) - 1];
    return inLeaf(item, x, y) ? &item : nullptr;
}

}  // namespace lacet
