#pragma once
// Helpers shared by the model tests: dense sampling of splines and point-in-area tests.

#include <vector>

#include "model/clip_and_refine.h"
#include "model/graph.h"

namespace lacet::test {

// Dense samples of a vertex chain: `perPiece` samples per Bezier piece, plus the last point.
inline std::vector<Vec2> sample(const std::vector<Vertex>& v, int perPiece = 64) {
    std::vector<Vec2> out;
    forEachPiece(v, [&](const BezierPiece& b, std::size_t) {
        for (int i = 0; i < perPiece; ++i) out.push_back(evaluate(b, double(i) / perPiece));
    });
    if (!v.empty()) out.push_back(v.back().p);
    return out;
}

// Even-odd test against closed polylines.
inline bool insidePolylines(const std::vector<std::vector<Vec2>>& rings, Vec2 q) {
    bool inside = false;
    for (const auto& r : rings)
        for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
            if ((r[i].y > q.y) != (r[j].y > q.y) && q.x < (r[j].x - r[i].x) * (q.y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
                inside = !inside;
    return inside;
}

inline bool insideClipped(const std::vector<ClippedArea>& pieces, Vec2 q) {
    for (const auto& a : pieces) {
        std::vector<std::vector<Vec2>> rings;
        for (const auto& l : a.loops) rings.push_back(sample(l.vertices, 32));
        if (insidePolylines(rings, q)) return true;
    }
    return false;
}

// Distance from q to the nearest sample of any ring.
inline double distanceToRings(const std::vector<std::vector<Vec2>>& rings, Vec2 q) {
    double d = 1e300;
    for (const auto& r : rings)
        for (std::size_t i = 0; i + 1 < r.size(); ++i) d = std::min(d, distanceToSegment(q, r[i], r[i + 1]));
    return d;
}

}  // namespace lacet::test
