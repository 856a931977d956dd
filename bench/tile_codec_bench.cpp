// Google Benchmark programs for the tile encoders of a GeoPackage pyramid (io/tile_codec.h), on real
// appearance tiles: the quadtree of a synthetic scene refined for a viewer 60 m above a road, every
// quad's tile produced and made a 256 x 256 RGB picture (border and water mask dropped, rows from the
// north), those of one colour dropped (uniform quads, field interiors: a pyramid can store them
// once), 32 kept evenly across levels (root to leaves).
// One iteration encodes one tile, going round the 32; the counter `bytes` is the mean tile size.
// The elevation encoder (float32 TIFF) is timed on the 24 x 24 z_m samples of a produced elevation
// tile.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "io/tile_codec.h"
#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

constexpr std::size_t kTiles = 32;

struct RgbTile {
    int side = 0;  // texels
    std::vector<std::uint8_t> rgb;
};

// The texels of a produced tile inside its quad, RGB, rows from the top (north) first.
RgbTile pictureOf(const AppearanceTile& tile) {
    const std::vector<std::uint8_t> texels = tileTexels(tile);
    RgbTile out{tile.resolution, std::vector<std::uint8_t>(std::size_t(tile.resolution) * std::size_t(tile.resolution) * 3)};
    for (int j = 0; j < tile.resolution; ++j)
        for (int i = 0; i < tile.resolution; ++i) {
            const std::uint8_t* t = texels.data() + tile.index(i, j);
            std::uint8_t* p = out.rgb.data() + (std::size_t(tile.resolution - 1 - j) * std::size_t(tile.resolution) + std::size_t(i)) * 3;
            std::copy_n(t, 3, p);
        }
    return out;
}

bool oneColour(const RgbTile& t) {
    for (std::size_t i = 3; i < t.rgb.size(); i += 3)
        if (!std::equal(t.rgb.begin(), t.rgb.begin() + 3, t.rgb.begin() + std::ptrdiff_t(i))) return false;
    return true;
}

struct Tiles {
    std::vector<RgbTile> rgb;
    std::vector<float> heights;  // 24 x 24
    int heightSide = 0;

    Tiles() {
        const Scene scene = makeSyntheticScene({7, 20000});
        const Dem dem = makeSyntheticDem(scene, {7, 5000});
        const DemHeightField field(dem);
        Quadtree quadtree(scene, RefineParams{});
        CurveDataCache data(quadtree, field);
        const auto& roads = scene.layers[kRoadsLayer].nodes;
        const Vec2 above = roads[roads.size() / 3].p;
        quadtree.refineForViewer({above.x, above.y, 60.0}, ViewParams{});
        std::vector<const Quad*> quads;
        quadtree.forEachQuad([&](const Quad& q) { quads.push_back(&q); });
        std::stable_sort(quads.begin(), quads.end(), [](const Quad* a, const Quad* b) { return a->level < b->level; });
        std::vector<RgbTile> all;
        for (const Quad* q : quads) {
            const AppearanceTile tile = produceAppearance(*q, quadtree, data, dem, {});
            RgbTile picture = pictureOf(tile);
            if (!oneColour(picture)) all.push_back(std::move(picture));
        }
        for (std::size_t k = 0; k < std::min(kTiles, all.size()); ++k) rgb.push_back(all[k * all.size() / std::min(kTiles, all.size())]);

        const ElevationTile e = produceElevation(*quads.back(), quadtree, data, dem, {});
        heightSide = e.resolution;
        for (int j = heightSide - 1; j >= 0; --j)
            for (int i = 0; i < heightSide; ++i) heights.push_back(e.zm[e.index(i, j)]);
    }
};

const Tiles& tiles() {
    static const Tiles t;
    return t;
}

template <class Encode>
void encodeTiles(benchmark::State& state, Encode encode) {
    const auto& t = tiles().rgb;
    std::size_t k = 0;
    double bytes = 0.0;
    for (auto _ : state) {
        const RgbTile& tile = t[k++ % t.size()];
        const std::vector<std::uint8_t> out = encode(tile);
        bytes += double(out.size());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["bytes"] = benchmark::Counter(bytes, benchmark::Counter::kAvgIterations);
    state.counters["tiles"] = double(t.size());
}

// PNG at zlib level range(0), rows filtered with kPngFilter (what encodeRgb does).
void BM_Png(benchmark::State& state) {
    TileEncoding e;
    e.format = TileFormat::Png;
    e.pngLevel = int(state.range(0));
    encodeTiles(state, [&](const RgbTile& t) { return encodeRgb(t.rgb, t.side, t.side, e); });
}
BENCHMARK(BM_Png)->Arg(1)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

// The choice of kPngFilter: filter range(0) (0 none, 1 sub, 2 adaptive) at level range(1).
void BM_PngFilter(benchmark::State& state) {
    const auto filter = PngFilter(state.range(0));
    const int level = int(state.range(1));
    encodeTiles(state, [&](const RgbTile& t) { return encodePng(t.rgb, t.side, t.side, 3, level, filter); });
}
BENCHMARK(BM_PngFilter)->ArgsProduct({{0, 1, 2}, {1, 6}})->Unit(benchmark::kMillisecond);

// JPEG at quality range(0).
void BM_Jpeg(benchmark::State& state) {
    TileEncoding e;
    e.format = TileFormat::Jpeg;
    e.jpegQuality = int(state.range(0));
    encodeTiles(state, [&](const RgbTile& t) { return encodeRgb(t.rgb, t.side, t.side, e); });
}
BENCHMARK(BM_Jpeg)->Arg(75)->Arg(85)->Arg(90)->Unit(benchmark::kMillisecond);

// Lossy WebP at quality range(0), method range(1) (0 fastest, 4 libwebp's default).
void BM_Webp(benchmark::State& state) {
    const int quality = int(state.range(0)), method = int(state.range(1));
    encodeTiles(state, [&](const RgbTile& t) { return encodeWebp(t.rgb, t.side, t.side, quality, method); });
}
BENCHMARK(BM_Webp)->ArgsProduct({{75, 90}, {0, 4}})->Unit(benchmark::kMillisecond);

// The float32 TIFF of an elevation tile's 24 x 24 samples.
void BM_FloatTiff(benchmark::State& state) {
    const Tiles& t = tiles();
    double bytes = 0.0;
    for (auto _ : state) {
        const std::vector<std::uint8_t> out = encodeFloatTiff(t.heights, t.heightSide, t.heightSide);
        bytes += double(out.size());
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["bytes"] = benchmark::Counter(bytes, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_FloatTiff)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace lacet
