#include "editor/draw_plan.h"

#include <algorithm>

namespace lacet {
namespace {

// A leaf key packed in 64 bits: the level (up to 63) and x, y (up to 2^28 each: any level a
// double-precision quadtree reaches over a planet).
std::uint64_t pack(int level, std::uint32_t x, std::uint32_t y) {
    return (std::uint64_t(level) << 58) | (std::uint64_t(x & 0x1FFFFFFFu) << 29) | std::uint64_t(y & 0x1FFFFFFFu);
}

}  // namespace

QuadKey keyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

DrawPlan makeDrawPlan(const Quadtree& tree, const std::function<const CachedTile*(const QuadKey&)>& tileOf,
                      const std::function<bool(const Quad&)>& visible, const SkirtParams& skirt) {
    DrawPlan plan;
    plan.rootBounds = tree.root().bounds;
    tree.forEachQuad([&](const Quad& leaf) {
        if (!leaf.isLeaf()) return;
        DrawItem item;
        item.leaf = keyOf(leaf);
        item.bounds = leaf.bounds;
        item.visible = !visible || visible(leaf);
        const Quad* q = &leaf;
        const CachedTile* tile = tileOf(keyOf(*q));
        while (!tile && q->parent) {
            q = q->parent;
            tile = tileOf(keyOf(*q));
        }
        item.tileKey = keyOf(*q);
        item.tile = tile;
        if (!item.visible) ++plan.culled;
        else if (!tile) ++plan.missing;
        else {
            ++plan.drawn;
            if (q != &leaf) {
                ++plan.fallback;
                plan.coarsestAncestorDelta = std::max(plan.coarsestAncestorDelta, tile->elevation.delta);
            }
        }
        plan.deepest = std::max(plan.deepest, leaf.level);
        plan.byKey.emplace(pack(leaf.level, leaf.tx, leaf.ty), plan.items.size());
        plan.items.push_back(item);
    });
    for (DrawItem& item : plan.items)
        item.skirt = item.bounds.size().x * skirt.sizeFraction + skirt.slope * plan.coarsestAncestorDelta;
    return plan;
}

const DrawItem* DrawPlan::itemAt(Vec2 p) const {
    if (items.empty()) return nullptr;
    // Down from the root as the tree splits (model/quadtree.cpp: children at the centre, the upper
    // half from the centre on), until the quad over p is a leaf of the plan; a point outside the
    // root goes to the quads along its nearest edge.
    Box b = rootBounds;
    std::uint32_t x = 0, y = 0;
    for (int level = 0; level <= deepest; ++level) {
        const auto it = byKey.find(pack(level, x, y));
        if (it != byKey.end()) return &items[it->second];
        const Vec2 mid = b.center();
        const bool right = p.x >= mid.x, up = p.y >= mid.y;
        b = Box{Vec2(right ? mid.x : b.min.x, up ? mid.y : b.min.y), Vec2(right ? b.max.x : mid.x, up ? b.max.y : mid.y)};
        x = 2 * x + std::uint32_t(right), y = 2 * y + std::uint32_t(up);
    }
    return nullptr;
}

}  // namespace lacet
