#include "raster/bridge_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "model/curve_data.h"
#include "model/edits.h"
#include "raster/elevation_producer.h"

namespace lacet {
namespace {

// A scene's tree, curve data and the elevation tiles of one level made on demand.
struct Terrain {
    GraphStep step;
    Quadtree qt;
    const DemSource& dem;
    CurveDataCache data;
    int level;
    std::map<std::pair<std::uint32_t, std::uint32_t>, ElevationTile> tiles;
    Terrain(const Scene& s, const DemSource& d, const BridgeCheckParams& p)
        : step(s, p.graph), qt(s, {}, &step), dem(d), data(qt, d.heights()), level(p.level) {}

    // z_m at p, bilinear between the samples of the level's tile holding p.
    double zm(Vec2 p) {
        Quad* q = &qt.root();
        while (q->level < level) {
            qt.subdivide(*q);
            const Vec2 mid = q->bounds.center();
            q = q->children[std::size_t((p.x >= mid.x ? 1 : 0) | (p.y >= mid.y ? 2 : 0))].get();
        }
        auto [it, made] = tiles.try_emplace({q->tx, q->ty});
        if (made) it->second = produceElevation(*q, qt, data, *dem.quadDem(*q), {});
        const ElevationTile& t = it->second;
        const Vec2 f = (p - t.bounds.min) / t.delta;
        const int i = std::clamp(int(std::floor(f.x)), 0, t.resolution - 1), j = std::clamp(int(std::floor(f.y)), 0, t.resolution - 1);
        const double a = std::clamp(f.x - i, 0.0, 1.0), b = std::clamp(f.y - j, 0.0, 1.0);
        auto z = [&](int di, int dj) { return double(t.zm[t.index(i + di, j + dj)]); };
        return (1 - a) * (1 - b) * z(0, 0) + a * (1 - b) * z(1, 0) + (1 - a) * b * z(0, 1) + a * b * z(1, 1);
    }
};

// Points of a curve every `step` metres (chord length of a fine flattening), with u and the left
// normal.
struct Station {
    Vec2 p, left;
    double u;
};
std::vector<Station> stations(const Curve& c, double step) {
    std::vector<Vec2> pts;
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
        constexpr int kPerPiece = 256;
        for (int i = pts.empty() ? 0 : 1; i <= kPerPiece; ++i) pts.push_back(evaluate(b, double(i) / kPerPiece));
    });
    std::vector<Station> out;
    double u = 0.0, next = 0.0;
    for (std::size_t i = 1; i < pts.size(); ++i) {
        const Vec2 d = pts[i] - pts[i - 1];
        const double len = glm::length(d);
        if (len <= 0.0) continue;
        const Vec2 left = Vec2(-d.y, d.x) / len;
        while (next <= u + len) {
            out.push_back({pts[i - 1] + d * ((next - u) / len), left, next});
            next += step;
        }
        u += len;
    }
    return out;
}

double distanceToCurve(const Curve& c, Vec2 p) {
    double best = INFINITY;
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) { best = std::min(best, distanceTo(b, p, 1e-3)); });
    return best;
}

}  // namespace

BridgeCheckReport checkBridges(const Scene& scene, const Dem& dem, const BridgeCheckParams& params) {
    return checkBridges(scene, InMemoryDem(dem), params);
}

BridgeCheckReport checkBridges(const Scene& scene, const DemSource& dem, const BridgeCheckParams& params) {
    BridgeCheck check(params);
    check.add(scene, dem, [](Vec2) { return true; });
    return check.finish();
}

BridgeCheck::BridgeCheck(BridgeCheckParams params) : params_(params), t0_(std::chrono::steady_clock::now()) {
    if (params.level < 0 || !(params.step > 0.0)) throw std::invalid_argument("checkBridges: level >= 0 and step > 0 required");
    r_.leastClearance = INFINITY;
}

void BridgeCheck::add(const Scene& scene, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
    BridgeCheckReport& r = r_;
    const BridgeCheckParams& params = params_;
    ++parts_;
    Terrain with(scene, dem, params);
    const GraphStepCounters& gc = with.step.counters();
    r.crossingsFound += gc.crossingsFound;
    r.flaggedRiverCrossings += gc.flaggedCrossings;
    r.bridgedCrossings += gc.bridgedCrossings;
    r.culverts += gc.culverts;

    // The points under the decks over the water, and the roads that carry a bridge (every one the
    // part holds leaves the scene without them: the terrain at a point is the whole scene's).
    std::vector<Vec2> bed;
    Scene without = scene;
    for (LayerId l = 0; l < scene.layers.size(); ++l) {
        if (scene.layers[l].kind != LayerKind::Roads) continue;
        for (ElementId id = 0; id < scene.layers[l].curves.size(); ++id) {
            const Curve& road = scene.layers[l].curves[id];
            const bool counted = road.alive && !road.vertices.empty() && owns(road.vertices.front().p);
            bool bridged = false;
            for (AncestorId a : with.qt.expansionOf(l, id)) {
                const ProceduralCurve* pc = with.qt.proceduralCurve(l, a);
                if (!(pc->curve.flags & kBridge)) continue;
                bridged = true;
                if (counted) {
                    ++r.bridges;
                    ++((road.flags & kBridge) ? r.importedBridges : r.proceduralBridges);
                }
                const ZProfile& deck = with.data.zProfile(l, a);
                const std::vector<Station> st = stations(pc->curve, params.step);
                for (const BridgeSpan& s : pc->spans) {
                    const Curve& over = scene.layers[s.layer].curves[ElementId(s.over)];
                    if (scene.layers[s.layer].kind != LayerKind::Rivers || (s.over & kProceduralBit) || !over.areas.empty()) continue;
                    if (counted) {
                        ++r.riverSpans;
                        const double water = with.data.spanWater(s);
                        for (std::size_t i = 0; i < deck.z.size(); ++i) {
                            if (std::abs(deck.spacing * double(i) - s.u) > s.halfLength) continue;
                            const double c = deck.z[i] - params.graph.deckThickness - water;
                            ++r.deckSamples;
                            r.deckSamplesBelowClearance += c < params.graph.clearance - 1e-9;
                            r.leastClearance = std::min(r.leastClearance, c);
                        }
                    }
                    const double half = 0.5 * double(over.w), quarter = 0.25 * double(pc->curve.w);
                    for (const Station& x : st) {
                        if (std::abs(x.u - s.u) > s.halfLength) continue;
                        for (double side : {-quarter, 0.0, quarter}) {
                            const Vec2 p = x.p + side * x.left;
                            if (owns(p) && distanceToCurve(over, p) <= half) bed.push_back(p);
                        }
                    }
                }
            }
            if (bridged) deleteCurve(without, l, id);
        }
    }
    Terrain plain(without, dem, params);
    for (const Vec2& p : bed) {
        const double d = std::abs(with.zm(p) - plain.zm(p));
        ++r.bedPoints;
        r.bedPointsDiffering += d > 0.0;
        r.largestBedDifference = std::max(r.largestBedDifference, d);
    }
    r.tilesCompared += with.tiles.size();
}

BridgeCheckReport BridgeCheck::finish() {
    BridgeCheckReport r = r_;
    r.graphCounters = parts_ <= 1;
    if (!r.graphCounters) r.crossingsFound = r.flaggedRiverCrossings = r.bridgedCrossings = r.culverts = 0;
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
    return r;
}

}  // namespace lacet
