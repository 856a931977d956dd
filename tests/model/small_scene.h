#pragma once
// A small hand-made scene for the model tests: a curved road, two fields sharing a border.
#include "model/graph.h"

namespace lacet::test {

inline Scene smallScene() {
    Scene s;
    s.extent = {{0, 0}, {1000, 1000}};
    s.layers.resize(2);
    s.layers[0].name = "roads";
    s.layers[0].kind = LayerKind::Roads;
    Layer& roads = s.layers[0];
    const ElementId a = roads.addNode({100, 100}), b = roads.addNode({900, 120});
    Curve r;
    r.vertices = {{{100, 100}}, {{300, 400}, false}, {{600, -100}, false}, {{900, 120}}};
    r.start = a;
    r.end = b;
    r.w = 6;
    r.wf = 14;
    roads.addCurve(r);
    s.layers[1].name = "fields";
    s.layers[1].kind = LayerKind::Fields;
    Layer& f = s.layers[1];
    ElementId n[6];
    const Vec2 p[6] = {{200, 500}, {400, 500}, {600, 500}, {600, 700}, {400, 700}, {200, 700}};
    for (int i = 0; i < 6; ++i) n[i] = f.addNode(p[i]);
    auto line = [&](int i, int j) {
        Curve c;
        c.vertices = {{p[i]}, {p[j]}};
        c.start = n[i];
        c.end = n[j];
        c.wf = 2;
        return f.addCurve(c);
    };
    const ElementId c01 = line(0, 1), c12 = line(1, 2), c23 = line(2, 3), c34 = line(3, 4), c45 = line(4, 5),
                    c50 = line(5, 0), c14 = line(1, 4);
    Area left, right;
    left.loops = {{{c01, false}, {c14, false}, {c45, false}, {c50, false}}};
    right.loops = {{{c12, false}, {c23, false}, {c34, false}, {c14, true}}};
    left.wf = right.wf = 2;
    f.addArea(left);
    f.addArea(right);
    return s;
}

}  // namespace lacet::test
