#pragma once
// A procedural step for the tests of the hook (Alg. 4.1).
#include "model/quadtree.h"

namespace lacet::test {

// The procedural hook under test: every road becomes two procedural curves, split at its middle.
class SplitRoadsInTwo : public ProceduralStep {
public:
    bool expand(const Scene& s, LayerId l, ElementId id, std::vector<ProceduralCurve>& out) const override {
        if (s.layers[l].kind != LayerKind::Roads) return false;
        const Curve& c = s.layers[l].curves[id];
        BezierPiece first;
        std::size_t firstEnd = 0;
        forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t i) {
            if (i == 0) {
                first = b;
                firstEnd = std::size_t(b.degree);
            }
        });
        const auto [a, b] = splitHalf(first);
        Curve left = c, right = c;
        left.vertices.clear();
        right.vertices.clear();
        for (int k = 0; k <= a.degree; ++k) left.vertices.push_back({a.p[k], k == 0 || k == a.degree});
        for (int k = 0; k <= b.degree; ++k) right.vertices.push_back({b.p[k], k == 0 || k == b.degree});
        right.vertices.insert(right.vertices.end(), c.vertices.begin() + std::ptrdiff_t(firstEnd) + 1, c.vertices.end());
        left.end = kNoElement;
        right.start = kNoElement;
        out = {{.curve = left}, {.curve = right}};
        return true;
    }
};

// Every road's polyline of on-curve vertices cut into `perSegment` straight procedural curves
// per segment (k in segment order), the first starting at the road's start node and the last
// ending at its end node.
class CutRoadsIntoSegments : public ProceduralStep {
public:
    explicit CutRoadsIntoSegments(int perSegment) : perSegment_(perSegment) {}
    bool expand(const Scene& s, LayerId l, ElementId id, std::vector<ProceduralCurve>& out) const override {
        if (s.layers[l].kind != LayerKind::Roads) return false;
        const Curve& c = s.layers[l].curves[id];
        std::vector<Vec2> on;
        for (const Vertex& v : c.vertices)
            if (v.onCurve) on.push_back(v.p);
        out.clear();
        for (std::size_t i = 0; i + 1 < on.size(); ++i)
            for (int j = 0; j < perSegment_; ++j) {
                Curve piece = c;
                piece.vertices = {{on[i] + (on[i + 1] - on[i]) * (double(j) / perSegment_)},
                                  {on[i] + (on[i + 1] - on[i]) * (double(j + 1) / perSegment_)}};
                piece.start = out.empty() ? c.start : kNoElement;
                piece.end = kNoElement;
                out.push_back({.curve = std::move(piece)});
            }
        if (!out.empty()) out.back().curve.end = c.end;
        return true;
    }

private:
    int perSegment_;
};

}  // namespace lacet::test
