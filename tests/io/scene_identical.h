// Two scene documents compared field by field, doubles and floats by their bits: what a save then a
// load, or two ways of making one scene, must give. Shared by the scene file and feature table tests.
#pragma once

#include <string>

#include <gtest/gtest.h>

#include "io/scene_file.h"
#include "tests/same_bits.h"

namespace lacet {

// Every field, doubles and floats by bit pattern; names the first difference.
inline ::testing::AssertionResult identical(const SceneDocument& x, const SceneDocument& y) {
    auto differ = [](const std::string& what) { return ::testing::AssertionFailure() << what << " differs"; };
    const Scene& a = x.scene;
    const Scene& b = y.scene;
    if (!sameBits(a.extent, b.extent)) return differ("extent");
    if (a.layers.size() != b.layers.size()) return differ("layer count");
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer& p = a.layers[l];
        const Layer& q = b.layers[l];
        const std::string at = "layer " + std::to_string(l) + " ";
        if (p.name != q.name || p.kind != q.kind) return differ(at + "name or kind");
        if (p.nodes.size() != q.nodes.size() || p.curves.size() != q.curves.size() || p.areas.size() != q.areas.size())
            return differ(at + "element count");
        for (std::size_t i = 0; i < p.nodes.size(); ++i)
            if (!sameBits(p.nodes[i].p, q.nodes[i].p) || p.nodes[i].curves != q.nodes[i].curves ||
                p.nodes[i].alive != q.nodes[i].alive || !sameBits(p.nodes[i].roundabout, q.nodes[i].roundabout))
                return differ(at + "node " + std::to_string(i));
        for (std::size_t i = 0; i < p.curves.size(); ++i) {
            const Curve& c = p.curves[i];
            const Curve& d = q.curves[i];
            bool same = c.start == d.start && c.end == d.end && sameBits(c.w, d.w) && sameBits(c.wf, d.wf) &&
                        c.cls == d.cls && c.flags == d.flags && c.areas == d.areas && c.alive == d.alive &&
                        c.vertices.size() == d.vertices.size();
            for (std::size_t k = 0; same && k < c.vertices.size(); ++k)
                same = sameBits(c.vertices[k].p, d.vertices[k].p) && c.vertices[k].onCurve == d.vertices[k].onCurve &&
                       c.vertices[k].closing == d.vertices[k].closing;
            if (!same) return differ(at + "curve " + std::to_string(i));
        }
        for (std::size_t i = 0; i < p.areas.size(); ++i) {
            const Area& c = p.areas[i];
            const Area& d = q.areas[i];
            if (c.loops != d.loops || !sameBits(c.wf, d.wf) || c.cls != d.cls || c.axial != d.axial || c.alive != d.alive)
                return differ(at + "area " + std::to_string(i));
        }
    }
    const Georeference& g = x.georeference;
    const Georeference& h = y.georeference;
    if (g.valid != h.valid || !sameBits(g.lon0, h.lon0) || !sameBits(g.lat0, h.lat0) ||
        !sameBits(g.originShift, h.originShift) || g.crsWkt != h.crsWkt)
        return differ("georeference");
    if (x.attributes != y.attributes) return differ("attributes");
    if (x.dem.has_value() != y.dem.has_value()) return differ("DEM presence");
    if (x.dem) {
        if (!sameBits(x.dem->extent(), y.dem->extent()) || x.dem->width() != y.dem->width() ||
            x.dem->height() != y.dem->height())
            return differ("DEM grid");
        for (std::size_t k = 0; k < x.dem->heights().size(); ++k)
            if (!sameBits(x.dem->heights()[k], y.dem->heights()[k])) return differ("DEM height " + std::to_string(k));
    }
    return ::testing::AssertionSuccess();
}

}  // namespace lacet
