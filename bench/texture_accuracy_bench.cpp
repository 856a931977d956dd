// `lacet bench texture-accuracy`: what the producers' accuracy knobs cost in time and the error
// they leave against a high-accuracy reference, on the same quads of views near roads.
#include <algorithm>
#include <cmath>
#include <memory>
#include <tuple>

#include "model/graph_step.h"
#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "raster/appearance_producer.h"
#include "raster/dem_height_field.h"
#include "raster/elevation_producer.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

using Key = std::tuple<int, std::uint32_t, std::uint32_t>;

// The quads of levels >= minLevel after refining for viewers 20 m above a few road points.
std::vector<Key> viewQuads(Quadtree& qt, const Scene& s, int views, int minLevel, int maxLevel) {
    const Layer& roads = s.layers[kRoadsLayer];
    std::vector<Key> keys;
    for (int v = 0; v < views; ++v) {
        const Curve& c = roads.curves[(std::size_t(v) * 7919 + 13) % roads.curves.size()];
        const Vec2 p = c.vertices[c.vertices.size() / 2].p;
        qt.refineForViewer({p.x, p.y, 20.0}, ViewParams{.maxLevel = maxLevel});
        qt.forEachQuad([&](const Quad& q) {
            if (q.level >= minLevel && keys.size() < std::size_t(views) * 24 && q.level % 2 == 0) keys.push_back({q.level, q.tx, q.ty});
        });
    }
    return keys;
}

// Makes sure every key's quad exists (subdividing down to it).
const Quad* reach(Quadtree& qt, const Key& k) {
    Quad* q = &qt.root();
    const auto [level, tx, ty] = k;
    while (q->level < level) {
        if (q->isLeaf()) qt.subdivide(*q);
        const int shift = level - q->level - 1;
        q = q->children[std::size_t(int((tx >> shift) & 1u) | int(((ty >> shift) & 1u) << 1))].get();
    }
    return q;
}

// PSNR (dB) and largest channel difference of the RGB of the tiles' interior texels, `fine`
// box filtered down to the resolution of `coarse`: over all texels, and over the edge texels
// only (those where the filtered reference differs from a 4-neighbour by more than 8 levels in
// a channel: flat texels are exact at every setting, and would hide the error in the average).
struct ImageError {
    double sumSquares = 0.0, count = 0.0, edgeSquares = 0.0, edgeCount = 0.0;
    int worst = 0;
    void add(const AppearanceTile& fine, const AppearanceTile& coarse) {
        const auto a = tileTexels(fine), b = tileTexels(coarse);
        const int factor = fine.resolution / coarse.resolution, n = coarse.resolution;
        std::vector<double> ref(std::size_t(n) * std::size_t(n) * 3);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) {
                    double sum = 0.0;
                    for (int y = 0; y < factor; ++y)
                        for (int x = 0; x < factor; ++x) sum += a[fine.index(i * factor + x, j * factor + y) + std::size_t(c)];
                    ref[(std::size_t(j) * std::size_t(n) + std::size_t(i)) * 3 + std::size_t(c)] = std::round(sum / double(factor * factor));
                }
        auto at = [&](int i, int j, int c) { return ref[(std::size_t(j) * std::size_t(n) + std::size_t(i)) * 3 + std::size_t(c)]; };
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                bool edge = false;
                for (int c = 0; c < 3; ++c)
                    for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{-1, 0}, std::pair{0, 1}, std::pair{0, -1}}) {
                        const int x = std::clamp(i + di, 0, n - 1), y = std::clamp(j + dj, 0, n - 1);
                        edge = edge || std::abs(at(x, y, c) - at(i, j, c)) > 8.0;
                    }
                for (int c = 0; c < 3; ++c) {
                    const double d = at(i, j, c) - double(b[coarse.index(i, j) + std::size_t(c)]);
                    sumSquares += d * d;
                    count += 1.0;
                    if (edge) edgeSquares += d * d, edgeCount += 1.0;
                    worst = std::max(worst, int(std::abs(d)));
                }
            }
    }
    static double psnr(double squares, double n) { return squares > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / (squares / n)) : 99.0; }
    nlohmann::json json() const {
        return {{"psnr_db", psnr(sumSquares, count)}, {"edge_psnr_db", psnr(edgeSquares, edgeCount)},
                {"edge_texel_fraction", count > 0.0 ? edgeCount / count : 0.0}, {"max_channel_error", worst}};
    }
};

constexpr int kTimingRuns = 3;  // per setting; the median over runs and tiles is reported

}  // namespace

nlohmann::json benchTextureAccuracy(std::size_t curves, std::uint64_t seed, int views) {
    const Scene scene = makeSyntheticScene({seed, curves});
    const Dem dem = makeSyntheticDem(scene, {seed, 5000});
    const DemHeightField heights(dem);
    std::vector<Key> keys;
    {
        GraphStep qtStep(scene);
        Quadtree qt(scene, {}, &qtStep);
        keys = viewQuads(qt, scene, views, 8, 12);
    }
    nlohmann::json out;
    out["quads"] = keys.size();
    out["levels"] = "8, 10, 12 (quads of 50, 12.6, 3.1 m) of views 20 m above roads";

    // Anti-aliasing: samples per texel axis at 256, against 8 x 8.
    {
        GraphStep qtStep(scene);
        Quadtree qt(scene, {}, &qtStep);
        std::vector<const Quad*> quads;
        for (const Key& k : keys) quads.push_back(reach(qt, k));
        CurveDataCache data(qt, heights);
        auto produceAll = [&](int samples, std::vector<double>* times) {
            AppearanceParams p;
            p.samples = samples;
            std::vector<AppearanceTile> tiles;
            for (int run = 0; run < (times ? kTimingRuns : 1); ++run) {
                tiles.clear();
                for (const Quad* q : quads) {
                    const auto t0 = Clock::now();
                    tiles.push_back(produceAppearance(*q, qt, data, dem, p));
                    if (times) times->push_back(msSince(t0));
                }
            }
            return tiles;
        };
        const auto reference = produceAll(8, nullptr);
        nlohmann::json rows = nlohmann::json::array();
        for (int samples : {1, 2, 3, 4}) {
            std::vector<double> times;
            const auto tiles = produceAll(samples, &times);
            ImageError e;
            for (std::size_t k = 0; k < tiles.size(); ++k) e.add(reference[k], tiles[k]);
            nlohmann::json row = e.json();
            row["samples_per_texel"] = samples * samples;
            row["median_ms_per_tile"] = median(times);
            rows.push_back(row);
        }
        out["anti_aliasing"] = {{"resolution", 256}, {"reference_samples_per_texel", 64}, {"rows", rows}};
    }

    // Appearance resolution, against 1536 box-filtered down (same quads, refinement tolerance in
    // texels of each resolution).
    {
        constexpr int kReference = 1536;
        auto produceAt = [&](int resolution, std::vector<double>* times) {
            GraphStep qtStep(scene);
            Quadtree qt(scene, RefineParams{{.resolution = resolution}}, &qtStep);
            std::vector<const Quad*> quads;
            for (const Key& k : keys) quads.push_back(reach(qt, k));
            CurveDataCache data(qt, heights);
            std::vector<AppearanceTile> tiles;
            for (int run = 0; run < (times ? kTimingRuns : 1); ++run) {
                tiles.clear();
                for (const Quad* q : quads) {
                    const auto t0 = Clock::now();
                    tiles.push_back(produceAppearance(*q, qt, data, dem, {}));
                    if (times) times->push_back(msSince(t0));
                }
            }
            return tiles;
        };
        const auto reference = produceAt(kReference, nullptr);
        nlohmann::json rows = nlohmann::json::array();
        for (int resolution : {128, 192, 256, 512}) {
            std::vector<double> times;
            const auto tiles = produceAt(resolution, &times);
            ImageError e;
            for (std::size_t k = 0; k < tiles.size(); ++k) e.add(reference[k], tiles[k]);
            nlohmann::json row = e.json();
            row["resolution"] = resolution;
            row["median_ms_per_tile"] = median(times);
            rows.push_back(row);
        }
        out["appearance_resolution"] = {{"reference_resolution", kReference}, {"rows", rows}};
    }

    // Elevation tile resolution (cells per quad side), against 192: the height each tile gives
    // (z_m, bilinear between its samples, as the terrain mesh interpolates it) at every sample of
    // the reference inside the quad; also only where the reference's footprint is full (b = 1:
    // on roads, rivers and lakes).
    {
        constexpr int kReference = 192;
        auto produceAt = [&](int resolution, std::vector<double>* times) {
            GraphStep qtStep(scene);
            Quadtree qt(scene, RefineParams{{.elevationResolution = resolution}}, &qtStep);
            std::vector<const Quad*> quads;
            for (const Key& k : keys) quads.push_back(reach(qt, k));
            CurveDataCache data(qt, heights);
            for (const Quad* q : quads) produceElevation(*q, qt, data, dem, {});  // z-profiles computed: warm
            std::vector<ElevationTile> tiles;
            for (int run = 0; run < (times ? kTimingRuns : 1); ++run) {
                tiles.clear();
                for (const Quad* q : quads) {
                    const auto t0 = Clock::now();
                    tiles.push_back(produceElevation(*q, qt, data, dem, {}));
                    if (times) times->push_back(msSince(t0));
                }
            }
            return tiles;
        };
        // z_m of `t` at p (inside its quad), bilinear between its samples.
        const auto heightAt = [](const ElevationTile& t, Vec2 p) {
            const Vec2 g = (p - t.bounds.min) / t.delta;
            const int i = std::clamp(int(std::floor(g.x)), 0, t.resolution - 1), j = std::clamp(int(std::floor(g.y)), 0, t.resolution - 1);
            const double fx = g.x - double(i), fy = g.y - double(j);
            const double a = t.zm[t.index(i, j)], b = t.zm[t.index(i + 1, j)], c = t.zm[t.index(i, j + 1)], d = t.zm[t.index(i + 1, j + 1)];
            return (a + (b - a) * fx) * (1.0 - fy) + (c + (d - c) * fx) * fy;
        };
        const auto reference = produceAt(kReference, nullptr);
        nlohmann::json rows = nlohmann::json::array();
        for (int resolution : {12, 24, 48, 96}) {
            std::vector<double> times;
            const auto tiles = produceAt(resolution, &times);
            double worst = 0.0, worstFootprint = 0.0, sum2 = 0.0;
            std::size_t samples = 0;
            for (std::size_t k = 0; k < tiles.size(); ++k) {
                const ElevationTile& r = reference[k];
                for (int j = 0; j <= r.resolution; ++j)
                    for (int i = 0; i <= r.resolution; ++i) {
                        const double e = std::abs(heightAt(tiles[k], r.position(i, j)) - double(r.zm[r.index(i, j)]));
                        worst = std::max(worst, e);
                        if (r.b[r.index(i, j)] >= 1.0f) worstFootprint = std::max(worstFootprint, e);
                        sum2 += e * e;
                        ++samples;
                    }
            }
            rows.push_back({{"resolution", resolution},
                            {"median_ms_per_tile", median(times)},
                            {"max_height_error_m", worst},
                            {"rms_height_error_m", std::sqrt(sum2 / double(std::max<std::size_t>(samples, 1)))},
                            {"max_height_error_on_footprints_m", worstFootprint}});
        }
        out["elevation_resolution"] = {{"reference_resolution", kReference}, {"rows", rows}};
    }

    // z-profiles: sample spacing against 0.5 m, kernel radius against the terrain it smooths.
    // Cost: computing the z-profiles of every road and river of the scene (cold cache), per curve.
    // Error: max |z_m - reference| over the elevation tiles of the quads, and the largest
    // difference between the profiles themselves, sampled every metre.
    {
        GraphStep qtStep(scene);
        Quadtree qt(scene, {}, &qtStep);
        std::vector<const Quad*> quads;
        for (const Key& k : keys) quads.push_back(reach(qt, k));
        std::vector<std::pair<LayerId, ElementId>> curvesWithProfiles;
        for (LayerId l : {kRoadsLayer, kRiversLayer})
            for (ElementId id = 0; id < scene.layers[l].curves.size(); ++id) curvesWithProfiles.push_back({l, id});
        struct Result {
            std::unique_ptr<CurveDataCache> data;
            std::vector<ElevationTile> tiles;
            double usPerCurve = 0.0;
        };
        auto run = [&](ZProfileParams zp) {
            Result r;
            std::vector<double> runs;
            for (int t = 0; t < kTimingRuns; ++t) {
                r.data = std::make_unique<CurveDataCache>(qt, heights, zp);
                const auto t0 = Clock::now();
                for (const auto& [l, id] : curvesWithProfiles) r.data->zProfile(l, id);
                runs.push_back(msSince(t0) * 1000.0 / double(curvesWithProfiles.size()));
            }
            r.usPerCurve = median(runs);
            for (const Quad* q : quads) r.tiles.push_back(produceElevation(*q, qt, *r.data, dem, {}));
            return r;
        };
        const Result reference = run({0.5, 40.0, 1e-4});
        auto errors = [&](const Result& r, double& zm, double& profile) {
            zm = profile = 0.0;
            for (std::size_t k = 0; k < r.tiles.size(); ++k)
                for (std::size_t i = 0; i < r.tiles[k].zm.size(); ++i)
                    zm = std::max(zm, double(std::abs(r.tiles[k].zm[i] - reference.tiles[k].zm[i])));
            for (const auto& [l, id] : curvesWithProfiles) {
                const ZProfile& a = r.data->zProfile(l, id);
                const ZProfile& b = reference.data->zProfile(l, id);
                for (double u = 0.0; u <= a.length; u += 1.0) profile = std::max(profile, std::abs(a.at(u) - b.at(u)));
            }
        };
        nlohmann::json spacing = nlohmann::json::array();
        for (double sp : {2.5, 5.0, 10.0, 20.0, 40.0}) {
            const Result r = run({sp, 40.0, 1e-4});
            double zm = 0.0, profile = 0.0;
            errors(r, zm, profile);
            spacing.push_back({{"sample_spacing_m", sp}, {"us_per_curve", r.usPerCurve}, {"max_zm_error_m", zm},
                               {"max_profile_error_m", profile}});
        }
        nlohmann::json kernel = nlohmann::json::array();
        for (double radius : {10.0, 20.0, 40.0, 80.0}) {
            const Result r = run({10.0, radius, 1e-4});
            double departure = 0.0;
            for (const ElevationTile& t : r.tiles)
                for (std::size_t i = 0; i < t.zm.size(); ++i)
                    if (t.b[i] >= 1.0f) departure = std::max(departure, double(std::abs(t.zm[i] - t.zo[i])));
            kernel.push_back({{"kernel_radius_m", radius}, {"us_per_curve", r.usPerCurve}, {"max_road_departure_from_dem_m", departure}});
        }
        out["z_profile"] = {{"curves", curvesWithProfiles.size()}, {"quads", quads.size()}, {"reference_spacing_m", 0.5},
                            {"reference_kernel_radius_m", 40.0}, {"spacing", spacing}, {"kernel", kernel}};
    }
    return out;
}

}  // namespace lacet::bench
