// `lacet bench pyramid`: what a pyramid build costs and what its choices cost in error
// (pyramid/pyramid_build.h). Each run builds into a temporary file, removed after.
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>

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

// The appearance tiles of two pyramids of the same levels compared texel by texel (8-bit
// channels, every tile both hold), per level.
struct LevelError {
    double sum2 = 0.0, sumAbs = 0.0, max = 0.0, count = 0.0, over16 = 0.0;
    void add(const LevelError& o) {
        sum2 += o.sum2, sumAbs += o.sumAbs, max = std::max(max, o.max), count += o.count, over16 += o.over16;
    }
    nlohmann::json json() const {
        // PSNR over 8-bit channels; identical tiles have none (null) and say so.
        const nlohmann::json psnr = sum2 > 0.0 ? nlohmann::json(10.0 * std::log10(255.0 * 255.0 * count / sum2)) : nlohmann::json();
        return {{"rmse", std::sqrt(sum2 / count)}, {"mean_abs", sumAbs / count}, {"max_abs", max},
                {"fraction_over_16", over16 / count}, {"psnr_db", psnr}, {"identical", sum2 == 0.0}};
    }
};

std::map<int, LevelError> compareAppearance(const std::string& pathA, const std::string& pathB) {
    PyramidStore a(pathA, PyramidStore::Mode::ReadOnly), b(pathB, PyramidStore::Mode::ReadOnly);
    const auto ta = a.allTiles(kAppearanceTable), tb = b.allTiles(kAppearanceTable);
    if (ta.size() != tb.size()) throw std::runtime_error("bench pyramid: the pyramids compared hold different tiles");
    std::map<int, LevelError> levels;
    for (std::size_t i = 0; i < ta.size(); ++i) {
        if (!(ta[i].first == tb[i].first)) throw std::runtime_error("bench pyramid: the pyramids compared hold different tiles");
        const DecodedImage ia = decodeImage(ta[i].second), ib = decodeImage(tb[i].second);
        if (ia.pixels.size() != ib.pixels.size()) throw std::runtime_error("bench pyramid: tiles of different sizes compared");
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
    return levels;
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

    // Encoders: the same build with each encoding (all threads), its appearance against the same
    // build in PNG (lossless): the coding error, carried up the mipmapped levels as a user sees it.
    nlohmann::json encoders = nlohmann::json::array();
    const int allThreads = int(o.threads.empty() ? 2 : o.threads.back());
    std::optional<TempPyramid> lossless;
    if (!o.encodings.empty()) {
        lossless.emplace("lossless");
        PyramidParams p = base;
        p.encoding = parseEncoding("png:1");
        build(doc, lossless->path, p, allThreads);
    }
    for (const std::string& e : o.encodings) {
        TempPyramid t("encoding");
        PyramidParams p = base;
        p.encoding = parseEncoding(e);
        nlohmann::json j = runJson(build(doc, t.path, p, allThreads));
        j["encoding"] = e;
        {
            PyramidStore s(t.path, PyramidStore::Mode::ReadOnly);
            j["appearance_bytes"] = s.tileBytes(kAppearanceTable);
        }
        LevelError all;
        for (const auto& [level, err] : compareAppearance(t.path, lossless->path)) {
            all.add(err);
            if (level == o.maxLevel) j["against_png_deepest_level"] = err.json();
        }
        j["against_png"] = all.json();
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
    // either), per level and over all levels, for each count of levels made from vector data
    // (PyramidParams::vectorLevels; the rest are 2x2 means of their children).
    if (o.mipError) {
        TempPyramid vec("vector");
        PyramidParams p = base;
        p.encoding = parseEncoding("png:1");
        p.vectorLevels = o.maxLevel - o.minLevel + 1;
        const PyramidStats sv = build(doc, vec.path, p, allThreads);
        nlohmann::json rows = nlohmann::json::array();
        for (int levels : o.vectorLevels.empty() ? std::vector<int>{1} : o.vectorLevels) {
            if (levels < 1 || levels > o.maxLevel - o.minLevel + 1)
                throw std::invalid_argument("bench pyramid --vector-levels: " + std::to_string(levels) + " is not within 1.." +
                                            std::to_string(o.maxLevel - o.minLevel + 1));
            TempPyramid mip("mip");
            p.vectorLevels = levels;
            const PyramidStats sm = build(doc, mip.path, p, allThreads);
            nlohmann::json perLevel = nlohmann::json::array();
            LevelError all;
            for (const auto& [level, e] : compareAppearance(mip.path, vec.path)) {
                all.add(e);
                nlohmann::json j = e.json();
                j["level"] = level;
                perLevel.push_back(j);
            }
            rows.push_back({{"vector_levels", levels}, {"wall_s", sm.wallSeconds}, {"appearance_tiles", sm.appearanceTiles},
                            {"all_levels", all.json()}, {"per_level", perLevel}});
        }
        out["mipmap_error"] = {{"rows", rows},
                               {"note", "8-bit channel values; the deepest vector_levels levels from vector data, the rest 2x2 means, "
                                        "against every level from vector data, both PNG"},
                               {"wall_s_all_vector", sv.wallSeconds}};
    }
    return out;
}

}  // namespace lacet::bench
