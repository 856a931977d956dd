#include "editor/cache_fit.h"

#include <algorithm>
#include <queue>
#include <tuple>
#include <unordered_set>

#include "editor/quad_forest.h"

namespace lacet {
namespace {

// Farthest first, then by level and position: a strict order, so the result does not depend on
// where the quads lie in memory.
using Rank = std::tuple<double, int, std::uint32_t, std::uint32_t>;
Rank rankOf(const Quad& q, glm::dvec3 viewer) { return {Quadtree::viewDistance(q, viewer), q.level, q.tx, q.ty}; }

}  // namespace

CacheFit fitToCache(std::span<const Quad* const> leaves, std::size_t capacity, glm::dvec3 viewer,
                    const std::function<bool(const Quad&)>& hasTile, const QuadForest* forest) {
    const auto parentOf = [&](const Quad* q) { return forest ? forest->parentOf(*q) : q->parent; };
    const auto child = [&](const std::unique_ptr<Quad>& c) -> const Quad* { return forest && c ? &forest->resolve(*c) : c.get(); };
    std::unordered_set<const Quad*> shown(leaves.begin(), leaves.end()), ancestors;
    CacheFit fit;
    fit.kept = shown.size();
    for (const Quad* q : leaves)
        for (const Quad* a = parentOf(q); a && ancestors.insert(a).second; a = parentOf(a)) fit.kept += hasTile(*a);
    if (fit.kept <= capacity) {
        fit.shown.assign(leaves.begin(), leaves.end());
        return fit;
    }
    // Candidates, farthest first: the parents of shown quads. A candidate stands in for its
    // children when none of them is an ancestor of a shown quad (each is shown or not needed);
    // that is checked when it is taken, and its parent becomes a candidate after it.
    std::priority_queue<std::pair<Rank, const Quad*>> candidates;
    std::unordered_set<const Quad*> queued;
    const auto offer = [&](const Quad* p) {
        if (p && queued.insert(p).second) candidates.push({rankOf(*p, viewer), p});
    };
    for (const Quad* q : leaves) offer(parentOf(q));
    while (fit.kept > capacity && !candidates.empty()) {
        const Quad* p = candidates.top().second;
        candidates.pop();
        queued.erase(p);
        if (!ancestors.count(p)) continue;
        const bool standsIn = std::none_of(p->children.begin(), p->children.end(),
                                           [&](const auto& c) { return c && ancestors.count(child(c)); });
        if (!standsIn) continue;  // offered again when one of its children stands in
        // Its tile, if not kept already, for its shown children (at least one): a single child and
        // no tile gains nothing here, but lets the quads above stand in.
        std::size_t children = 0;
        for (const auto& c : p->children)
            if (c) children += shown.erase(child(c));
        fit.kept = fit.kept - children + (hasTile(*p) ? 0 : 1);
        ancestors.erase(p);
        shown.insert(p);
        offer(parentOf(p));
    }
    for (const Quad* q : leaves)
        if (!shown.count(q)) fit.replaced.push_back(q);
    fit.shown.assign(shown.begin(), shown.end());
    std::sort(fit.shown.begin(), fit.shown.end(), [&](const Quad* a, const Quad* b) { return rankOf(*a, viewer) < rankOf(*b, viewer); });
    return fit;
}

}  // namespace lacet
