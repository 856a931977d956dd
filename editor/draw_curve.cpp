#include "editor/draw_curve.h"

#include <algorithm>
#include <stdexcept>

namespace lacet {

Curve curveThrough(std::span<const Vec2> p, const NewCurveStyle& style) {
    if (p.size() < 2) throw std::invalid_argument("curveThrough(): a curve needs at least 2 points");
    Curve c;
    for (std::size_t k = 0; k + 1 < p.size(); ++k) {
        const Vec2 a = p[k], b = p[k + 1];
        const Vec2 before = k > 0 ? p[k - 1] : a, after = k + 2 < p.size() ? p[k + 2] : b;
        if (k == 0) c.vertices.push_back({a, true, false});
        c.vertices.push_back({a + (b - before) / 6.0, false, false});
        c.vertices.push_back({b - (after - a) / 6.0, false, false});
        c.vertices.push_back({b, true, false});
    }
    c.w = style.width;
    c.wf = std::max(style.footprint, style.width);
    c.cls = std::uint16_t(std::clamp(style.cls, 0, 65535));
    return c;
}

}  // namespace lacet
