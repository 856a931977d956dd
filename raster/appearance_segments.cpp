#include "raster/appearance_segments.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "model/segment.h"

namespace lacet::appearance {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Lower bound of the distance from any point of `box` to the segment: the distance from the
// segment's bounding box to `box`.
double lowerBound(const Segment& sg, const Box& box) {
    const Vec2 lo = glm::min(sg.p0, sg.p1), hi = glm::max(sg.p0, sg.p1);
    const Vec2 gap = glm::max(glm::max(box.min - hi, lo - box.max), Vec2(0.0));
    return glm::length(gap);
}

// A segment with an infinite end would pass the lower bound (its box reaches everywhere) and,
// its distances being NaN, leave an upper bound of 0 that prunes every other segment.
bool finiteSegment(const Segment& sg) {
    return std::isfinite(sg.p0.x) && std::isfinite(sg.p0.y) && std::isfinite(sg.p1.x) && std::isfinite(sg.p1.y);
}

}  // namespace

std::vector<Segment> segmentsOf(const std::vector<ClippedCurve>& pieces, const CurveDataCache* data, LayerId l, AncestorId a) {
    std::vector<Segment> out;
    for (const ClippedCurve& run : pieces) {
        Vec2 prev{};
        double prevU = 0.0;
        std::size_t k = 0;
        const std::size_t first = out.size();
        for (const Vertex& vx : run.vertices) {
            if (!vx.onCurve) continue;
            const double u = data ? data->u(l, a, run.s[k]) : 0.0;
            if (k > 0) out.push_back({prev, vx.p, prevU, u});
            prev = vx.p;
            prevU = u;
            ++k;
        }
        if (out.size() > first) {
            out[first].startCap = run.startsAtNode;
            out.back().endCap = run.endsAtNode;
        }
    }
    return out;
}

double candidatesNear(const std::vector<Segment>& segments, const Box& box, double reach,
                      std::vector<const Segment*>& out) {
    out.clear();
    for (const Segment& sg : segments)
        if (finiteSegment(sg) && lowerBound(sg, box) <= reach) out.push_back(&sg);
    if (out.empty()) return kInfinity;
    // The least upper bound among those in reach bounds the nearest distance at every point of
    // the box (if that is within reach at all).
    const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, {box.min.x, box.max.y}, box.max};
    double upper = kInfinity;
    for (const Segment* sg : out) {
        double farthest = 0.0;
        for (const Vec2& c : corners) farthest = std::max(farthest, distanceToSegment(c, sg->p0, sg->p1));
        upper = std::min(upper, farthest);
    }
    double nearest = kInfinity;
    std::size_t kept = 0;
    for (const Segment* sg : out) {
        const double lower = lowerBound(*sg, box);
        if (lower > upper) continue;
        out[kept++] = sg;
        nearest = std::min(nearest, lower);
    }
    out.resize(kept);
    return nearest;
}

}  // namespace lacet::appearance
