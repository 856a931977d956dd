// Issue 14: a bridge leaves the river bed as it is. Under every bridge the elevation (z_m) equals
// the elevation produced without the bridge's road, and the appearance keeps the river's water
// under the deck; a tunnel leaves the terrain untouched between its portals.
#include <gtest/gtest.h>

#include <cmath>

#include "model/graph_step.h"
#include "raster/appearance_producer.h"
#include "raster/bridge_check.h"
#include "raster/river_check.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"
#include "synth/synthetic_scene.h"
#include "tests/raster/hand_scenes.h"

namespace lacet {
namespace {

constexpr double kSide = 512.0, kAxisX = 256.0, kRoadY = 250.0;

double valley(Vec2 p) { return 1000.0 + 0.25 * std::abs(p.x - kAxisX) + 0.02 * p.y; }

Dem valleyDem() {
    constexpr int kCells = 128;  // 4 m
    std::vector<float> h(std::size_t(kCells) * kCells);
    for (int j = 0; j < kCells; ++j)
        for (int i = 0; i < kCells; ++i)
            h[std::size_t(j) * kCells + std::size_t(i)] = float(valley(Vec2(i + 0.5, j + 0.5) * (kSide / kCells)));
    return Dem({{0.0, 0.0}, {kSide, kSide}}, kCells, kCells, std::move(h));
}

// A river down the valley floor and, if `roadFlags` is set, a road across it at y = kRoadY.
Scene valleyScene(std::optional<std::uint16_t> roadFlags) {
    test::SceneBuilder b(kSide);
    const ElementId up = b.node(kRiversLayer, {kAxisX, 500.0}), down = b.node(kRiversLayer, {kAxisX, 12.0});
    b.curve(kRiversLayer, up, down, {}, 10.0f, 20.0f);
    if (roadFlags) {
        const ElementId w = b.node(kRoadsLayer, {20.0, kRoadY}), e = b.node(kRoadsLayer, {490.0, kRoadY + 4.0});
        const ElementId r = b.curve(kRoadsLayer, w, e, {}, 6.0f, 12.0f, 1);
        b.scene().layers[kRoadsLayer].curves[r].flags = *roadFlags;
    }
    return std::move(b.scene());
}

struct Produced {
    Scene scene;
    GraphStep step;
    Quadtree qt;
    DemHeightField heights;
    CurveDataCache data;
    std::vector<ElevationTile> elevation;
    std::vector<AppearanceTile> appearance;
    Produced(Scene s, const Dem& dem, int level)
        : scene(std::move(s)), step(scene), qt(scene, {}, &step), heights(dem), data(qt, heights) {
        auto rec = [&](auto& self, Quad& q) -> void {
            if (q.level == level) {
                elevation.push_back(produceElevation(q, qt, data, dem, {}));
                AppearanceParams ap;
                ap.detectUniform = false;
                appearance.push_back(produceAppearance(q, qt, data, dem, ap));
                return;
            }
            qt.subdivide(q);
            for (auto& c : q.children) self(self, *c);
        };
        rec(rec, qt.root());
    }
};

TEST(BridgeElevation, UnderABridgeTheRiverBedIsTheOneProducedWithoutTheRoad) {
    const Dem dem = valleyDem();
    constexpr int kLevel = 3;  // 64 m quads, samples 2 m apart
    const Produced with(valleyScene(std::uint16_t(0)), dem, kLevel), without(valleyScene(std::nullopt), dem, kLevel);
    ASSERT_EQ(with.qt.proceduralCount(kBridge), 1u);
    // Under the deck: within the river's footprint (10 m of the axis) and the road's half width.
    std::size_t under = 0, differ = 0;
    double worst = 0.0;
    for (std::size_t t = 0; t < with.elevation.size(); ++t) {
        const ElevationTile& a = with.elevation[t];
        const ElevationTile& b = without.elevation[t];
        ASSERT_EQ(a.bounds, b.bounds);
        for (int j = 0; j <= a.resolution; ++j)
            for (int i = 0; i <= a.resolution; ++i) {
                const Vec2 p = a.position(i, j);
                const double roadY = kRoadY + 4.0 * (p.x - 20.0) / 470.0;
                if (std::abs(p.x - kAxisX) > 10.0 || std::abs(p.y - roadY) > 3.0) continue;
                ++under;
                const double d = std::abs(double(a.zm[a.index(i, j)]) - double(b.zm[b.index(i, j)]));
                worst = std::max(worst, d);
                differ += d > 0.0;
            }
    }
    EXPECT_GT(under, 10u);
    EXPECT_EQ(differ, 0u) << "worst " << worst << " m";
    // The water shows under the deck: every texel of the river's water band there is water.
    std::size_t water = 0, dry = 0;
    for (const AppearanceTile& t : with.appearance)
        for (int j = 0; j < t.resolution; ++j)
            for (int i = 0; i < t.resolution; ++i) {
                const Vec2 p = t.bounds.min + (Vec2(i, j) + 0.5) * t.delta;
                const double roadY = kRoadY + 4.0 * (p.x - 20.0) / 470.0;
                if (std::abs(p.x - kAxisX) > 3.0 || std::abs(p.y - roadY) > 3.0) continue;
                const std::size_t k = (std::size_t(j + t.border) * std::size_t(t.stride) + std::size_t(i + t.border)) * 4 + 3;
                (t.rgbm[k] > 0 ? water : dry) += 1;
            }
    EXPECT_GT(water, 20u);
    EXPECT_EQ(dry, 0u);
}

TEST(BridgeElevation, ATunnelLeavesTheTerrainAsItIsButTheRoadOutsideItDoes) {
    const Dem dem = valleyDem();
    constexpr int kLevel = 3;
    const Produced tunnel(valleyScene(std::uint16_t(kTunnel)), dem, kLevel), none(valleyScene(std::nullopt), dem, kLevel),
        road(valleyScene(std::uint16_t(kNoBridge)), dem, kLevel);
    ASSERT_EQ(tunnel.qt.proceduralCount(kBridge), 0u);
    std::size_t differ = 0, roadDiffers = 0;
    for (std::size_t t = 0; t < tunnel.elevation.size(); ++t) {
        differ += tunnel.elevation[t].zm != none.elevation[t].zm;
        roadDiffers += road.elevation[t].zm != none.elevation[t].zm;
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(roadDiffers, 0u);  // a ford does flatten its footprint: the comparison can see a road
}

// The whole-scene check behind `lacet check bridges` finds the same on the valley.
TEST(BridgeElevation, TheSceneCheckFindsTheBedUntouchedAndTheDeckClear) {
    const Dem dem = valleyDem();
    const Scene scene = valleyScene(std::uint16_t(0));
    const BridgeCheckReport r = checkBridges(scene, dem, {.level = 3, .step = 1.0, .graph = {}});
    EXPECT_EQ(r.bridges, 1u);
    EXPECT_EQ(r.riverSpans, 1u);
    EXPECT_GT(r.bedPoints, 10u);
    EXPECT_EQ(r.bedPointsDiffering, 0u);
    EXPECT_GT(r.deckSamples, 1u);
    EXPECT_GE(r.leastClearance, GraphStepParams{}.clearance - 1e-9);
    EXPECT_TRUE(r.passed());
}

// `lacet check rivers` on the valley: the river runs on its floor (at most the DEM's bilinear
// error above it, the DEM being the valley sampled every 4 m) and never rises.
TEST(BridgeElevation, TheRiverCheckFindsTheRiverOnTheValleyFloor) {
    const Dem dem = valleyDem();
    const RiverCheckReport r = checkRivers(valleyScene(std::nullopt), dem);
    EXPECT_EQ(r.curves, 1u);
    EXPECT_GT(r.profileAboveDem.count, 40u);
    EXPECT_LE(r.profileAboveDem.max, 0.01);
    EXPECT_LE(r.nodesAboveDem.max, 0.0);
    EXPECT_EQ(r.risingSamples, 0u);
}

// A bridge over a lake's shore (an imported bridge, half over the water): the lake keeps its level
// and the shore its shape under the deck, and the deck never dips under the lake's level.
TEST(BridgeElevation, ABridgeOverALakesShoreLeavesTheLakeAndTheShoreAsTheyAre) {
    const Dem dem = valleyDem();
    auto scene = [](bool withBridge) {
        test::SceneBuilder b(kSide);
        const Vec2 corners[4] = {{200.0, 150.0}, {320.0, 150.0}, {320.0, 350.0}, {200.0, 350.0}};
        ElementId n[4];
        for (int i = 0; i < 4; ++i) n[i] = b.node(kLakesLayer, corners[i]);
        std::vector<AreaEdge> ring;
        for (int i = 0; i < 4; ++i) ring.push_back({b.curve(kLakesLayer, n[i], n[(i + 1) % 4], {}, 0.0f, 6.0f), false});
        b.area(kLakesLayer, {ring}, 6.0f);
        if (withBridge) {
            const ElementId w = b.node(kRoadsLayer, {150.0, kRoadY}), e = b.node(kRoadsLayer, {260.0, kRoadY});
            const ElementId r = b.curve(kRoadsLayer, w, e, {}, 6.0f, 12.0f, 1);
            b.scene().layers[kRoadsLayer].curves[r].flags = kBridge;
        }
        return std::move(b.scene());
    };
    const Produced with(scene(true), dem, 3), without(scene(false), dem, 3);
    for (std::size_t t = 0; t < with.elevation.size(); ++t) EXPECT_EQ(with.elevation[t].zm, without.elevation[t].zm) << t;
    const double level = with.data.lakeLevel(kLakesLayer, 0);
    const auto ids = with.qt.expansionOf(kRoadsLayer, 0);
    ASSERT_EQ(ids.size(), 1u);
    for (double z : with.data.zProfile(kRoadsLayer, ids[0]).z) EXPECT_GE(z, level);
}

}  // namespace
}  // namespace lacet
