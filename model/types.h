#pragma once
// Basic value types of the model: positions, element ids, vertices of Bezier splines, boxes.
// All positions are in the scene's projected CRS, in metres, as doubles.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

namespace lacet {

using Vec2 = glm::dvec2;

// Stable id of a root element inside its layer (its slot index; never reused after deletion).
using ElementId = std::uint32_t;
constexpr ElementId kNoElement = 0xffffffffu;

// Id of an ancestor curve (§4.2) in its layer: a root curve's own ElementId, or a procedural
// curve's, made by the procedural step at the root (§4.3), which carries kProceduralBit and its
// root curve's id and index (proceduralId(), model/quadtree.h). 64 bits so that every root curve
// id, whatever the size of the layer, has room for its procedural curves.
using AncestorId = std::uint64_t;
constexpr AncestorId kProceduralBit = AncestorId(1) << 63;

using LayerId = std::uint16_t;

enum class ElementKind : std::uint8_t { Node, Curve, Area };

// A vertex of a Bezier spline: on-curve, or a control point. Between two on-curve vertices lie
// 0, 1 or 2 control points (line, quadratic or cubic piece). `closing` marks, on an on-curve
// vertex of a clipped area loop, that the piece starting there is a closing segment along the
// quad border rather than a piece of a real border curve.
struct Vertex {
    Vec2 p;
    bool onCurve = true;
    bool closing = false;
    friend bool operator==(const Vertex&, const Vertex&) = default;
};

// Axis-aligned box, closed on all sides.
struct Box {
    Vec2 min{0.0};
    Vec2 max{0.0};

    Vec2 size() const { return max - min; }
    Vec2 center() const { return (min + max) * 0.5; }
    Box dilated(double margin) const { return {min - margin, max + margin}; }
    bool intersects(const Box& o) const {
        return min.x <= o.max.x && o.min.x <= max.x && min.y <= o.max.y && o.min.y <= max.y;
    }
    bool contains(Vec2 p) const { return min.x <= p.x && p.x <= max.x && min.y <= p.y && p.y <= max.y; }
    bool contains(const Box& o) const { return contains(o.min) && contains(o.max); }
    // Distance from p to the box (0 inside): a lower bound of the distance to anything in it.
    double distanceTo(Vec2 p) const {
        const double dx = std::max({min.x - p.x, 0.0, p.x - max.x});
        const double dy = std::max({min.y - p.y, 0.0, p.y - max.y});
        return std::sqrt(dx * dx + dy * dy);
    }
    friend bool operator==(const Box&, const Box&) = default;
};

}  // namespace lacet
