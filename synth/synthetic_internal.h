#pragma once
// Internals of the synthetic scene generator (synth/synthetic_scene.h), shared by
// synthetic_scene.cpp (roads, rivers, driver) and synthetic_areas.cpp (lakes, forests, fields).
// Not a public API. Units: metres.

#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "model/graph.h"

namespace lacet::synth {

// Deterministic random numbers. std::mt19937_64's output is fully specified by the standard;
// doubles come from its top 53 bits and integers from a modulo (std::uniform_*_distribution
// and std::shuffle are implementation-defined, so they are not used).
class Rng {
public:
    explicit Rng(std::uint64_t seed) : g_(seed) {}
    double uniform() { return double(g_() >> 11) * 0x1.0p-53; }  // [0, 1)
    double uniform(double a, double b) { return a + (b - a) * uniform(); }
    std::size_t below(std::size_t n) { return n == 0 ? 0 : std::size_t(g_() % n); }
    bool chance(double p) { return uniform() < p; }

private:
    std::mt19937_64 g_;
};

// Occupancy bits of the coarse grid below.
enum : std::uint8_t {
    kBlocked = 1,    // taken by a river corridor, a lake or a forest: no field or other area here
    kNearRiver = 2,  // close to a river: other river reaches keep away
};

// A coarse square grid over the extent (cells of 10..50 m) marking taken ground, so that
// areas and rivers avoid each other approximately (conservatively: a box touching a marked
// cell counts as taken).
class Occupancy {
public:
    explicit Occupancy(double side);
    double cell() const { return cell_; }
    bool any(const Box& b, std::uint8_t bits) const;
    void mark(const Box& b, std::uint8_t bits);
    // Marks the cells whose centre lies in the axis-aligned ellipse (centre c, radii r) grown
    // by one cell.
    void markEllipse(Vec2 c, Vec2 r, std::uint8_t bits);
    // Fraction of the cells touching b that have none of `bits`.
    double freeFraction(const Box& b, std::uint8_t bits) const;

private:
    std::size_t index(double x) const;
    double cell_;
    std::size_t n_;
    std::vector<std::uint8_t> bits_;
};

struct Context {
    double side = 0.0;        // extent [0, side]^2
    std::size_t target = 0;   // target curve count of the whole scene
    Occupancy occ;
    std::vector<Box> blocks;  // road-free rectangles (between roads), where areas go
};

inline Vec2 direction(double angle) { return {std::cos(angle), std::sin(angle)}; }
inline Vec2 perp(Vec2 v) { return {-v.y, v.x}; }
inline Vertex onCurve(Vec2 p) { return {p, true, false}; }
inline Vertex control(Vec2 p) { return {p, false, false}; }

// Appends the vertices of `b` after its start (which the chain already ends with).
inline void appendPiece(std::vector<Vertex>& v, const BezierPiece& b) {
    for (int i = 1; i < b.degree; ++i) v.push_back(control(b.p[i]));
    v.push_back(onCurve(b.p[b.degree]));
}

inline Curve makeCurve(std::vector<Vertex> v, ElementId start, ElementId end, float w, float wf,
                       std::uint16_t cls, std::size_t areaSlots) {
    Curve c;
    c.vertices = std::move(v);
    c.start = start;
    c.end = end;
    c.w = w;
    c.wf = wf;
    c.cls = cls;
    c.areas.reserve(areaSlots);
    return c;
}

// Adds a node that will have `degree` adjacent curves (reserved, so that adjacency lists are
// allocated once at their final size).
inline ElementId addNode(Layer& layer, Vec2 p, std::size_t degree) {
    const ElementId id = layer.addNode(p);
    layer.nodes[id].curves.reserve(degree);
    return id;
}

void buildRoads(Layer& layer, Context& ctx, Rng& rng);
void buildRivers(Layer& layer, Context& ctx, Rng& rng);
void buildLakes(Layer& layer, Context& ctx, Rng& rng);
void buildForests(Layer& layer, Context& ctx, Rng& rng);
// Makes field patches with at most `curveBudget` curves in total (fewer only when space runs out),
// handed to `sink` in parts of whole patches (model/graph.h), a part as soon as it holds
// `partCurves` curves or more, and the rest at the end; nothing when there are no patches.
void buildFields(Context& ctx, Rng& rng, std::size_t curveBudget, std::size_t partCurves,
                 const std::function<void(Layer&& part)>& sink);

}  // namespace lacet::synth
