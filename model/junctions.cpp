#include "model/junctions.h"

#include <algorithm>
#include <limits>

#include <glm/geometric.hpp>

namespace lacet {
namespace {

// Unit direction in which `c` leaves the node at its start (atStart) or end: towards the first
// vertex that differs from the node (a control point, or the next on-curve vertex). Zero for a
// curve of one repeated point.
Vec2 leavingDirection(const Curve& c, bool atStart) {
    const std::size_t n = c.vertices.size();
    const Vec2 origin = atStart ? c.vertices.front().p : c.vertices.back().p;
    for (std::size_t k = 1; k < n; ++k) {
        const Vec2 d = (atStart ? c.vertices[k].p : c.vertices[n - 1 - k].p) - origin;
        if (d != Vec2(0.0)) return glm::normalize(d);
    }
    return Vec2(0.0);
}

}  // namespace

int nodeDegree(const Layer& layer, ElementId node) {
    return layer.aliveNode(node) ? int(layer.nodes[node].curves.size()) : 0;
}

bool hasStopLine(const Layer& layer, ElementId node, ElementId curve) {
    const int degree = nodeDegree(layer, node);
    if (degree >= 4) return true;
    if (degree != 3) return false;
    // The three curve ends at the node, each with its leaving direction (a closed curve gives two).
    struct End {
        ElementId curve;
        Vec2 dir;
    };
    std::vector<End> ends;
    for (ElementId id : layer.nodes[node].curves) {
        if (std::find_if(ends.begin(), ends.end(), [&](const End& e) { return e.curve == id; }) != ends.end()) continue;
        const Curve& c = layer.curves[id];
        if (c.start == node) ends.push_back({id, leavingDirection(c, true)});
        if (c.end == node) ends.push_back({id, leavingDirection(c, false)});
    }
    if (ends.size() != 3) return false;
    // The most opposite pair is the through road; the third end is the stem. Ties go to the
    // pair of lowest indices, so the choice is deterministic.
    std::size_t stem = 0;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t a = (i + 1) % 3, b = (i + 2) % 3;
        const double d = glm::dot(ends[a].dir, ends[b].dir);
        if (d < best) best = d, stem = i;
    }
    return ends[stem].curve == curve;
}

double junctionRadius(const Layer& layer, ElementId node) {
    if (nodeDegree(layer, node) < 3) return 0.0;
    double w = 0.0;
    for (ElementId id : layer.nodes[node].curves) w = std::max(w, double(layer.curves[id].w));
    return 0.5 * w;
}

}  // namespace lacet
