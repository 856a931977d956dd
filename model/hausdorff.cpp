#include "model/hausdorff.h"

#include <array>
#include <optional>

#include "model/box_grid.h"

namespace lacet {
namespace {

// A subdivided piece closer than this many halvings to a point cannot be told apart in doubles.
constexpr int kMaxDepth = 48;

// Pieces or segments beyond this count are found through a BoxGrid.
constexpr std::size_t kGridFrom = 16;

// The piece lies within `flat` of its chord and the chord within `flat` of the piece (bezier.h,
// flatness()), so the distance from q lies within `flat` of q's distance to the chord: a lower
// bound that converges quadratically as the piece is halved, and an upper bound.
void boundedDistanceRec(const BezierPiece& b, Vec2 q, double precision, int depth, double& best) {
    const double flat = flatness(b);
    const double chord = distanceToSegment(q, b.start(), b.end());
    if (std::max(chord - flat, 0.0) >= best - precision) return;
    best = std::min(best, chord + flat);
    if (2.0 * flat <= precision || depth >= kMaxDepth) return;
    const auto [l, r] = splitHalf(b);
    // Nearer half first, so that the other is more likely pruned.
    const bool leftFirst = distanceToSegment(q, l.start(), l.end()) <= distanceToSegment(q, r.start(), r.end());
    boundedDistanceRec(leftFirst ? l : r, q, precision, depth + 1, best);
    boundedDistanceRec(leftFirst ? r : l, q, precision, depth + 1, best);
}

// Both directions between pieces and a polyline, brute force with box pruning.
template <class ForEachPiece>
void measure(ForEachPiece&& forEachPiece, std::span<const Vec2> polyline, const HausdorffParams& params, Hausdorff& h) {
    struct BoxedPiece {
        BezierPiece piece;
        Box box;
    };
    std::vector<BoxedPiece> pieces;
    forEachPiece([&](const BezierPiece& b) { pieces.push_back({b, controlBounds(b)}); });
    std::vector<Box> pieceBoxes, segmentBoxes;
    for (const BoxedPiece& p : pieces) pieceBoxes.push_back(p.box);
    for (std::size_t i = 0; i + 1 < polyline.size(); ++i)
        segmentBoxes.push_back({glm::min(polyline[i], polyline[i + 1]), glm::max(polyline[i], polyline[i + 1])});
    // Few items: a loop over all of them is cheaper than a grid.
    std::optional<BoxGrid> pieceGrid, segmentGrid;
    if (pieceBoxes.size() > kGridFrom) pieceGrid.emplace(pieceBoxes);
    if (segmentBoxes.size() > kGridFrom) segmentGrid.emplace(segmentBoxes);
    auto near = [](const std::optional<BoxGrid>& grid, std::size_t count, Vec2 q, const double& best, auto&& visit) {
        if (grid) grid->visitNear(q, best, visit);
        else
            for (std::size_t i = 0; i < count; ++i) visit(i);
    };
    const double oraclePrecision = 0.25 * params.precision;

    auto toPolyline = [&](Vec2 q) {
        Nearest n;
        if (polyline.size() == 1) return Nearest{glm::length(q - polyline[0]), 0, true};
        near(segmentGrid, segmentBoxes.size(), q, n.distance, [&](std::size_t i) {
            if (segmentBoxes[i].distanceTo(q) >= n.distance) return;
            const double d = distanceToSegment(q, polyline[i], polyline[i + 1]);
            if (d < n.distance) n = {d, i, true};
        });
        return n;
    };
    auto toCurve = [&](Vec2 q) {
        Nearest n;
        near(pieceGrid, pieces.size(), q, n.distance, [&](std::size_t i) {
            const BoxedPiece& p = pieces[i];
            if (p.box.distanceTo(q) >= n.distance - oraclePrecision) return;
            double d = std::min({n.distance, glm::length(q - p.piece.start()), glm::length(q - p.piece.end())});
            boundedDistanceRec(p.piece, q, oraclePrecision, 0, d);
            // A line piece is a segment: convex. (boundedDistanceRec is exact on it: flatness 0.)
            if (d < n.distance) n = {d, i, p.piece.degree == 1};
        });
        return n;
    };

    for (const BoxedPiece& p : pieces) maxAlongPiece(p.piece, toPolyline, 0.0, params, h.curveToSource);
    if (polyline.size() == 1) maxAlongSegment(polyline[0], polyline[0], toCurve, oraclePrecision, params, h.sourceToCurve);
    for (std::size_t i = 0; i + 1 < polyline.size(); ++i)
        maxAlongSegment(polyline[i], polyline[i + 1], toCurve, oraclePrecision, params, h.sourceToCurve);
}

}  // namespace

double distanceUpperBound(const BezierPiece& b, Vec2 q, double precision) {
    double best = std::min(glm::length(q - b.start()), glm::length(q - b.end()));
    boundedDistanceRec(b, q, precision, 0, best);
    return best;
}

double speedBound(const BezierPiece& b) {
    // B'(t) = degree * sum of Bernstein-weighted control differences: within their convex hull.
    double s = 0.0;
    for (int i = 0; i < b.degree; ++i) s = std::max(s, glm::length(b.p[i + 1] - b.p[i]));
    return double(b.degree) * s;
}

void addHausdorff(std::span<const Vertex> curve, std::span<const Vec2> polyline, const HausdorffParams& params,
                  Hausdorff& running) {
    measure([&](auto&& add) { forEachPiece(curve, [&](const BezierPiece& b, std::size_t) { add(b); }); }, polyline, params,
            running);
}

Hausdorff hausdorff(std::span<const Vertex> curve, std::span<const Vec2> polyline, const HausdorffParams& params) {
    Hausdorff h;
    addHausdorff(curve, polyline, params, h);
    return h;
}

Hausdorff hausdorff(const BezierPiece& piece, std::span<const Vec2> polyline, const HausdorffParams& params) {
    Hausdorff h;
    measure([&](auto&& add) { add(piece); }, polyline, params, h);
    return h;
}

}  // namespace lacet
