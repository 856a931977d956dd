// The appearance producer (§5.1): seams, geometry at hairpins and sharp turns, uniform quads,
// incremental regeneration equal to production from scratch, independence from the thread
// count, and no work a scene does not call for.
#include "raster/appearance_producer.h"

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "raster/appearance_canvas.h"
#include "raster/appearance_shading.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"
#include "raster/parallel_producers.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/raster/hand_render.h"
#include "tests/raster/hand_scenes.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

struct AppearanceWorld {
    Scene scene;
    Dem dem;
    DemHeightField heights;
    AppearanceWorld(std::uint64_t seed, std::size_t curves)
        : scene(makeSyntheticScene({seed, curves})), dem(makeSyntheticDem(scene, {seed, 1000})), heights(dem) {}
};

using Key = std::tuple<int, std::uint32_t, std::uint32_t>;
Key appearanceKeyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

std::vector<const Quad*> quadsFrom(const Quadtree& qt, int minLevel) {
    std::vector<const Quad*> out;
    qt.forEachQuad([&](const Quad& q) {
        if (q.level >= minLevel) out.push_back(&q);
    });
    return out;
}

TEST(AppearanceShading, FastCosIsWithinItsBoundOfLibmCos) {
    std::mt19937_64 rng(7);
    double worst = 0.0;
    for (const double scale : {1.0, 10.0, 1e3, 1e5, 1e7}) {
        std::uniform_real_distribution<double> x(-scale, scale);
        for (int i = 0; i < 20000; ++i) {
            const double v = x(rng);
            worst = std::max(worst, std::abs(fastCos(v) - std::cos(v)));
        }
    }
    for (const double v : {0.0, std::numbers::pi, -std::numbers::pi, 0.5 * std::numbers::pi, 1e7})
        worst = std::max(worst, std::abs(fastCos(v) - std::cos(v)));
    EXPECT_LT(worst, 1e-8);
}

TEST(AppearanceShading, BlocksAreTheColoursOfTheirPoints) {
    // Fields step their furrows along rows and columns (within 1e-6); the others (forests: the
    // noise's columns and rows made once) give what at() gives bit for bit, far from the origin
    // too, in full blocks and in the partial ones at a canvas's edge, with the noise's lattice
    // prepared or not.
    for (const Surface surface : {Surface::Field, Surface::Forest, Surface::Water, Surface::Other})
        for (std::uint32_t seed = 0; seed < 8; ++seed) {
            const double texel = 0.02 * double(seed % 6 + 1) * (seed == 7 ? 40.0 : 1.0);
            SurfaceShader shader({surface, std::uint16_t(seed), seed * 977u}, texel);
            const Vec2 start(812345.678 + 31.0 * seed, -4321.5 * seed);
            if (seed != 6) shader.prepare({start - 1.0, start + 40.0 * texel + 1.0});
            shader.prepareBlocks(texel);
            constexpr int n = SurfaceShader::kMaxBlock;
            const int nx = seed % 2 ? n : 5 + int(seed), ny = seed % 3 ? n : 3;
            std::vector<Rgbm> block(std::size_t(n * n), Rgbm(-1.0f));
            shader.block(start, nx, ny, block.data(), n);
            float worst = 0.0f;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const Rgbm& got = block[std::size_t(j * n + i)];
                    if (i >= nx || j >= ny) {  // left alone
                        EXPECT_EQ(got, Rgbm(-1.0f));
                        continue;
                    }
                    const Rgbm c = shader.at(start + Vec2(double(i), double(j)) * texel);
                    for (int k = 0; k < 4; ++k) worst = std::max(worst, std::abs(c[k] - got[k]));
                }
            EXPECT_LT(worst, 1e-6f) << int(surface) << " " << seed;
            if (surface != Surface::Field) {
                EXPECT_EQ(worst, 0.0f) << int(surface) << " " << seed;
            }
        }
}

// A call cancelled from another thread (model/cancel.h: the editor's background tiles) throws
// WorkCancelled, for the appearance and the elevation alike, and leaves the per-thread buffers
// ready: the next call on the same thread makes the same tile as before.
TEST(AppearanceProducer, ACancelledCallThrowsAndTheNextCallMakesTheSameTile) {
    AppearanceWorld w(4, 2000);
    Quadtree qt(w.scene, RefineParams{{.resolution = 64}});
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, ViewParams{.maxLevel = 6});
    CurveDataCache data(qt, w.heights);
    std::size_t tried = 0;
    qt.forEachQuad([&](const Quad& q) {
        if (q.level != 3 || elementCount(q) < 64) return;
        const AppearanceTile before = produceAppearance(q, qt, data, w.dem, {});
        const ElevationTile elevationBefore = produceElevation(q, qt, data, w.dem, {});
        CancelFlag cancel{true};
        EXPECT_THROW((void)produceAppearance(q, qt, data, w.dem, {}, nullptr, &cancel), WorkCancelled);
        EXPECT_THROW((void)produceElevation(q, qt, data, w.dem, {}, nullptr, &cancel), WorkCancelled);
        EXPECT_TRUE(produceAppearance(q, qt, data, w.dem, {}) == before);
        EXPECT_TRUE(produceElevation(q, qt, data, w.dem, {}) == elevationBefore);
        cancel = false;
        EXPECT_TRUE(produceAppearance(q, qt, data, w.dem, {}, nullptr, &cancel) == before);
        ++tried;
    });
    EXPECT_GT(tried, 3u);
}

TEST(AppearanceProducer, AdjacentTilesAgreeOnTheirBorderTexels) {
    AppearanceWorld w(2, 3000);
    Quadtree qt(w.scene, RefineParams{{.resolution = 128}});
    // Near a road junction, down to quads of 14 m (texels of 11 cm: markings show).
    const Vec2 junction = w.scene.layers[kRoadsLayer].nodes[w.scene.layers[kRoadsLayer].nodes.size() / 2].p;
    qt.refineForViewer({junction.x, junction.y, 20.0}, ViewParams{.maxLevel = 9});
    DemHeightField heights(w.dem);
    CurveDataCache data(qt, heights);
    AppearanceCounters counters;
    const auto quads = quadsFrom(qt, 4);
    const auto tiles = produceAppearanceTiles(quads, qt, data, w.dem, {}, &counters);
    std::map<Key, std::vector<std::uint8_t>> texels;
    std::map<Key, const AppearanceTile*> byKey;
    for (std::size_t k = 0; k < quads.size(); ++k) {
        texels[appearanceKeyOf(*quads[k])] = tileTexels(tiles[k]);
        byKey[appearanceKeyOf(*quads[k])] = &tiles[k];
    }
    std::size_t compared = 0, differing = 0;
    int worst = 0;
    for (const auto& [k, t] : byKey) {
        const auto [level, tx, ty] = k;
        const int n = t->resolution, b = t->border;
        const auto& a = texels[k];
        // The neighbour's first `b` columns (rows) are this tile's border texels beyond the edge.
        for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
            const auto it = texels.find({level, tx + std::uint32_t(dx), ty + std::uint32_t(dy)});
            if (it == texels.end()) continue;
            for (int s = -b; s < n + b; ++s)
                for (int o = 0; o < b; ++o) {
                    const std::size_t ia = dx ? t->index(n + o, s) : t->index(s, n + o);
                    const std::size_t ib = dx ? t->index(o, s) : t->index(s, o);
                    int d = 0;
                    for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(a[ia + std::size_t(c)]) - int(it->second[ib + std::size_t(c)])));
                    worst = std::max(worst, d);
                    differing += d > 0;
                    ++compared;
                }
        }
    }
    EXPECT_GT(compared, 5000u);
    EXPECT_GT(counters.curvesWithMarkings, 0u) << "the seams must cross road markings";
    EXPECT_LE(worst, 1) << "of 255; " << differing << " of " << compared << " texels differ";
    EXPECT_LT(double(differing), 1e-3 * double(compared));
    std::cout << "[ figures  ] appearance seams: " << compared << " border texels compared, " << differing
              << " differ, by at most " << worst << " of 255\n";
}

TEST(AppearanceProducer, ACoarserGroundGridInSmallQuadsChangesTexelsByLittle) {
    // groundCellMin: quads smaller than 32 cells of it get fewer ground nodes. What it leaves,
    // measured on quads of 160 m down to 10 m, over an Alpine DEM of 20 m samples (the paper's
    // spacing, the finest it had) whose heights and slopes cross every ground colour's range
    // (meadow, rock by height and by slope, snow; the synthetic DEM is one uniform grass here).
    AppearanceWorld w(2, 3000);
    const Box extent = w.scene.extent;
    const int nx = int(extent.size().x / 20.0) + 1, ny = int(extent.size().y / 20.0) + 1;
    std::vector<float> z(std::size_t(nx) * std::size_t(ny));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double x = 20.0 * i, y = 20.0 * j;
            z[std::size_t(j) * std::size_t(nx) + std::size_t(i)] =
                float(1900.0 + 900.0 * std::sin(x / 700.0) * std::cos(y / 900.0) + 250.0 * std::sin(x / 130.0 + y / 170.0));
        }
    const Dem dem(extent, nx, ny, std::move(z));
    const DemHeightField heights(dem);
    const Vec2 at = extent.center();
    Quadtree qt(w.scene, RefineParams{{.resolution = 128}});
    qt.refineForViewer({at.x, at.y, 20.0}, ViewParams{.maxLevel = 12});
    CurveDataCache data(qt, heights);
    std::vector<const Quad*> small;
    for (const Quad* q : quadsFrom(qt, 8))
        if (q->bounds.size().x < 32.0 * AppearanceParams{}.groundCellMin) small.push_back(q);
    ASSERT_GT(small.size(), 20u);
    AppearanceParams fine;
    fine.groundCellMin = 0.0;  // 32 cells whatever the quad
    const auto exact = produceAppearanceTiles(small, qt, data, dem, fine);
    auto error = [&](double cellMin) {  // worst and mean texel difference, of 255
        AppearanceParams p;
        p.groundCellMin = cellMin;
        const auto coarse = produceAppearanceTiles(small, qt, data, dem, p);
        int worst = 0;
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t k = 0; k < small.size(); ++k) {
            const auto a = tileTexels(coarse[k]), b = tileTexels(exact[k]);
            for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
                const int d = std::abs(int(a[i]) - int(b[i]));
                worst = std::max(worst, d), sum += d, ++n;
            }
        }
        std::cout << "[ figures  ] groundCellMin " << cellMin << " m on " << small.size() << " quads: texels within "
                  << worst << " of 255, mean " << sum / double(std::max<std::size_t>(n, 1)) << "\n";
        return std::pair{worst, sum / double(std::max<std::size_t>(n, 1))};
    };
    const auto [worst, mean] = error(AppearanceParams{}.groundCellMin);
    EXPECT_LE(worst, 1) << "of 255";
    EXPECT_LT(mean, error(20.0).second);  // the knob is what decides it
}

// Every texel whose centre is well inside a road is asphalt, every texel well outside is not:
// the hairpin (narrower than its road) and the sharp V turn have no gap and no spike.
TEST(AppearanceProducer, HairpinsAndSharpTurnsHaveNoGapAndNoSpike) {
    const Scene scene = test::hairpinScene();
    AppearanceParams params;
    params.markingMinTexels = 1e9;  // no markings: inside is plain asphalt
    const std::vector<std::uint8_t> image = test::renderHandScene(scene, params);
    const int side = 256;
    const double texel = 64.0 / side;
    // The exact axes as fine polylines (chords of 1/400 of a piece: their sag is far below a texel).
    std::vector<std::pair<Vec2, Vec2>> axis;
    for (const Curve& c : scene.layers[kRoadsLayer].curves)
        forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
            for (int i = 0; i < 400; ++i) axis.push_back({evaluate(b, i / 400.0), evaluate(b, (i + 1) / 400.0)});
        });
    const glm::vec3 asphalt = roadColour(1);
    auto isAsphalt = [&](const std::uint8_t* p) {
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(p[c]) - int(asphalt[c] * 255.0f + 0.5f)) > 1) return false;
        return true;
    };
    std::size_t inside = 0, outside = 0, wrongInside = 0, wrongOutside = 0;
    const double hw = 2.5, slack = 1.0 * texel + 0.5 * texel;  // a texel of coverage ramp, half a texel of refinement
    for (int row = 0; row < side; ++row)
        for (int x = 0; x < side; ++x) {
            const Vec2 p((x + 0.5) * texel, (side - 1 - row + 0.5) * texel);
            double d = 1e300;
            for (const auto& [a, b] : axis) d = std::min(d, distanceToSegment(p, a, b));
            const std::uint8_t* px = &image[(std::size_t(row) * side + std::size_t(x)) * 3];
            if (d < hw - slack) {
                ++inside;
                wrongInside += !isAsphalt(px);
            } else if (d > hw + slack) {
                ++outside;
                wrongOutside += isAsphalt(px);
            }
        }
    EXPECT_GT(inside, 3000u);
    EXPECT_EQ(wrongInside, 0u) << "gaps in the road";
    EXPECT_EQ(wrongOutside, 0u) << "spikes out of the road";
}

TEST(AppearanceProducer, UniformQuadsStoreNoTexelsAndExpandToWhatTheProducerDraws) {
    AppearanceWorld w(3, 3000);
    Quadtree qt(w.scene, RefineParams{{.resolution = 64}});
    qt.refineForViewer({0.0, 0.0, 1.0}, ViewParams{.K = 1e12, .maxLevel = 6});  // every quad down to level 6 (110 m)
    DemHeightField heights(w.dem);
    CurveDataCache data(qt, heights);
    AppearanceParams full;
    full.detectUniform = false;
    AppearanceCounters counters;
    std::size_t uniform = 0;
    for (const Quad* q : quadsFrom(qt, 6)) {
        const AppearanceTile t = produceAppearance(*q, qt, data, w.dem, {}, &counters);
        if (!t.uniform) continue;
        ++uniform;
        EXPECT_TRUE(t.rgbm.empty());
        const AppearanceTile drawn = produceAppearance(*q, qt, data, w.dem, full);
        ASSERT_FALSE(drawn.uniform);
        EXPECT_TRUE(tileTexels(t) == drawn.rgbm) << "quad " << q->tx << "," << q->ty;
    }
    EXPECT_EQ(counters.uniformTiles, uniform);
    EXPECT_GT(uniform, 20u);
}

TEST(AppearanceProducer, UniformFurrowedFieldQuadsExpandToWhatTheProducerDraws) {
    // Quads inside a field, with texels fine enough for its furrows (the pattern the producer
    // and tileTexels both shade row by row).
    AppearanceWorld w(3, 3000);
    const Layer& fields = w.scene.layers[kFieldsLayer];
    ASSERT_FALSE(fields.nodes.empty());
    const Vec2 at = fields.nodes[fields.nodes.size() / 2].p;
    Quadtree qt(w.scene, RefineParams{{.resolution = 256}});
    qt.refineForViewer({at.x, at.y, 5.0}, ViewParams{.maxLevel = 11});
    DemHeightField heights(w.dem);
    CurveDataCache data(qt, heights);
    AppearanceParams full;
    full.detectUniform = false;
    std::size_t furrowed = 0;
    for (const Quad* q : quadsFrom(qt, 8)) {
        if (!q->isLeaf()) continue;
        const AppearanceTile t = produceAppearance(*q, qt, data, w.dem, {});
        if (!t.uniform || t.shade.surface != Surface::Field || t.delta > 1.0) continue;
        ++furrowed;
        EXPECT_TRUE(tileTexels(t) == produceAppearance(*q, qt, data, w.dem, full).rgbm) << "quad " << q->tx << "," << q->ty;
    }
    EXPECT_GT(furrowed, 5u);
}

TEST(AppearanceProducer, RiversWiderThanTheQuadMakeUniformWaterQuads) {
    test::SceneBuilder b(64.0);
    const ElementId a = b.node(kRiversLayer, {0, 30}), c = b.node(kRiversLayer, {64, 34});
    b.curve(kRiversLayer, a, c, {}, 40.0f, 50.0f);
    const Scene scene = std::move(b.scene());
    const Dem dem = test::gentleSlope(scene.extent);
    Quadtree qt(scene, RefineParams{{.resolution = 64}});
    qt.refineForViewer({0.0, 0.0, 1.0}, ViewParams{.K = 1e12, .maxLevel = 3});
    DemHeightField heights(dem);
    CurveDataCache data(qt, heights);
    AppearanceParams full;
    full.detectUniform = false;
    std::size_t uniform = 0;
    for (const Quad* q : quadsFrom(qt, 3)) {
        const AppearanceTile t = produceAppearance(*q, qt, data, dem, {});
        if (!t.uniform) continue;
        ++uniform;
        EXPECT_EQ(t.shade.surface, Surface::Water);
        EXPECT_TRUE(tileTexels(t) == produceAppearance(*q, qt, data, dem, full).rgbm);
    }
    EXPECT_GE(uniform, 8u);  // the quads of 8 m well inside the 40 m wide river
}

TEST(AppearanceProducer, IncrementalRegenerationEqualsProductionFromScratch) {
    AppearanceWorld w(6, 1500);
    const RefineParams rp{{.resolution = 32}};
    Quadtree qt(w.scene, rp);
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 30.0}, ViewParams{.maxLevel = 9});
    CurveDataCache data(qt, w.heights);
    auto produceAll = [&](const Quadtree& tree, const CurveDataCache& cache) {
        std::map<Key, std::pair<AppearanceTile, ElevationTile>> tiles;
        tree.forEachQuad([&](const Quad& q) {
            if (q.level >= 1)
                tiles.emplace(appearanceKeyOf(q), std::pair{produceAppearance(q, tree, cache, w.dem, {}), produceElevation(q, tree, cache, w.dem, {})});
        });
        return tiles;
    };
    auto tiles = produceAll(qt, data);
    std::mt19937_64 rng(16);
    std::size_t regenerated = 0, edits = 0;
    const int kEdits = test::sanitizedOr(30, 12);
    for (int e = 0; e < kEdits; ++e) {
        const RandomEdit edit = applyRandomEdit(w.scene, rng, 0.02 * w.scene.extent.size().x);
        if (edit.changeset.empty()) continue;
        ++edits;
        data.invalidate(edit.changeset);
        const UpdateStats st = qt.update(edit.changeset);
        for (const Quad* q : st.changedQuads)
            tiles[appearanceKeyOf(*q)] = {produceAppearance(*q, qt, data, w.dem, {}), produceElevation(*q, qt, data, w.dem, {})};
        regenerated += st.changedQuads.size();
        Quadtree fresh(w.scene, rp);
        fresh.copyStructureOf(qt);
        CurveDataCache freshData(fresh, w.heights);
        const auto expected = produceAll(fresh, freshData);
        ASSERT_EQ(expected.size(), tiles.size());
        for (const auto& [k, t] : expected) {
            EXPECT_TRUE(tiles.at(k).first == t.first) << "appearance, edit " << e << " (" << toString(edit.kind) << ")";
            EXPECT_TRUE(tiles.at(k).second == t.second) << "elevation, edit " << e << " (" << toString(edit.kind) << ")";
        }
    }
    EXPECT_GT(edits, std::size_t(kEdits / 2));
    EXPECT_LT(regenerated, edits * tiles.size() / 4) << "only the quads whose graph changed are regenerated";
    std::cout << "[ figures  ] " << edits << " edits regenerated " << regenerated << " of " << edits * tiles.size()
              << " tile pairs\n";
}

TEST(AppearanceProducer, ATileDoesNotDependOnTheTilesMadeBeforeItOnItsThread) {
    // A thread's canvas is reused from tile to tile without being cleared (every pass clears what
    // it set): the same tiles made in opposite orders, on this thread, must be identical.
    AppearanceWorld w(2, 3000);
    Quadtree qt(w.scene, RefineParams{{.resolution = 128}});
    // Near a road junction, down to quads of 14 m (texels of 11 cm: markings show).
    const Vec2 junction = w.scene.layers[kRoadsLayer].nodes[w.scene.layers[kRoadsLayer].nodes.size() / 2].p;
    qt.refineForViewer({junction.x, junction.y, 20.0}, ViewParams{.maxLevel = 9});
    CurveDataCache data(qt, w.heights);
    const auto quads = quadsFrom(qt, 4);
    std::vector<AppearanceTile> forward, backward(quads.size());
    AppearanceCounters counters;
    for (const Quad* q : quads) forward.push_back(produceAppearance(*q, qt, data, w.dem, {}, &counters));
    for (std::size_t i = quads.size(); i-- > 0;) backward[i] = produceAppearance(*quads[i], qt, data, w.dem, {});
    for (std::size_t i = 0; i < quads.size(); ++i) EXPECT_TRUE(forward[i] == backward[i]) << "quad " << i;
    // And directly: the thread's canvas is left clean.
    const appearance::Scratch& scratch = appearance::threadScratch();
    EXPECT_TRUE(scratch.clean);
    EXPECT_EQ(std::count(scratch.flags.begin(), scratch.flags.end(), 0), std::ptrdiff_t(scratch.flags.size()));
    EXPECT_EQ(std::count(scratch.dist.begin(), scratch.dist.end(), appearance::kInf), std::ptrdiff_t(scratch.dist.size()));
    // The scene has every kind of pass.
    EXPECT_GT(counters.areaPieces, 0u);
    EXPECT_GT(counters.curvesDrawn, 0u);
    EXPECT_GT(counters.curvesWithMarkings, 0u);
}

TEST(AppearanceProducer, AnAreaWithoutAStripBlendsOnlyItsSurfaceOverTheGround) {
    // A lake with wf = 0: every texel is the ground and the water mixed by the water's coverage
    // (the mask channel), nothing of the border strip's colour, inside the border or out.
    test::SceneBuilder lake(64.0);
    lake.area(kLakesLayer, {lake.circle(kLakesLayer, {32.0, 32.0}, 20.0)}, 0.0f);
    const Scene bare = test::SceneBuilder(64.0).scene();
    const Dem dem = test::gentleSlope(bare.extent);
    DemHeightField heights(dem);
    auto texels = [&](const Scene& scene) {
        Quadtree qt(scene, RefineParams{{.resolution = 128}});
        qt.subdivide(qt.root());
        CurveDataCache data(qt, heights);
        std::vector<std::vector<std::uint8_t>> out;
        for (const auto& child : qt.root().children) out.push_back(tileTexels(produceAppearance(*child, qt, data, dem, {})));
        return out;
    };
    const auto withLake = texels(lake.scene()), ground = texels(bare);
    const Rgbm water = surfaceColour({Surface::Water, 0, 0}, Vec2(0.0), 1.0);
    std::size_t border = 0;
    double worst = 0.0;
    for (std::size_t k = 0; k < 4; ++k)
        for (std::size_t i = 0; i < withLake[k].size(); i += 4) {
            const double m = withLake[k][i + 3] / 255.0;
            border += m > 0.0 && m < 1.0;
            for (std::size_t c = 0; c < 3; ++c) {
                const double expected = ground[k][i + c] * (1.0 - m) + 255.0 * water[int(c)] * m;
                worst = std::max(worst, std::abs(withLake[k][i + c] - expected));
            }
        }
    EXPECT_GT(border, 200u);  // the circle's border, about a texel wide
    EXPECT_LT(worst, 1.6) << "levels of 255";
}

// A river area (§4.1: a large river's water) is drawn as water, mask set, over the banks of the
// river running through it (a bank strip inside the area would be land in the river) and under
// the river's own water; beyond the area the river keeps its banks.
TEST(AppearanceProducer, RiverAreasAreWaterOverTheirRiversBanks) {
    constexpr double kRiverX = 32.0, kHalfW = 3.0, kHalfWf = 6.0;  // metres
    const Box area{{20.0, 12.0}, {44.0, 52.0}};                     // metres
    test::SceneBuilder b(64.0);
    const ElementId up = b.node(kRiversLayer, {kRiverX, 64.0}), down = b.node(kRiversLayer, {kRiverX, 0.0});
    const ElementId river = b.curve(kRiversLayer, up, down, {}, float(2.0 * kHalfW), float(2.0 * kHalfWf));
    const Vec2 corners[4] = {area.min, {area.max.x, area.min.y}, area.max, {area.min.x, area.max.y}};
    ElementId n[4];
    for (int i = 0; i < 4; ++i) n[i] = b.node(kRiversLayer, corners[i]);
    std::vector<AreaEdge> ring;
    for (int i = 0; i < 4; ++i) ring.push_back({b.curve(kRiversLayer, n[i], n[(i + 1) % 4], {}, 0.0f, 3.0f), false});
    const ElementId a = b.area(kRiversLayer, {ring}, 3.0f);
    b.scene().layers[kRiversLayer].areas[a].axial = river;
    const Scene& scene = b.scene();
    const Dem dem = test::gentleSlope(scene.extent);
    DemHeightField heights(dem);
    Quadtree qt(scene, RefineParams{{.resolution = 128}});
    qt.subdivide(qt.root());
    CurveDataCache data(qt, heights);
    const Rgbm water = surfaceColour({Surface::Water, 0, 0}, Vec2(0.0), 1.0);
    auto isWater = [&](const std::uint8_t* texel) {
        bool same = texel[3] == 255;
        for (int c = 0; c < 3; ++c) same = same && std::abs(texel[c] - 255.0 * water[c]) < 1.6;
        return same;
    };
    std::size_t inside = 0, insideBanks = 0, outsideBanks = 0;
    for (const auto& child : qt.root().children) {
        const AppearanceTile t = produceAppearance(*child, qt, data, dem, {});
        const std::vector<std::uint8_t> texels = tileTexels(t);
        for (int j = 0; j < t.resolution; ++j)
            for (int i = 0; i < t.resolution; ++i) {
                const Vec2 p = t.texelCentre(i, j);
                const std::uint8_t* texel = &texels[t.index(i, j)];
                const double fromAxis = std::abs(p.x - kRiverX);
                if (area.dilated(-1.0).contains(p)) {
                    EXPECT_TRUE(isWater(texel)) << "inside the river area at " << p.x << ", " << p.y;
                    ++inside;
                    insideBanks += fromAxis > kHalfW + 0.5 && fromAxis < kHalfWf - 0.5;
                } else if ((p.y > area.max.y + 5.0 || p.y < area.min.y - 5.0) && fromAxis > kHalfW + 0.5 && fromAxis < kHalfWf - 0.5) {
                    EXPECT_EQ(texel[3], 0) << "the river's banks beyond the area at " << p.x << ", " << p.y;
                    ++outsideBanks;
                } else if (fromAxis < kHalfW - 0.5) {
                    EXPECT_TRUE(isWater(texel)) << "the river's water at " << p.x << ", " << p.y;
                }
            }
    }
    EXPECT_GT(inside, 10000u);   // 0.25 m texels over 20 x 38 m
    EXPECT_GT(insideBanks, 2000u);
    EXPECT_GT(outsideBanks, 600u);
}

TEST(AppearanceProducer, ResultsDoNotDependOnTheThreadCount) {
    AppearanceWorld w(5, 2000);
    Quadtree qt(w.scene, RefineParams{{.resolution = 64}});
    const Vec2 c = w.scene.extent.center();
    qt.refineForViewer({c.x, c.y, 50.0}, ViewParams{.maxLevel = 8});
    const auto quads = quadsFrom(qt, 0);
    auto run = [&](int threads) {
        CurveDataCache data(qt, w.heights);
        tbb::task_arena arena(threads);
        std::vector<AppearanceTile> tiles;
        arena.execute([&] { tiles = produceAppearanceTiles(quads, qt, data, w.dem, {}); });
        return tiles;
    };
    EXPECT_TRUE(run(1) == run(2));
}

TEST(AppearanceProducer, MarkingsBelowATexelCostNoCurvilinearCoordinate) {
    AppearanceWorld w(8, 3000);
    Quadtree qt(w.scene);
    qt.refineForViewer({0.0, 0.0, 1e6}, ViewParams{.K = 1e6, .maxLevel = 2});  // texels of 7 m: no marking shows
    CurveDataCache data(qt, w.heights);
    AppearanceCounters counters;
    for (const Quad* q : quadsFrom(qt, 2)) produceAppearance(*q, qt, data, w.dem, {}, &counters);
    EXPECT_EQ(counters.tiles, 16u);
    EXPECT_GT(counters.markingsBelowTexel, 20u);
    EXPECT_EQ(counters.curvesWithMarkings, 0u);
    EXPECT_EQ(data.counters().arcLengthTables, 0u);
    EXPECT_EQ(data.counters().zProfiles, 0u);
}

TEST(AppearanceProducer, ScenesWithoutWaterDrawNoWater) {
    AppearanceWorld w(9, 2000);
    AppearanceCounters withWater, without;
    {
        Quadtree qt(w.scene, RefineParams{{.resolution = 64}});
        qt.refineForViewer({0.0, 0.0, 1e6}, ViewParams{.K = 1e6, .maxLevel = 3});
        CurveDataCache data(qt, w.heights);
        for (const Quad* q : quadsFrom(qt, 3)) produceAppearance(*q, qt, data, w.dem, {}, &withWater);
    }
    for (LayerId l : {kRiversLayer, kLakesLayer}) {
        w.scene.layers[l].nodes.clear();
        w.scene.layers[l].curves.clear();
        w.scene.layers[l].areas.clear();
    }
    Quadtree qt(w.scene, RefineParams{{.resolution = 64}});
    qt.refineForViewer({0.0, 0.0, 1e6}, ViewParams{.K = 1e6, .maxLevel = 3});
    CurveDataCache data(qt, w.heights);
    for (const Quad* q : quadsFrom(qt, 3)) produceAppearance(*q, qt, data, w.dem, {}, &without);
    EXPECT_GT(withWater.waterTexels, 1000u);
    EXPECT_EQ(without.waterTexels, 0u);
    EXPECT_EQ(without.tiles, withWater.tiles);
}

TEST(AppearanceProducer, JunctionSceneDrawsStopLinesWhereTheRuleSaysOnly) {
    // The T's through road has no stop line at the T: the texels across its lane just outside
    // the junction are asphalt; the stem's are marking-white.
    const std::vector<std::uint8_t> image = test::renderHandScene(test::junctionsScene());
    const double texel = 64.0 / 256.0;
    auto at = [&](Vec2 p) { return &image[(std::size_t(255 - int(p.y / texel)) * 256 + std::size_t(p.x / texel)) * 3]; };
    const MarkingGeometry g;
    const double stop = 3.5 + g.stopLineGap + 0.5 * g.stopLineWidth;  // from the node: junction radius 3.5 m
    // Stem (curve 5, from T node (46, 34) downwards, starting at the node): its incoming lane is
    // on the left of its direction of travel away from the node (v > 0), i.e. east of it.
    EXPECT_GT(int(at({46.0 + 1.2, 34.0 - stop})[0]), 200) << "stop line on the stem";
    // Through road east of the T (curve 2 from the T to the east): no stop line.
    EXPECT_LT(int(at({46.0 + stop, 34.0 + 1.2})[0]), 120) << "no stop line on the through road";
    // 4-way crossing: the road from the west ends there (incoming lane on its right, v < 0).
    EXPECT_GT(int(at({20.0 - stop, 34.0 - 1.8})[0]), 200) << "stop line at the 4-way crossing";
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Issue 12: where the scene extends beyond the DEM, heights are not measured: the ground there is
// shown as no data (kNoDataGround), not as terrain continued from the DEM's border.
TEST(AppearanceProducer, GroundBeyondTheDemIsShownAsNoData) {
    Scene scene;
    scene.extent = {{0.0, 0.0}, {1024.0, 1024.0}};
    scene.layers.emplace_back();
    scene.layers.back().kind = LayerKind::Roads;
    // The DEM covers the western half only (a slope, so the ground has colour there).
    std::vector<float> z(64 * 128);
    for (int j = 0; j < 128; ++j)
        for (int i = 0; i < 64; ++i) z[std::size_t(j) * 64 + std::size_t(i)] = float(1300.0 + 2.0 * i);
    const Dem dem({{0.0, 0.0}, {512.0, 1024.0}}, 64, 128, std::move(z));
    const DemHeightField heights(dem);
    Quadtree qt(scene);
    CurveDataCache data(qt, heights);
    const AppearanceTile t = produceAppearance(qt.root(), qt, data, dem, AppearanceParams{});
    const std::vector<std::uint8_t> texels = tileTexels(t);
    // The no-data colour as the resolve stores it: the texel in the east, far from the border.
    const std::size_t east = t.index(t.resolution - 8, t.resolution / 2);
    const double ground = t.bounds.size().x / 32.0;  // the ground grid's cell (32 cells a side here)
    std::size_t noData = 0, measured = 0;
    for (int j = 0; j < t.resolution; ++j)
        for (int i = 0; i < t.resolution; ++i) {
            const double x = t.texelCentre(i, j).x;
            const std::size_t k = t.index(i, j);
            const bool same = std::equal(texels.begin() + std::ptrdiff_t(k), texels.begin() + std::ptrdiff_t(k + 3),
                                         texels.begin() + std::ptrdiff_t(east));
            if (x > 512.0 + ground) {
                EXPECT_TRUE(same) << i << ", " << j;
                noData += same;
            }
            if (x < 512.0 - ground) {
                EXPECT_FALSE(same) << i << ", " << j;
                measured += !same;
            }
        }
    EXPECT_GT(noData, 0u);
    EXPECT_GT(measured, 0u);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(texels[east + std::size_t(c)] / 255.0f, kNoDataGround[c], 1.0f / 255.0f);
}

}  // namespace
}  // namespace lacet
