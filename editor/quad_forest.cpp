#include "editor/quad_forest.h"

namespace lacet {

bool QuadForest::keeps(const Quad& q, std::span<const glm::dvec3> viewers, const ViewParams& view) const {
    for (const Quad* a = q.parent; a; a = a->parent)
        if (!Quadtree::wantedByAny(*a, viewers, view)) return false;
    return true;
}

const Quad* findQuad(const QuadForest& forest, const QuadKey& key) {
    const auto [level, tx, ty] = key;
    const Quad* q = &forest.resolve(forest.root());
    while (q->level < level) {
        if (q->isLeaf()) return nullptr;
        const int shift = level - q->level - 1;
        q = &forest.resolve(*q->children[std::size_t(int((tx >> shift) & 1u) | int(((ty >> shift) & 1u) << 1))]);
    }
    return q->tx == tx && q->ty == ty ? q : nullptr;
}

bool holdsDropped(const Quad& q, const Quadtree& tree, const Scene& scene, const std::vector<ElementRef>& dropped) {
    for (const ElementRef& d : dropped) {
        // The root curve, or the procedural curves it expands to now (their profiles were
        // dropped with it; one it expanded to before the edit left the quad with the edit).
        const LayerId l = d.layer;
        if (q.layers.size() <= l) continue;
        const auto& curves = q.layers[l].curves;
        if (curves.count(d.id) > 0) return true;
        for (AncestorId a : tree.expansionOf(l, d.id))
            if (curves.count(a) > 0) return true;
        // A river area's heights follow its river's profiles (the axial curve and the river
        // on through the area), which need not be in the quad: any river area there is redone.
        if (scene.layers[l].kind == LayerKind::Rivers && !q.layers[l].areas.empty()) return true;
    }
    return false;
}

}  // namespace lacet
