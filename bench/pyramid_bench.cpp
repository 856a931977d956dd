// `lacet bench pyramid`: what a pyramid build costs and what its choices cost in error
// (pyramid/pyramid_build.h). Each run builds into a temporary file, removed after.
#include <cmath>
#include <filesystem>
#include <map>

#include <glm/geometric.hpp>
#include <tbb/global_control.h>

#include "bench/tasks.h"
#include "io/scene_file.h"
#include "io/tile_codec.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_store.h"

namespace lacet::bench {
namespace {

namespace fs = std::filesystem;

struct TempPyramid {
    std::string path;
    explicit TempPyramid(const std::string& name)
        : path((fs::temp_directory_path() / ("lacet_bench_" + name + ".gpkg")).string()) {
        fs::remove(path);
    }
    ~TempPyramid() { fs::remove(path); }
};

nlohmann::json runJson(const PyramidStats& s) {
    const auto& t = s.times;
    return {{"wall_s", s.wallSeconds},
            {"tiles", s.tilesMade},
            {"appearance_tiles", s.appearanceTiles},
            {"tiles_per_s", s.wallSeconds > 0 ? double(s.tilesMade) / s.wallSeconds : 0.0},
            {"appearance_tiles_per_s", s.wallSeconds > 0 ? double(s.appearanceTiles) / s.wallSeconds : 0.0},
            {"bytes", s.bytes},
            {"thread_seconds",
             {{"clip", t.clip}, {"digest", t.digest}, {"elevation", t.elevation}, {"appearance", t.appearance},
              {"mipmap", t.mipmap}, {"encode", t.encode}, {"decode", t.decode}, {"write", t.write}}}};
}

PyramidStats build(const SceneDocument& doc, const std::string& path, PyramidParams p, int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return buildPyramid(doc, path, p, true, nullptr);
}

}  // namespace

nlohmann::json benchPyramid(const PyramidBenchOptions& o) {
    const SceneDocument doc = loadScene(o.scene);
    PyramidParams base;
    base.minLevel = o.minLevel;
    base.maxLevel = o.maxLevel;
    base.encoding = parseEncoding(o.encoding);
    nlohmann::json out;
    out["scene"] = o.scene;
    out["levels"] = {o.minLevel, o.maxLevel};
    out["encoding"] = o.encoding;

    // Threads: the same build on 1, 2, ... threads.
    nlohmann::json threads = nlohmann::json::array();
    double oneThread = 0.0;
    for (int n : o.threads) {
        TempPyramid t("threads");
        const PyramidStats s = build(doc, t.path, base, n);
        nlohmann::json j = runJson(s);
        j["threads"] = n;
        if (n == 1) oneThread = s.wallSeconds;
        if (oneThread > 0) j["speedup_over_1"] = oneThread / s.wallSeconds;
        threads.push_back(j);
    }
    out["threads"] = threads;

    // Encoders: the same build with each encoding (all threads).
    nlohmann::json encoders = nlohmann::json::array();
    for (const std::string& e : o.encodings) {
        TempPyramid t("encoding");
        PyramidParams p = base;
        p.encoding = parseEncoding(e);
        nlohmann::json j = runJson(build(doc, t.path, p, int(o.threads.empty() ? 2 : o.threads.back())));
        j["encoding"] = e;
        PyramidStore s(t.path, PyramidStore::Mode::ReadOnly);
        j["appearance_bytes"] = s.tileBytes(kAppearanceTable);
        encoders.push_back(j);
    }
    out["encodings"] = encoders;

    // One road edited: a control point of the road nearest the scene's centre among those with
    // an inner control point, moved 20 m across the road; then `pyramid update` against a build
    // from scratch of the edited scene, tile for tile.
    if (o.editRoad) {
        TempPyramid updated("updated"), rebuilt("rebuilt");
        const PyramidStats before = buildPyramid(doc, updated.path, base, true, nullptr);
        SceneDocument edited = doc;
        const Vec2 centre = (doc.scene.extent.min + doc.scene.extent.max) * 0.5;
        LayerId roadLayer = 0;
        ElementId best = kNoElement;
        double bestDistance = INFINITY;
        for (LayerId l = 0; l < edited.scene.layers.size(); ++l) {
            if (edited.scene.layers[l].kind != LayerKind::Roads) continue;
            const Layer& layer = edited.scene.layers[l];
            for (ElementId c = 0; c < layer.curves.size(); ++c) {
                const Curve& cv = layer.curves[c];
                if (!cv.alive || cv.vertices.size() < 4 || cv.vertices[1].onCurve || cv.flags != 0) continue;
                const double d = glm::length(cv.vertices[1].p - centre);
                if (d < bestDistance) bestDistance = d, best = c, roadLayer = l;
            }
        }
        if (best == kNoElement) throw std::invalid_argument("bench pyramid --edit-road: the scene has no road with a control point");
        Curve& road = edited.scene.layers[roadLayer].curves[best];
        const Vec2 along = road.vertices.back().p - road.vertices.front().p;
        const Vec2 across = glm::length(along) > 0 ? Vec2(-along.y, along.x) / glm::length(along) : Vec2(1.0, 0.0);
        road.vertices[1].p += 20.0 * across;
        const PyramidStats up = updatePyramid(edited, updated.path, nullptr);
        const PyramidStats full = buildPyramid(edited, rebuilt.path, base, true, nullptr);
        PyramidStore a(updated.path, PyramidStore::Mode::ReadOnly), b(rebuilt.path, PyramidStore::Mode::ReadOnly);
        std::size_t compared = 0, differ = 0;
        for (const char* table : {kAppearanceTable, kWaterTable, kElevationTable}) {
            const auto ta = a.allTiles(table), tb = b.allTiles(table);
            if (ta.size() != tb.size()) differ += std::max(ta.size(), tb.size()) - std::min(ta.size(), tb.size());
            for (std::size_t i = 0; i < std::min(ta.size(), tb.size()); ++i) {
                ++compared;
                if (!(ta[i].first == tb[i].first) || ta[i].second != tb[i].second) ++differ;
            }
        }
        out["edit_road"] = {{"road", {{"layer", roadLayer}, {"curve", best}, {"moved_m", 20.0}}},
                            {"tiles_total", before.tilesMade},
                            {"quads", up.quads},
                            {"quads_changed", up.quadsChanged},
                            {"tiles_remade", up.tilesMade},
                            {"tiles_written", up.tilesWritten},
                            {"update_wall_s", up.wallSeconds},
                            {"rebuild_wall_s", full.wallSeconds},
                            {"tiles_compared_with_rebuild", compared},
                            {"tiles_differing_from_rebuild", differ}};
    }

    // Mipmapped levels against the same levels made from vector data (PNG: no coding error in
    // either), per level: the colour difference over every texel.
    if (o.mipError) {
        TempPyramid mip("mip"), vec("vector");
        PyramidParams p = base;
        p.encoding = parseEncoding("png:1");
        p.vectorLevels = 1;
        const PyramidStats sm = build(doc, mip.path, p, 2);
        p.vectorLevels = o.maxLevel - o.minLevel + 1;
        const PyramidStats sv = build(doc, vec.path, p, 2);
        PyramidStore a(mip.path, PyramidStore::Mode::ReadOnly), b(vec.path, PyramidStore::Mode::ReadOnly);
        const auto ta = a.allTiles(kAppearanceTable), tb = b.allTiles(kAppearanceTable);
        struct LevelError {
            double sum2 = 0.0, sumAbs = 0.0, max = 0.0, count = 0.0, over16 = 0.0;
        };
        std::map<int, LevelError> levels;
        for (std::size_t i = 0; i < ta.size() && i < tb.size(); ++i) {
            const DecodedImage ia = decodeImage(ta[i].second), ib = decodeImage(tb[i].second);
            LevelError& e = levels[ta[i].first.level];
            for (std::size_t k = 0; k < ia.pixels.size(); ++k) {
                const double d = std::abs(double(ia.pixels[k]) - double(ib.pixels[k]));
                e.sum2 += d * d;
                e.sumAbs += d;
                e.max = std::max(e.max, d);
                e.count += 1.0;
                e.over16 += d > 16.0 ? 1.0 : 0.0;
            }
        }
        nlohmann::json err = nlohmann::json::array();
        for (const auto& [level, e] : levels)
            err.push_back({{"level", level},
                           {"rmse", std::sqrt(e.sum2 / e.count)},
                           {"mean_abs", e.sumAbs / e.count},
                           {"max_abs", e.max},
                           {"fraction_over_16", e.over16 / e.count}});
        out["mipmap_error"] = {{"per_level", err},
                               {"note", "8-bit channel values; mipmapped (deepest level from vector data, the rest 2x2 means) "
                                        "against every level from vector data, both PNG"},
                               {"wall_s_mipmapped", sm.wallSeconds},
                               {"wall_s_all_vector", sv.wallSeconds}};
    }
    return out;
}

}  // namespace lacet::bench
