#pragma once
// The quads the live loop makes tiles of (editor/tile_loop.h), and the tree and curve data each
// one's tiles are made from: one quadtree over the whole scene (WholeTree), or, for a scene read
// lazily (§7, vector data out of core; editor/lazy_forest.h), a tree over the levels above the
// parts and one tree per part read, each refined below its part's quad.
//
// The forest is walked from root() as a quadtree, each quad reached through resolve(): a quad
// stands for itself, or, where a part is loaded, the part tree's quad of the same level and
// position stands for it with its own subtree. Keys (level, x, y) are the same in every tree, and
// so are bounds; a quad's parent chain is its own tree's (the same keys above it).

#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "editor/draw_plan.h"
#include "model/curve_data.h"
#include "model/quadtree.h"
#include "model/view_params.h"
#include "model/work_clock.h"

namespace lacet {

class QuadForest {
public:
    virtual ~QuadForest() = default;
    virtual const Quad& root() const = 0;
    // The quad whose subtree and data stand for q (q itself where no part replaces it).
    virtual const Quad& resolve(const Quad& q) const { return q; }
    // The parent of resolved quad q in the forest (its own tree's, except a part's quad, whose
    // parent is the top tree's).
    virtual const Quad* parentOf(const Quad& q) const { return q.parent; }
    // The tree (its ancestors and procedural curves) and curve data a resolved quad is made from.
    virtual const Quadtree& treeOf(const Quad& q) const = 0;
    virtual const CurveDataCache& dataOf(const Quad& q) const = 0;
    // Refines for `viewers` (Quadtree::refineForViewers, the children from `maker` when given);
    // false when a subdivision was deferred.
    virtual bool refine(std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                        ChildMaker* maker = nullptr) = 0;
    // Whether refine(viewers, view) keeps resolved quad q (a thread may go on reading it): every
    // quad above it in its tree is wanted by a viewer, so none is merged.
    virtual bool keeps(const Quad& q, std::span<const glm::dvec3> viewers, const ViewParams& view) const;
    // Whether the forest holds what the appearance of resolved quad q is made from (false: the
    // levels above a lazy scene's parts read without it, whose appearance only a pyramid gives).
    virtual bool holdsAppearance(const Quad&) const { return true; }
    // Quads whose vector data arrived since the last call (a part read): tiles made of them before
    // are made again.
    virtual std::vector<QuadKey> takeArrived() { return {}; }
};

// The forest of one quadtree over the whole scene (both must outlive it).
class WholeTree final : public QuadForest {
public:
    WholeTree(Quadtree& tree, const CurveDataCache& data) : tree_(tree), data_(data) {}
    const Quad& root() const override { return tree_.root(); }
    const Quadtree& treeOf(const Quad&) const override { return tree_; }
    const CurveDataCache& dataOf(const Quad&) const override { return data_; }
    bool refine(std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                ChildMaker* maker = nullptr) override {
        return tree_.refineForViewers(viewers, view, deadline, maker);
    }

private:
    Quadtree& tree_;
    const CurveDataCache& data_;
};

// Every quad of the forest, parents before children, each resolved.
template <class F>
void forEachQuad(const QuadForest& forest, F&& f) {
    auto visit = [&](const Quad& q, const auto& self) -> void {
        f(q);
        if (!q.isLeaf())
            for (const auto& c : q.children) self(forest.resolve(*c), self);
    };
    visit(forest.resolve(forest.root()), visit);
}

// Whether quad q of `tree` (over `scene`) holds a curve whose z-profile was `dropped` (after an
// edit: CurveDataCache::invalidate): the root curve, or a procedural curve it expands to now, or,
// for a river, any river area (its heights follow its river's profiles, which need not be in q).
bool holdsDropped(const Quad& q, const Quadtree& tree, const Scene& scene, const std::vector<ElementRef>& dropped);

// The (resolved) quad of the forest with `key`; nullptr when the forest has none.
const Quad* findQuad(const QuadForest& forest, const QuadKey& key);

}  // namespace lacet
