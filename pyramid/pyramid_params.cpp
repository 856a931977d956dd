// The knobs of a pyramid run (pyramid/pyramid_build.h): their defaults and ranges, the names of
// the tile encodings, and where a scene's pyramid goes.
#include <cmath>
#include <stdexcept>
#include <string>

#include "pyramid/pyramid_build.h"

namespace lacet {

std::string encodingName(const TileEncoding& e) {
    switch (e.format) {
        case TileFormat::Png: return "png:" + std::to_string(e.pngLevel);
        case TileFormat::Jpeg: return "jpeg:" + std::to_string(e.jpegQuality);
        case TileFormat::Webp: return "webp:" + std::to_string(e.webpQuality);
    }
    return "?";
}

TileEncoding parseEncoding(const std::string& text) {
    const auto colon = text.find(':');
    const std::string name = text.substr(0, colon);
    TileEncoding e;
    int value = -1;
    if (colon != std::string::npos) {
        try {
            std::size_t used = 0;
            value = std::stoi(text.substr(colon + 1), &used);
            if (used != text.size() - colon - 1) value = -1000;
        } catch (const std::exception&) {
            value = -1000;
        }
    }
    const auto bad = [&](const char* range) {
        return std::invalid_argument("encoding '" + text + "': expected png[:LEVEL 0..9], jpeg[:QUALITY 1..100] or webp[:QUALITY 0..100] (" +
                                     range + ")");
    };
    if (name == "png") {
        e.format = TileFormat::Png;
        if (value != -1 && (value < 0 || value > 9)) throw bad("zlib level 0..9");
        if (value != -1) e.pngLevel = value;
    } else if (name == "jpeg" || name == "jpg") {
        e.format = TileFormat::Jpeg;
        if (value != -1 && (value < 1 || value > 100)) throw bad("quality 1..100");
        if (value != -1) e.jpegQuality = value;
    } else if (name == "webp") {
        e.format = TileFormat::Webp;
        if (value != -1 && (value < 0 || value > 100)) throw bad("quality 0..100");
        if (value != -1) e.webpQuality = value;
    } else {
        throw bad("unknown format");
    }
    return e;
}

void PyramidParams::resolve(double extentSize, int tileSize, std::size_t sceneElements) {
    if (!(texel > 0.0) || !std::isfinite(texel)) throw std::invalid_argument("PyramidParams: texel must be > 0 metres");
    if (!(extentSize > 0.0)) throw std::invalid_argument("PyramidParams: the scene has an empty extent");
    if (!(demBudgetMiB > 0.0) || !std::isfinite(demBudgetMiB))
        throw std::invalid_argument("PyramidParams: the DEM budget must be a positive number of MiB (got " + std::to_string(demBudgetMiB) + ")");
    if (!(vectorBudgetMiB > 0.0))
        throw std::invalid_argument("PyramidParams: the vector budget must be a positive number of MiB (got " +
                                    std::to_string(vectorBudgetMiB) + ")");
    if (maxLevel < 0) {
        // The level whose texel is nearest `texel` by ratio.
        maxLevel = 0;
        double best = INFINITY;
        for (int l = 0; l <= 24; ++l) {
            const double ratio = std::abs(std::log2(extentSize / double(std::int64_t(1) << l) / double(tileSize) / texel));
            if (ratio < best - 1e-12) {
                best = ratio;
                maxLevel = l;
            }
        }
    }
    if (minLevel < 0 || maxLevel < minLevel || maxLevel > 24)
        throw std::invalid_argument("PyramidParams: levels must satisfy 0 <= minLevel <= maxLevel <= 24 (got " +
                                    std::to_string(minLevel) + "-" + std::to_string(maxLevel) + ")");
    if (vectorLevels < 1) throw std::invalid_argument("PyramidParams: vectorLevels must be >= 1");
    vectorLevels = std::min(vectorLevels, maxLevel - minLevel + 1);  // as stored (PyramidInfo::vectorLevel)
    if (!(shardElements > 0.0))
        throw std::invalid_argument("PyramidParams: shardElements must be a positive count of curves and areas");
    if (shardLevel < 0) {
        shardLevel = std::max(0, maxLevel - 4);
        while (shardLevel < std::min(maxLevel, kMaxShardLevel) && double(sceneElements) / std::ldexp(1.0, 2 * shardLevel) > shardElements)
            ++shardLevel;
    }
    if (passLevels < 1) throw std::invalid_argument("PyramidParams: passLevels must be >= 1 (got " + std::to_string(passLevels) + ")");
    if (shardLevel > maxLevel) throw std::invalid_argument("PyramidParams: shardLevel must be <= maxLevel");
    if (shardLevel > kMaxShardLevel)
        throw std::invalid_argument("PyramidParams: shardLevel " + std::to_string(shardLevel) + " makes over 4^" +
                                    std::to_string(kMaxShardLevel) + " shards; choose --shard-level " + std::to_string(kMaxShardLevel) +
                                    " or less");
    double quads = 0.0;
    for (int l = minLevel; l <= maxLevel; ++l) quads += std::ldexp(1.0, 2 * l);
    if (quads > kMaxPyramidQuads)
        throw std::invalid_argument("PyramidParams: levels " + std::to_string(minLevel) + "-" + std::to_string(maxLevel) + " are " +
                                    std::to_string(quads) + " quads, over the " + std::to_string(kMaxPyramidQuads) +
                                    " a pyramid may hold; choose fewer levels (--levels) or a coarser --texel");
    if (!appearance && !elevation) throw std::invalid_argument("PyramidParams: no layer chosen (appearance, elevation)");
}

std::string defaultPyramidPath(const std::string& scenePath) {
    const std::string ext = ".gpkg";
    if (scenePath.size() > ext.size() && scenePath.compare(scenePath.size() - ext.size(), ext.size(), ext) == 0)
        return scenePath.substr(0, scenePath.size() - ext.size()) + ".pyramid.gpkg";
    return scenePath + ".pyramid.gpkg";
}

PyramidParams pyramidParams(const PyramidInfo& info) {
    PyramidParams p;
    p.minLevel = info.minLevel;
    p.maxLevel = info.maxLevel;
    p.vectorLevels = info.maxLevel - info.vectorLevel + 1;
    p.appearance = info.appearance;
    p.elevation = info.elevation;
    p.encoding = parseEncoding(info.encoding);
    return p;
}

}  // namespace lacet
