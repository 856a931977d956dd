// The elevation producer (§5.2) on synthetic scenes: seams, shape constraints, incremental
// regeneration equal to production from scratch, and no work a scene does not call for.
#include "raster/elevation_producer.h"

#include <map>
#include <random>
#include <tuple>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/edits.h"
#include "raster/area_triangulation.h"
#include "raster/dem_height_field.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/raster/hand_scenes.h"

namespace lacet {
namespace {

struct World {
    Scene scene;
    Dem dem;
    DemHeightField heights;
    World(std::uint64_t seed, std::size_t curves)
        : scene(makeSyntheticScene({seed, curves})), dem(makeSyntheticDem(scene, {seed, 1000})), heights(dem) {}
};

using Key = std::tuple<int, std::uint32_t, std::uint32_t>;
Key keyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

std::map<Key, ElevationTile> produceAll(const Quadtree& qt, const CurveDataCache& data, const Dem& dem, int minLevel) {
    std::map<Key, ElevationTile> tiles;
    qt.forEachQuad([&](const Quad& q) {
        if (q.level >= minLevel) tiles.emplace(keyOf(q), produceElevation(q, qt, data, dem, {}));
    });
    return tiles;
}

// z_m at a point of the tile, bilinear between samples.
double zmAt(const ElevationTile& t, Vec2 p) {
    const Vec2 g = (p - t.bounds.min) / t.delta;
    const int i = int(std::floor(g.x)), j = int(std::floor(g.y));
    const double fx = g.x - i, fy = g.y - j;
    auto z = [&](int a, int b) { return double(t.zm[t.index(a, b)]); };
    return (z(i, j) * (1 - fx) + z(i + 1, j) * fx) * (1 - fy) + (z(i, j + 1) * (1 - fx) + z(i + 1, j + 1) * fx) * fy;
}

const ElevationTile* tileAt(const std::map<Key, ElevationTile>& tiles, int level, Vec2 p) {
    for (const auto& [k, t] : tiles)
        if (std::get<0>(k) == level && t.bounds.contains(p)) return &t;
    return nullptr;
}

// Subdivides every quad meeting `region` down to `level` and produces the tiles of that level.
void refineAround(Quadtree& qt, Quad& q, const Box& region, int level, std::vector<const Quad*>& out) {
    if (!q.bounds.intersects(region)) return;
    if (q.level == level) {
        out.push_back(&q);
        return;
    }
    if (q.isLeaf()) qt.subdivide(q);
    for (auto& c : q.children) refineAround(qt, *c, region, level, out);
}

std::map<Key, ElevationTile> tilesAround(Quadtree& qt, const CurveDataCache& data, const Dem& dem, const Box& region, int level) {
    std::vector<const Quad*> quads;
    refineAround(qt, qt.root(), region, level, quads);
    std::map<Key, ElevationTile> tiles;
    for (const Quad* q : quads) tiles.emplace(keyOf(*q), produceElevation(*q, qt, data, dem, {}));
    return tiles;
}

std::vector<Vec2> densePoints(const std::vector<Vertex>& vertices, int perPiece) {
    std::vector<Vec2> out;
    forEachPiece(vertices, [&](const BezierPiece& b, std::size_t) {
        for (int i = 0; i <= perPiece; ++i) out.push_back(evaluate(b, i / double(perPiece)));
    });
    return out;
}

double distanceTo(const std::vector<Vec2>& points, Vec2 p) {
    double d = 1e300;
    for (const Vec2& q : points) d = std::min(d, glm::length(p - q));
    return d;
}

// Across a road, inside its width, z_m varies by less than 1 cm per metre of width (§5.2: roads
// are flat across), away from where another road or a river crosses it.
TEST(ElevationProducer, RoadsAreLevelAcrossTheirWidth) {
    World w(4, 3000);
    Quadtree qt(w.scene);
    const Layer& roads = w.scene.layers[kRoadsLayer];
    const int level = 8;  // samples 1.15 m apart: a 7 m road spans 6 of them
    CurveDataCache data(qt, w.heights);
    std::size_t checked = 0;
    double worst = 0.0;
    for (ElementId id = 0; id < roads.curves.size() && checked < 600; ++id) {
        const Curve& road = roads.curves[id];
        if (road.cls != 0) continue;
        const std::vector<Vec2> axis = densePoints(road.vertices, 400);
        Box region{axis.front(), axis.front()};
        for (const Vec2& p : axis) region = {glm::min(region.min, p), glm::max(region.max, p)};
        const auto tiles = tilesAround(qt, data, w.dem, region.dilated(20.0), level);
        // Other curves near this road (junction ends, crossings) are left out.
        std::vector<Vec2> others;
        for (LayerId l : {kRoadsLayer, kRiversLayer})
            for (ElementId o = 0; o < w.scene.layers[l].curves.size(); ++o)
                if (l != kRoadsLayer || o != id) {
                    const auto pts = densePoints(w.scene.layers[l].curves[o].vertices, 200);
                    for (const Vec2& p : pts)
                        if (region.dilated(40.0).contains(p)) others.push_back(p);
                }
        for (std::size_t k = 10; k + 10 < axis.size(); k += 7) {
            const Vec2 p = axis[k];
            if (distanceTo(others, p) < 40.0) continue;
            const Vec2 t = glm::normalize(axis[k + 1] - axis[k - 1]), n(-t.y, t.x);
            double lo = 1e300, hi = -1e300;
            bool inside = true;
            for (int i = -4; i <= 4; ++i) {
                const Vec2 q = p + n * (0.5 * double(road.w) * i / 4.0);
                const ElevationTile* tile = tileAt(tiles, level, q);
                if (!tile) inside = false;
                if (!inside) break;
                const double z = zmAt(*tile, q);
                lo = std::min(lo, z), hi = std::max(hi, z);
            }
            if (!inside) continue;
            worst = std::max(worst, (hi - lo) / double(road.w));
            ++checked;
        }
    }
    EXPECT_GT(checked, 200u);
    EXPECT_LT(worst, 0.01) << "metres per metre of width";
    std::cout << "[ figures  ] roads across: " << checked << " cross-sections, at most " << worst * 100.0 << " cm per metre\n";
}

// A river area (§4.1: a large river's water) on a valley sloping down to the south (a V across
// x = 256 whose floor descends with y), a 40 x 300 m rectangle around a river flowing south along
// the floor, its border made of curves of the rivers layer as the import makes them. The river is
// two curves, split where a stream (another class) joins it inside the area, as imported rivers
// are at their confluences; the area's axial curve is the upstream one.
struct RiverAreaValley {
    static constexpr double kSide = 512.0;      // metres
    static constexpr double kAxisX = 256.0;     // metres: the valley floor and the river
    static constexpr double kSideSlope = 0.3;   // m/m across the valley
    static constexpr double kDownSlope = 0.05;  // m/m along it
    static constexpr double kUpY = 500.0;       // metres: the river's source; its mouth is at y = 12
    static constexpr double kJoinY = 250.0;     // metres: the confluence
    static inline const Box kArea{{236.0, 100.0}, {276.0, 400.0}};  // metres: the river area
    Scene scene;
    Dem dem;
    ElementId upper = kNoElement, lower = kNoElement, area = kNoElement;

    static double height(Vec2 p) { return 1000.0 + kSideSlope * std::abs(p.x - kAxisX) + kDownSlope * p.y; }
    static Dem makeDem() {
        constexpr int kCells = 64;  // 8 m
        std::vector<float> h(std::size_t(kCells) * kCells);
        for (int j = 0; j < kCells; ++j)
            for (int i = 0; i < kCells; ++i)
                h[std::size_t(j) * kCells + std::size_t(i)] = float(height(Vec2(i + 0.5, j + 0.5) * (kSide / kCells)));
        return Dem({{0.0, 0.0}, {kSide, kSide}}, kCells, kCells, std::move(h));
    }
    explicit RiverAreaValley(bool withAxial) : dem(makeDem()) {
        test::SceneBuilder b(kSide);
        const ElementId up = b.node(kRiversLayer, {kAxisX, kUpY}), join = b.node(kRiversLayer, {kAxisX, kJoinY});
        const ElementId down = b.node(kRiversLayer, {kAxisX, 12.0}), spring = b.node(kRiversLayer, {400.0, 300.0});
        upper = b.curve(kRiversLayer, up, join, {}, 10.0f, 20.0f);
        lower = b.curve(kRiversLayer, join, down, {}, 10.0f, 20.0f);
        b.curve(kRiversLayer, spring, join, {}, 2.0f, 6.0f, 1);  // a stream, nearer than the river to some of the area
        const Vec2 corners[4] = {kArea.min, {kArea.max.x, kArea.min.y}, kArea.max, {kArea.min.x, kArea.max.y}};
        ElementId n[4];
        for (int i = 0; i < 4; ++i) n[i] = b.node(kRiversLayer, corners[i]);
        std::vector<AreaEdge> ring;
        for (int i = 0; i < 4; ++i) ring.push_back({b.curve(kRiversLayer, n[i], n[(i + 1) % 4], {}, 0.0f, 8.0f), false});
        area = b.area(kRiversLayer, {ring}, 8.0f);
        if (withAxial) b.scene().layers[kRiversLayer].areas[area].axial = upper;
        scene = std::move(b.scene());
    }
};

// §5.2, areas in three steps: inside a river area, z_m is its axial curve's z-profile at the
// nearest point of the axial curve (here straight down the valley: u = 500 - y), and on through
// the area, the profile of the river's next curve (u = 250 - y), not the stream's; so the water
// descends with the river, and is not the flat level of its lowest border, which it keeps only
// without an axial curve (as a lake).
TEST(ElevationProducer, RiverAreasFollowTheirAxialCurvesProfileDownstream) {
    constexpr int kLevel = 3;              // 64 m quads, samples 2.7 m apart
    constexpr double kTolerance = 0.01;    // metres
    // Within kNearJoin of the confluence the profiles bend (each curve's is clamped to the node's
    // height over its last sample spacing) and the 3 x 3 filter and the bilinear lookup smooth the
    // bend: kNearJoinTolerance there.
    constexpr double kNearJoin = 15.0, kNearJoinTolerance = 0.05;  // metres
    constexpr double kAwayFromBorder = 10.0;  // metres: beyond the border's blend and the 3 x 3 filter
    for (const bool withAxial : {true, false}) {
        const RiverAreaValley v(withAxial);
        DemHeightField heights(v.dem);
        Quadtree qt(v.scene);
        CurveDataCache data(qt, heights);
        const auto tiles = tilesAround(qt, data, v.dem, RiverAreaValley::kArea, kLevel);
        const ZProfile& upper = data.zProfile(kRiversLayer, v.upper);
        const ZProfile& lower = data.zProfile(kRiversLayer, v.lower);
        const double level = data.lakeLevel(kRiversLayer, v.area);
        double worst = 0.0, highest = -1e300;
        Vec2 worstAt(0.0);
        std::size_t checked = 0;
        for (const double x : {RiverAreaValley::kArea.min.x + kAwayFromBorder, RiverAreaValley::kAxisX, RiverAreaValley::kArea.max.x - kAwayFromBorder}) {
            double previous = 1e300;
            for (double y = RiverAreaValley::kArea.max.y - kAwayFromBorder; y >= RiverAreaValley::kArea.min.y + kAwayFromBorder; y -= 10.0) {
                const ElevationTile* t = tileAt(tiles, kLevel, {x, y});
                ASSERT_NE(t, nullptr);
                const double zm = zmAt(*t, {x, y});
                const double expected = !withAxial ? level
                                        : y >= RiverAreaValley::kJoinY ? upper.at(RiverAreaValley::kUpY - y)
                                                                       : lower.at(RiverAreaValley::kJoinY - y);
                const bool nearJoin = withAxial && std::abs(y - RiverAreaValley::kJoinY) <= kNearJoin;
                if (nearJoin) {
                    EXPECT_NEAR(zm, expected, kNearJoinTolerance) << "near the confluence at " << x << ", " << y;
                } else if (std::abs(zm - expected) > worst) {
                    worst = std::abs(zm - expected);
                    worstAt = {x, y};
                }
                highest = std::max(highest, zm);
                if (withAxial) {
                    EXPECT_LT(zm, previous - 0.5 * RiverAreaValley::kDownSlope * 10.0) << "descends downstream at x " << x << ", y " << y;
                }
                previous = zm;
                ++checked;
            }
        }
        EXPECT_EQ(checked, 3u * 29u);
        EXPECT_LT(worst, kTolerance) << (withAxial ? "the axial profile" : "the lowest border level") << ", metres, at " << worstAt.x
                                     << ", " << worstAt.y;
        if (withAxial) {
            EXPECT_GT(highest - level, 0.8 * RiverAreaValley::kDownSlope * 280.0) << "not flat at the lowest border's level";
        }
        std::cout << "[ figures  ] river area " << (withAxial ? "with" : "without") << " an axial curve: " << checked
                  << " samples, those farther than kNearJoin from the confluence within " << worst * 1000.0 << " mm of " << (withAxial ? "its profile" : "its lowest border")
                  << ", highest " << highest - level << " m above the lowest border\n";
    }
}

// A lake's surface is flat within 1 mm, away from its border by the filter's reach.
TEST(ElevationProducer, LakesAreFlat) {
    World w(4, 3000);
    Quadtree qt(w.scene);
    const Layer& lakes = w.scene.layers[kLakesLayer];
    ASSERT_FALSE(lakes.areas.empty());
    CurveDataCache data(qt, w.heights);
    const int level = 6;
    std::size_t checked = 0;
    double worst = 0.0;
    for (ElementId a = 0; a < lakes.areas.size(); ++a) {
        std::vector<std::vector<Vec2>> loops;
        std::vector<Vec2> border;
        for (const auto& loop : lakes.areas[a].loops) {
            loops.push_back(densePoints(loopVertices(lakes, loop), 100));
            border.insert(border.end(), loops.back().begin(), loops.back().end());
        }
        Box region{border.front(), border.front()};
        for (const Vec2& p : border) region = {glm::min(region.min, p), glm::max(region.max, p)};
        const auto tiles = tilesAround(qt, data, w.dem, region, level);
        const double level0 = data.lakeLevel(kLakesLayer, a);
        for (const auto& [k, t] : tiles)
            for (int j = 0; j <= t.resolution; ++j)
                for (int i = 0; i <= t.resolution; ++i) {
                    const Vec2 p = t.position(i, j);
                    if (!insideLoops(loops, p) || distanceTo(border, p) < 3.0 * t.delta) continue;
                    worst = std::max(worst, std::abs(double(t.zm[t.index(i, j)]) - level0));
                    ++checked;
                }
    }
    EXPECT_GT(checked, 500u);
    EXPECT_LE(worst, 1e-3) << "metres";
    std::cout << "[ figures  ] lakes flat: " << checked << " samples within " << worst * 1000.0 << " mm of the lake level\n";
}

// Every road meeting at a junction arrives at the node's one height: each arm's z-profile ends
// exactly at it, and the produced z_m around the node is that height.
TEST(ElevationProducer, RoadsMeetAtOneHeightAtJunctions) {
    World w(4, 3000);
    Quadtree qt(w.scene);
    const Layer& roads = w.scene.layers[kRoadsLayer];
    CurveDataCache data(qt, w.heights);
    const int level = 10;  // samples 29 cm apart
    std::size_t junctions = 0;
    double worstProfile = 0.0, worstProduced = 0.0;
    for (ElementId n = 0; n < roads.nodes.size() && junctions < 25; ++n) {
        if (roads.nodes[n].curves.size() < 3) continue;
        ++junctions;
        const double h = data.nodeHeight(kRoadsLayer, n);
        for (ElementId c : roads.nodes[n].curves) {
            const ZProfile& z = data.zProfile(kRoadsLayer, c);
            worstProfile = std::max(worstProfile, std::abs(z.at(roads.curves[c].start == n ? 0.0 : z.length) - h));
        }
        const Vec2 p = roads.nodes[n].p;
        const auto tiles = tilesAround(qt, data, w.dem, {p - 1.0, p + 1.0}, level);
        worstProduced = std::max(worstProduced, std::abs(zmAt(*tileAt(tiles, level, p), p) - h));
    }
    EXPECT_GE(junctions, 10u);
    EXPECT_LE(worstProfile, 1e-9) << "metres";
    // z_m at the node mixes the arms' z_e within 2 sqrt(2) delta of it, which follow their slopes.
    EXPECT_LE(worstProduced, 0.02) << "metres, with samples 29 cm apart";
    std::cout << "[ figures  ] junction height: produced z_m within " << worstProduced << " m of the node height\n";
}

TEST(ElevationProducer, AdjacentTilesAgreeOnTheirSharedBorder) {
    World w(2, 3000);
    Quadtree qt(w.scene);
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, ViewParams{.maxLevel = 11});
    CurveDataCache data(qt, w.heights);
    const auto tiles = produceAll(qt, data, w.dem, 3);
    std::size_t compared = 0;
    double worstZ = 0.0, worstB = 0.0;
    for (const auto& [k, t] : tiles) {
        const auto [level, tx, ty] = k;
        const auto right = tiles.find({level, tx + 1, ty});
        const auto up = tiles.find({level, tx, ty + 1});
        const int n = t.resolution;
        for (int s = 0; s <= n; ++s) {
            if (right != tiles.end()) {
                worstZ = std::max(worstZ, double(std::abs(t.zm[t.index(n, s)] - right->second.zm[right->second.index(0, s)])));
                worstB = std::max(worstB, double(std::abs(t.b[t.index(n, s)] - right->second.b[right->second.index(0, s)])));
                ++compared;
            }
            if (up != tiles.end()) {
                worstZ = std::max(worstZ, double(std::abs(t.zm[t.index(s, n)] - up->second.zm[up->second.index(s, 0)])));
                worstB = std::max(worstB, double(std::abs(t.b[t.index(s, n)] - up->second.b[up->second.index(s, 0)])));
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 1000u);
    EXPECT_LE(worstZ, 1e-3) << "metres";
    EXPECT_LE(worstB, 1e-3);
    std::cout << "[ figures  ] elevation seams: " << compared << " shared samples, z_m within " << worstZ << " m, b within "
              << worstB << "\n";
}

TEST(ElevationProducer, RiversNeverRiseAlongTheirAxis) {
    World w(4, 3000);
    Quadtree qt(w.scene);
    const Layer& rivers = w.scene.layers[kRiversLayer];
    // Follow the widest river at a level where it is drawn.
    ElementId river = 0;
    for (ElementId c = 0; c < rivers.curves.size(); ++c)
        if (rivers.curves[c].w > rivers.curves[river].w) river = c;
    const Curve& rc = rivers.curves[river];
    // The coarsest level whose samples (delta = size / 24) are at most w / 2 apart.
    int level = 0;
    while (w.scene.extent.size().x / std::ldexp(1.0, level) / 24.0 > 0.5 * double(rc.w)) ++level;
    qt.refineForViewer({0.0, 0.0, 1.0}, ViewParams{.K = 1e12, .maxLevel = level});  // every quad down to `level`
    CurveDataCache data(qt, w.heights);
    const auto tiles = produceAll(qt, data, w.dem, level);
    ASSERT_GE(double(rc.w), 2.0 * tiles.begin()->second.delta) << "the river must be drawn at this level";
    double previous = 1e300, worstRise = 0.0;
    int samples = 0;
    forEachPiece(rc.vertices, [&](const BezierPiece& b, std::size_t) {
        for (int i = 0; i <= 200; ++i) {
            const Vec2 p = evaluate(b, i / 200.0);
            const ElevationTile* t = tileAt(tiles, level, p);
            if (!t) continue;
            const double z = zmAt(*t, p);
            worstRise = std::max(worstRise, z - previous);
            previous = std::min(previous, z);
            ++samples;
        }
    });
    EXPECT_GT(samples, 100);
    EXPECT_LE(worstRise, 1e-3) << "metres";
    std::cout << "[ figures  ] river axis: " << samples << " samples, largest rise " << worstRise << " m\n";
}

TEST(ElevationProducer, IncrementalRegenerationEqualsProductionFromScratch) {
    World w(6, 1500);
    Quadtree qt(w.scene);
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, ViewParams{.maxLevel = 9});
    CurveDataCache data(qt, w.heights);
    auto tiles = produceAll(qt, data, w.dem, 1);
    std::mt19937_64 rng(6);
    std::size_t regenerated = 0, edits = 0;
    for (int e = 0; e < 40; ++e) {
        const RandomEdit edit = applyRandomEdit(w.scene, rng, 0.02 * w.scene.extent.size().x);
        if (edit.changeset.empty()) continue;
        ++edits;
        data.invalidate(edit.changeset);
        const UpdateStats st = qt.update(edit.changeset);
        for (const Quad* q : st.changedQuads) tiles[keyOf(*q)] = produceElevation(*q, qt, data, w.dem, {});
        regenerated += st.changedQuads.size();
        Quadtree fresh(w.scene);
        fresh.copyStructureOf(qt);
        CurveDataCache freshData(fresh, w.heights);
        const auto expected = produceAll(fresh, freshData, w.dem, 1);
        ASSERT_EQ(expected.size(), tiles.size());
        for (const auto& [k, t] : expected) EXPECT_TRUE(tiles.at(k) == t) << "edit " << e << " (" << toString(edit.kind) << ")";
    }
    EXPECT_GT(edits, 20u);
    EXPECT_LT(regenerated, edits * tiles.size() / 4) << "only the quads whose graph changed are regenerated";
}

TEST(ElevationProducer, ThinCurvesAtCoarseLevelsCostNoZProfile) {
    World w(8, 3000);
    Quadtree qt(w.scene);
    qt.refineForViewer({0.0, 0.0, 1e6}, ViewParams{.K = 1e6, .maxLevel = 2});  // levels 0..2 only: delta is hundreds of metres
    CurveDataCache data(qt, w.heights);
    ElevationCounters counters;
    qt.forEachQuad([&](const Quad& q) {
        if (q.level == 2) produceElevation(q, qt, data, w.dem, {}, &counters);
    });
    EXPECT_EQ(counters.tiles, 16u);
    EXPECT_GT(counters.curvesSkippedThin, 50u);
    EXPECT_EQ(counters.curvesDrawn, 0u);
    EXPECT_EQ(data.counters().zProfiles, 0u);
    EXPECT_EQ(data.counters().arcLengthTables, 0u);
}

}  // namespace
}  // namespace lacet
