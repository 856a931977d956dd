#include "model/bezier.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace lacet {
namespace {

// Below this squared length (m^2) a derivative is treated as vanished when picking a tangent
// direction: far under any coordinate resolution of the model (1e-12 m).
constexpr double kVanishingSquared = 1e-24;
// Subdivision depth after which arcLength and distanceTo stop refining (2^-30 of the piece).
constexpr int kMaxSubdivisionDepth = 30;

Vec2 lerp(Vec2 a, Vec2 b, double t) { return a + (b - a) * t; }

// Control points of the hodograph (derivative curve), degree-1 of them.
std::array<Vec2, 3> hodograph(const BezierPiece& b) {
    std::array<Vec2, 3> d{};
    for (int i = 0; i < b.degree; ++i) d[i] = (b.p[i + 1] - b.p[i]) * double(b.degree);
    return d;
}

// Roots in (0, 1) of the derivative of one coordinate of the piece.
void derivativeRoots(const BezierPiece& b, int axis, std::vector<double>& out) {
    if (b.degree == 2) {
        const double a = b.p[0][axis] - 2.0 * b.p[1][axis] + b.p[2][axis];
        if (a != 0.0) {
            const double t = (b.p[0][axis] - b.p[1][axis]) / a;
            if (t > 0.0 && t < 1.0) out.push_back(t);
        }
    } else if (b.degree == 3) {
        // B'(t)/3 = a t^2 + 2 bq t + c, from the hodograph d0, d1, d2.
        const double d0 = b.p[1][axis] - b.p[0][axis];
        const double d1 = b.p[2][axis] - b.p[1][axis];
        const double d2 = b.p[3][axis] - b.p[2][axis];
        const double a = d0 - 2.0 * d1 + d2;
        const double bq = d1 - d0;
        const double c = d0;
        if (a == 0.0) {
            if (bq != 0.0) {
                const double t = -c / (2.0 * bq);
                if (t > 0.0 && t < 1.0) out.push_back(t);
            }
            return;
        }
        const double disc = bq * bq - a * c;
        if (disc < 0.0) return;
        const double s = std::sqrt(disc);
        // Numerically stable pair of roots.
        const double q = -(bq + std::copysign(s, bq));
        const double r1 = q / a;
        const double r2 = q != 0.0 ? c / q : r1;
        for (double t : {r1, r2})
            if (t > 0.0 && t < 1.0) out.push_back(t);
    }
}

void arcLengthRec(const BezierPiece& b, double tolerance, int depth, double& sum) {
    double polygon = 0.0;
    for (int i = 0; i < b.degree; ++i) polygon += glm::length(b.p[i + 1] - b.p[i]);
    const double chord = glm::length(b.end() - b.start());
    if (polygon - chord <= tolerance || depth >= kMaxSubdivisionDepth) {
        // Gravesen's estimate: weighted mean of chord and polygon lengths.
        sum += (2.0 * chord + double(b.degree - 1) * polygon) / double(b.degree + 1);
        return;
    }
    auto [l, r] = splitHalf(b);
    arcLengthRec(l, tolerance * 0.5, depth + 1, sum);
    arcLengthRec(r, tolerance * 0.5, depth + 1, sum);
}

void distanceRec(const BezierPiece& b, Vec2 q, double tolerance, int depth, double& best) {
    if (controlBounds(b).distanceTo(q) >= best) return;
    const double flat = flatness(b);
    const double chordDistance = distanceToSegment(q, b.start(), b.end());
    best = std::min(best, std::min(glm::length(q - b.start()), glm::length(q - b.end())));
    if (flat <= tolerance || depth >= kMaxSubdivisionDepth) {
        // The curve is within `flat` of its chord.
        best = std::min(best, std::max(chordDistance - flat, 0.0) + flat);
        return;
    }
    auto [l, r] = splitHalf(b);
    distanceRec(l, q, tolerance, depth + 1, best);
    distanceRec(r, q, tolerance, depth + 1, best);
}

}  // namespace

BezierPiece BezierPiece::reversed() const {
    BezierPiece r;
    r.degree = degree;
    for (int i = 0; i <= degree; ++i) r.p[i] = p[degree - i];
    return r;
}

Vec2 evaluate(const BezierPiece& b, double t) {
    std::array<Vec2, 4> q = b.p;
    for (int level = b.degree; level > 0; --level)
        for (int i = 0; i < level; ++i) q[i] = lerp(q[i], q[i + 1], t);
    return q[0];
}

Vec2 derivative(const BezierPiece& b, double t) {
    auto d = hodograph(b);
    for (int level = b.degree - 1; level > 0; --level)
        for (int i = 0; i < level; ++i) d[i] = lerp(d[i], d[i + 1], t);
    return d[0];
}

Vec2 unitTangent(const BezierPiece& b, double t) {
    // Near a zero of B' at t0, B'(s) ~ B''(t0) (s - t0): the curve leaves along +B'' and arrives
    // along -B''. Where B'' vanishes too (three coincident cubic controls), B' ~ B''' (s - t0)^2 / 2.
    Vec2 d = derivative(b, t);
    if (glm::dot(d, d) <= kVanishingSquared && b.degree >= 2) {
        const auto h = hodograph(b);
        const Vec2 dd0 = (h[1] - h[0]) * double(b.degree - 1);
        const Vec2 dd1 = b.degree == 3 ? (h[2] - h[1]) * 2.0 : dd0;
        d = lerp(dd0, dd1, t) * (t >= 1.0 ? -1.0 : 1.0);
        if (glm::dot(d, d) <= kVanishingSquared && b.degree == 3) d = dd1 - dd0;
    }
    if (glm::dot(d, d) <= kVanishingSquared) d = b.end() - b.start();
    if (glm::dot(d, d) <= kVanishingSquared) return Vec2(0.0);
    return d / glm::length(d);
}

std::pair<BezierPiece, BezierPiece> split(const BezierPiece& b, double t) {
    BezierPiece left, right;
    left.degree = right.degree = b.degree;
    std::array<Vec2, 4> q = b.p;
    left.p[0] = q[0];
    right.p[b.degree] = q[b.degree];
    for (int level = b.degree; level > 0; --level) {
        for (int i = 0; i < level; ++i) q[i] = lerp(q[i], q[i + 1], t);
        left.p[b.degree - level + 1] = q[0];
        right.p[level - 1] = q[level - 1];
    }
    return {left, right};
}

std::pair<BezierPiece, BezierPiece> splitHalf(const BezierPiece& b) {
    BezierPiece left, right;
    left.degree = right.degree = b.degree;
    std::array<Vec2, 4> q = b.p;
    left.p[0] = q[0];
    right.p[b.degree] = q[b.degree];
    for (int level = b.degree; level > 0; --level) {
        for (int i = 0; i < level; ++i) q[i] = (q[i] + q[i + 1]) * 0.5;
        left.p[b.degree - level + 1] = q[0];
        right.p[level - 1] = q[level - 1];
    }
    return {left, right};
}

Box controlBounds(const BezierPiece& b) {
    Box box{b.p[0], b.p[0]};
    for (int i = 1; i <= b.degree; ++i) {
        box.min = glm::min(box.min, b.p[i]);
        box.max = glm::max(box.max, b.p[i]);
    }
    return box;
}

Box tightBounds(const BezierPiece& b) {
    Box box{glm::min(b.start(), b.end()), glm::max(b.start(), b.end())};
    std::vector<double> roots;
    roots.reserve(4);
    for (int axis = 0; axis < 2; ++axis) {
        roots.clear();
        derivativeRoots(b, axis, roots);
        for (double t : roots) {
            const double v = evaluate(b, t)[axis];
            box.min[axis] = std::min(box.min[axis], v);
            box.max[axis] = std::max(box.max[axis], v);
        }
    }
    // Evaluation rounding must never make the box smaller than the true curve's: the tight box
    // never exceeds the control box, and is widened by the rounding bound of evaluate().
    const Box cb = controlBounds(b);
    const Vec2 slack = (glm::abs(cb.min) + glm::abs(cb.max)) * (8.0 * std::numeric_limits<double>::epsilon());
    box.min = glm::max(box.min - slack, cb.min);
    box.max = glm::min(box.max + slack, cb.max);
    return box;
}

double flatness(const BezierPiece& b) {
    double d = 0.0;
    for (int i = 1; i < b.degree; ++i) d = std::max(d, distanceToSegment(b.p[i], b.start(), b.end()));
    return d;
}

double arcLength(const BezierPiece& b, double tolerance) {
    double sum = 0.0;
    arcLengthRec(b, tolerance, 0, sum);
    return sum;
}

double distanceTo(const BezierPiece& b, Vec2 q, double tolerance) {
    double best = std::numeric_limits<double>::infinity();
    distanceRec(b, q, tolerance, 0, best);
    return best;
}

}  // namespace lacet
