#include "pyramid/pyramid_check.h"

#include <cmath>

#include "io/tile_codec.h"

namespace lacet {

nlohmann::json PyramidCheck::json() const {
    nlohmann::json j;
    j["levels"] = {info.minLevel, info.maxLevel};
    j["vector_level"] = info.vectorLevel;
    j["encoding"] = info.encoding;
    j["complete"] = info.complete;
    j["extent"] = {info.extent.min.x, info.extent.min.y, info.extent.max.x, info.extent.max.y};
    j["tiles"] = {{"appearance", appearanceTiles}, {"water", waterTiles}, {"elevation", elevationTiles}};
    j["bytes"] = {{"appearance", appearanceBytes}, {"water", waterBytes}, {"elevation", elevationBytes}};
    nlohmann::json p = nlohmann::json::array();
    for (const auto& pr : problems)
        p.push_back({{"table", pr.table}, {"level", pr.quad.level}, {"column", pr.quad.tx},
                     {"row", (std::int64_t(1) << pr.quad.level) - 1 - std::int64_t(pr.quad.ty)}, {"reason", pr.reason}});
    j["problems"] = p;
    return j;
}

PyramidCheck checkPyramid(const std::string& path) {
    PyramidStore store(path, PyramidStore::Mode::ReadOnly);
    PyramidCheck c;
    const auto info = store.info();
    if (!info) throw PyramidError(path + ": the file holds no Lacet pyramid (lacet_pyramid table)");
    c.info = *info;
    const auto check = [&](const char* table, int size, int channels, std::size_t& count, std::uint64_t& bytes,
                           bool required) {
        QuadDigestMap seen;
        for (auto& [k, blob] : store.allTiles(table)) {
            ++count;
            bytes += blob.size();
            seen[k] = 1;
            std::string reason;
            try {
                if (channels == 0) {
                    const DecodedFloats f = decodeFloatTiff(blob);
                    if (f.width != size || f.height != size) reason = "not " + std::to_string(size) + "x" + std::to_string(size);
                    for (float v : f.values)
                        if (!std::isfinite(v)) {
                            reason = "a height that is not a finite number";
                            break;
                        }
                } else {
                    const DecodedImage d = decodeImage(blob);
                    if (d.width != size || d.height != size || d.channels != channels)
                        reason = std::to_string(d.width) + "x" + std::to_string(d.height) + " with " + std::to_string(d.channels) +
                                 " band(s), expected " + std::to_string(size) + "x" + std::to_string(size) + " with " +
                                 std::to_string(channels);
                }
            } catch (const std::exception& e) {
                reason = std::string("does not decode: ") + e.what();
            }
            if (!reason.empty()) c.problems.push_back({table, k, reason});
        }
        if (!required || !info->complete) return;
        for (int l = info->minLevel; l <= info->maxLevel; ++l)
            for (std::uint32_t ty = 0; ty < (1u << l); ++ty)
                for (std::uint32_t tx = 0; tx < (1u << l); ++tx)
                    if (!seen.count(PyramidKey{l, tx, ty})) c.problems.push_back({table, PyramidKey{l, tx, ty}, "missing"});
    };
    if (info->appearance) {
        check(kAppearanceTable, info->tileSize, 3, c.appearanceTiles, c.appearanceBytes, true);
        check(kWaterTable, info->tileSize, 1, c.waterTiles, c.waterBytes, false);
    }
    if (info->elevation) check(kElevationTable, info->elevationSize, 0, c.elevationTiles, c.elevationBytes, true);
    return c;
}

}  // namespace lacet
