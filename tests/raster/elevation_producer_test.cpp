// The elevation producer (§5.2) on synthetic scenes: seams, shape constraints, incremental
// regeneration equal to production from scratch, and no work a scene does not call for.
#include "raster/elevation_producer.h"

#include <map>
#include <random>
#include <tuple>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/random_edits.h"
#include "model/synthetic_scene.h"
#include "raster/dem_height_field.h"
#include "raster/synthetic_dem.h"

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

TEST(ElevationProducer, AdjacentTilesAgreeOnTheirSharedBorder) {
    World w(2, 3000);
    Quadtree qt(w.scene);
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, 2.8, 11);
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
    qt.refineForViewer({0.0, 0.0, 1.0}, 1e12, level);  // every quad down to `level`
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
}

TEST(ElevationProducer, IncrementalRegenerationEqualsProductionFromScratch) {
    World w(6, 1500);
    Quadtree qt(w.scene);
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, 2.8, 9);
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
    qt.refineForViewer({0.0, 0.0, 1e6}, 1e6, 2);  // levels 0..2 only: delta is hundreds of metres
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
