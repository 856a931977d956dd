#pragma once
// Which quads a frame shows within the tile cache's capacity (§9.1 of the paper: "we use the
// texture of a quad instead of the textures of its 4 subquads, so as to never exceed the cache
// capacity"). The session keeps the tiles of the quads it shows and of their ancestors (what the
// window draws while a quad's own tile is being made); when the view's leaves and their ancestors
// are more than the cache holds, the farthest quads are shown instead of their children.

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "model/quadtree.h"

namespace lacet {

struct CacheFit {
    std::vector<const Quad*> shown;     // the leaves given, or ancestors standing for some of them
    std::vector<const Quad*> replaced;  // the leaves given that an ancestor stands for
    std::size_t kept = 0;               // shown quads and their ancestors that have tiles: the tiles kept
};

// The quads to show for `leaves` (distinct quads of one tree, none above another: those the view
// needs) within `capacity` tiles, counting each shown quad and each ancestor of one that
// `hasTile`. When they fit, the leaves are shown. Otherwise, farthest from `viewer` first
// (Quadtree::viewDistance), a quad whose shown descendants are all its children is shown in their
// place, until the count fits: with the root alone shown, one tile is kept, so `kept` exceeds
// the capacity only when that is 0.
// With a `forest` (editor/quad_forest.h: a scene read lazily), the quads' parents and children are
// the forest's (QuadForest::parentOf, resolve), not those of the tree each quad is in.
class QuadForest;
CacheFit fitToCache(std::span<const Quad* const> leaves, std::size_t capacity, glm::dvec3 viewer,
                    const std::function<bool(const Quad&)>& hasTile, const QuadForest* forest = nullptr);

}  // namespace lacet
