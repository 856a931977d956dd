#include "editor/quad_forest.h"

namespace lacet {

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

}  // namespace lacet
