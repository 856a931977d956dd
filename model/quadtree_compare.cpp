#include "model/quadtree_compare.h"

#include <bit>
#include <cstdint>

namespace lacet {
namespace {

std::string quadName(const Quad& q) {
    return "quad L" + std::to_string(q.level) + " (" + std::to_string(q.tx) + "," + std::to_string(q.ty) + ")";
}

bool sameBits(Vec2 a, Vec2 b) {
    return std::bit_cast<std::uint64_t>(a.x) == std::bit_cast<std::uint64_t>(b.x) &&
           std::bit_cast<std::uint64_t>(a.y) == std::bit_cast<std::uint64_t>(b.y);
}

bool samePieces(const std::vector<ClippedCurve>& a, const std::vector<ClippedCurve>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!identical(a[i], b[i])) return false;
    return true;
}

bool samePieces(const std::vector<ClippedArea>& a, const std::vector<ClippedArea>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!identical(a[i], b[i])) return false;
    return true;
}

bool sameValue(Vec2 a, Vec2 b) { return sameBits(a, b); }
template <class T>
bool sameValue(const std::vector<T>& a, const std::vector<T>& b) { return samePieces(a, b); }

class Comparer {
public:
    explicit Comparer(std::size_t maxDetails) : maxDetails_(maxDetails) {}

    void quad(const Quad& a, const Quad& b, bool recurse = true) {
        ++diff.quadsCompared;
        if (recurse && a.isLeaf() != b.isLeaf()) report(quadName(a) + ": subdivided in one tree only");
        if (a.layers.size() != b.layers.size()) report(quadName(a) + ": different layer counts");
        for (std::size_t l = 0; l < std::min(a.layers.size(), b.layers.size()); ++l) {
            const std::string where = quadName(a) + " layer " + std::to_string(l);
            map(a.layers[l].nodes, b.layers[l].nodes, where + " node");
            map(a.layers[l].curves, b.layers[l].curves, where + " curve");
            map(a.layers[l].areas, b.layers[l].areas, where + " area");
        }
        if (!recurse || a.isLeaf() || b.isLeaf()) return;
        for (int k = 0; k < 4; ++k) quad(*a.children[k], *b.children[k]);
    }

    QuadtreeDiff diff;

private:
    template <class Map>
    void map(const Map& a, const Map& b, const std::string& what) {
        for (const auto& [id, value] : a) {
            const auto it = b.find(id);
            if (it == b.end()) report(what + " ancestor " + std::to_string(id) + ": only in the first tree");
            else if (!sameValue(value, it->second)) report(what + " ancestor " + std::to_string(id) + ": pieces differ");
        }
        for (const auto& [id, value] : b)
            if (!a.count(id)) report(what + " ancestor " + std::to_string(id) + ": only in the second tree");
    }

    void report(std::string s) {
        ++diff.mismatches;
        if (diff.details.size() < maxDetails_) diff.details.push_back(std::move(s));
    }

    std::size_t maxDetails_;
};

}  // namespace

QuadtreeDiff compareQuadtrees(const Quadtree& a, const Quadtree& b, std::size_t maxDetails) {
    Comparer c(maxDetails);
    c.quad(a.root(), b.root());
    return c.diff;
}

QuadtreeDiff compareQuads(const Quad& a, const Quad& b, std::size_t maxDetails) {
    Comparer c(maxDetails);
    c.quad(a, b, false);
    return c.diff;
}

}  // namespace lacet
