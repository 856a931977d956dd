#pragma once
// Small hand-made scenes (64 x 64 m) for the appearance tests and golden images: junctions with
// stop lines, a river under a road, a lake with an island, a hairpin, fields and a forest.
// Layers in the synthetic order: roads, rivers, lakes, fields, forests.

#include <cmath>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "model/graph.h"
#include "synth/synthetic_scene.h"

namespace lacet::test {

class SceneBuilder {
public:
    explicit SceneBuilder(double side) {
        s_.extent = {{0.0, 0.0}, {side, side}};
        const std::pair<const char*, LayerKind> layers[] = {{"roads", LayerKind::Roads},
                                                             {"rivers", LayerKind::Rivers},
                                                             {"lakes", LayerKind::Lakes},
                                                             {"fields", LayerKind::Fields},
                                                             {"forests", LayerKind::Forests}};
        for (const auto& [name, kind] : layers) {
            s_.layers.emplace_back();
            s_.layers.back().name = name;
            s_.layers.back().kind = kind;
        }
    }
    ElementId node(LayerId l, Vec2 p) { return s_.layers[l].addNode(p); }
    // A curve from node a to node b through `inner` vertices (controls unless marked on-curve).
    ElementId curve(LayerId l, ElementId a, ElementId b, std::vector<Vertex> inner, float w, float wf, std::uint16_t cls = 0) {
        Layer& layer = s_.layers[l];
        Curve c;
        c.vertices.push_back({layer.nodes[a].p, true});
        for (const Vertex& v : inner) c.vertices.push_back(v);
        c.vertices.push_back({layer.nodes[b].p, true});
        c.start = a;
        c.end = b;
        c.w = w;
        c.wf = wf;
        c.cls = cls;
        return layer.addCurve(std::move(c));
    }
    static Vertex control(Vec2 p) { return {p, false}; }
    static Vertex corner(Vec2 p) { return {p, true}; }
    // A circle of radius r made of 4 cubic curves, as an area loop.
    std::vector<AreaEdge> circle(LayerId l, Vec2 c, double r) {
        const double k = 4.0 / 3.0 * std::tan(std::numbers::pi / 8.0) * r;
        ElementId n[4];
        Vec2 p[4], t[4];
        for (int i = 0; i < 4; ++i) {
            const double a = i * std::numbers::pi / 2.0;
            p[i] = c + r * Vec2(std::cos(a), std::sin(a));
            t[i] = Vec2(-std::sin(a), std::cos(a));
            n[i] = node(l, p[i]);
        }
        std::vector<AreaEdge> loop;
        for (int i = 0; i < 4; ++i) {
            const int j = (i + 1) % 4;
            loop.push_back({curve(l, n[i], n[j], {control(p[i] + t[i] * k), control(p[j] - t[j] * k)}, 0.0f, 0.0f), false});
        }
        return loop;
    }
    ElementId area(LayerId l, std::vector<std::vector<AreaEdge>> loops, float wf, std::uint16_t cls = 0) {
        Area a;
        a.loops = std::move(loops);
        a.wf = wf;
        a.cls = cls;
        return s_.layers[l].addArea(std::move(a));
    }
    Scene& scene() { return s_; }

private:
    Scene s_;
};

// A 4-way junction (stop lines on every road) and a T junction (a stop line on its stem only).
inline Scene junctionsScene() {
    SceneBuilder b(64.0);
    const ElementId x = b.node(kRoadsLayer, {20, 34}), t = b.node(kRoadsLayer, {46, 34});
    const ElementId w = b.node(kRoadsLayer, {0, 33}), n = b.node(kRoadsLayer, {21, 64}), s = b.node(kRoadsLayer, {19, 0});
    const ElementId e = b.node(kRoadsLayer, {64, 35}), stem = b.node(kRoadsLayer, {47, 0});
    b.curve(kRoadsLayer, w, x, {}, 7.0f, 15.0f, 0);
    b.curve(kRoadsLayer, x, t, {}, 7.0f, 15.0f, 0);
    b.curve(kRoadsLayer, t, e, {}, 7.0f, 15.0f, 0);
    b.curve(kRoadsLayer, n, x, {}, 5.0f, 11.0f, 1);
    b.curve(kRoadsLayer, x, s, {}, 5.0f, 11.0f, 1);
    b.curve(kRoadsLayer, t, stem, {SceneBuilder::control({46, 20}), SceneBuilder::control({50, 12})}, 5.0f, 11.0f, 1);
    return std::move(b.scene());
}

// A river flowing under a road (the road is drawn over it), with a tributary joining it.
inline Scene riverUnderRoadScene() {
    SceneBuilder b(64.0);
    const ElementId up = b.node(kRiversLayer, {8, 64}), join = b.node(kRiversLayer, {30, 40}), down = b.node(kRiversLayer, {52, 0});
    const ElementId trib = b.node(kRiversLayer, {64, 60});
    b.curve(kRiversLayer, up, join, {SceneBuilder::control({10, 50}), SceneBuilder::control({20, 44})}, 5.0f, 11.0f);
    b.curve(kRiversLayer, trib, join, {SceneBuilder::control({50, 56})}, 3.0f, 7.0f);
    b.curve(kRiversLayer, join, down, {SceneBuilder::control({40, 36}), SceneBuilder::control({44, 14})}, 8.0f, 14.0f);
    const ElementId w = b.node(kRoadsLayer, {0, 22}), e = b.node(kRoadsLayer, {64, 26});
    b.curve(kRoadsLayer, w, e, {SceneBuilder::control({30, 20})}, 7.0f, 15.0f, 0);
    return std::move(b.scene());
}

// A lake with an island (a hole).
inline Scene lakeIslandScene() {
    SceneBuilder b(64.0);
    auto outer = b.circle(kLakesLayer, {32, 32}, 24.0);
    auto island = b.circle(kLakesLayer, {36, 29}, 7.0);
    b.area(kLakesLayer, {outer, island}, 4.0f);
    return std::move(b.scene());
}

// A hairpin narrower than its road (the inner edge folds over itself) and a sharp V turn.
inline Scene hairpinScene() {
    SceneBuilder b(64.0);
    const ElementId a = b.node(kRoadsLayer, {34, 2}), c = b.node(kRoadsLayer, {44, 2});
    b.curve(kRoadsLayer, a, c, {SceneBuilder::control({34, 66}), SceneBuilder::control({44, 66})}, 5.0f, 11.0f, 1);
    const ElementId d = b.node(kRoadsLayer, {2, 62}), e = b.node(kRoadsLayer, {24, 62});
    b.curve(kRoadsLayer, d, e, {SceneBuilder::corner({12, 6})}, 5.0f, 11.0f, 1);
    return std::move(b.scene());
}

// Four fields sharing their borders, and a forest with a clearing.
inline Scene fieldsScene() {
    SceneBuilder b(64.0);
    ElementId n[3][3];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) n[j][i] = b.node(kFieldsLayer, {3.0 + 15.0 * i + (j == 1 ? 2.0 : 0.0), 3.0 + 15.0 * j});
    ElementId h[3][2], v[2][3];  // horizontal edges h[j][i]: n[j][i] -> n[j][i+1]; vertical v[j][i]: n[j][i] -> n[j+1][i]
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 2; ++i) h[j][i] = b.curve(kFieldsLayer, n[j][i], n[j][i + 1], {}, 0.0f, 1.0f);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) v[j][i] = b.curve(kFieldsLayer, n[j][i], n[j + 1][i], {}, 0.0f, 1.0f);
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i)
            b.area(kFieldsLayer, {{{h[j][i], false}, {v[j][i + 1], false}, {h[j + 1][i], true}, {v[j][i], true}}}, 1.0f,
                   std::uint16_t(j * 2 + i));
    auto outer = b.circle(kForestsLayer, {48, 46}, 14.0);
    auto clearing = b.circle(kForestsLayer, {50, 44}, 4.0);
    b.area(kForestsLayer, {outer, clearing}, 3.0f);
    return std::move(b.scene());
}

struct NamedScene {
    std::string name;
    Scene (*make)();
};
// GoogleTest prints a parameter with this instead of its bytes.
inline void PrintTo(const NamedScene& s, std::ostream* os) { *os << s.name; }
inline const std::vector<NamedScene>& handScenes() {
    static const std::vector<NamedScene> scenes = {{"junctions", junctionsScene},
                                                   {"river_under_road", riverUnderRoadScene},
                                                   {"lake_island", lakeIslandScene},
                                                   {"hairpin", hairpinScene},
                                                   {"fields_forest", fieldsScene}};
    return scenes;
}

}  // namespace lacet::test
