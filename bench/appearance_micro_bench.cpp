// Google Benchmark programs for the appearance producer (§5.1): the tiles a field-border drag
// remakes (bench edit), timed alone. A viewer 10 m above a field corner of a synthetic scene
// refines the quadtree (the default ViewParams); the leaves within 25 m of the corner that hold a piece of a
// field without covering the quad are produced, one thread. items_per_second is tiles per second.
#include <algorithm>

#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>

#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

struct FieldBorder {
    Scene scene = makeSyntheticScene({5, 20000});
    Dem dem = makeSyntheticDem(scene, {5, 5000});
    DemHeightField heights{dem};
    Quadtree quadtree{scene, RefineParams{}};
    CurveDataCache data{quadtree, heights};
    std::vector<const Quad*> quads;

    FieldBorder() {
        const auto& nodes = scene.layers[kFieldsLayer].nodes;
        const Vec2 corner = nodes[nodes.size() / 2].p;
        quadtree.refineForViewer({corner.x, corner.y, 10.0}, ViewParams{});
        quadtree.forEachQuad([&](const Quad& q) {
            if (!q.isLeaf() || glm::length(q.bounds.center() - corner) > 25.0) return;
            const auto& areas = q.layers[kFieldsLayer].areas;
            const bool border = std::any_of(areas.begin(), areas.end(), [](const auto& a) {
                return std::any_of(a.second.begin(), a.second.end(), [](const ClippedArea& p) { return !p.coversQuad; });
            });
            if (border) quads.push_back(&q);
        });
    }
};

void BM_FieldBorderTiles(benchmark::State& state) {
    static const FieldBorder world;
    for (auto _ : state)
        for (const Quad* q : world.quads) benchmark::DoNotOptimize(produceAppearance(*q, world.quadtree, world.data, world.dem, {}).rgbm.data());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(world.quads.size()));
    state.counters["tiles"] = double(world.quads.size());
}
BENCHMARK(BM_FieldBorderTiles)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace lacet
