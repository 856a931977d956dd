#pragma once
// What a pyramid file holds and whether every tile reads back: `lacet info PYRAMID` and `lacet
// pyramid info`. Each stored tile is decoded; one that does not decode, has the wrong size or
// bands, or holds a non-finite height is reported (table, level, column, row, reason) instead of
// being shown as garbage; a tile missing from the colour or elevation table of a complete pyramid
// too.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pyramid/pyramid_store.h"

namespace lacet {

struct PyramidTileProblem {
    std::string table;
    PyramidKey quad;
    std::string reason;
};

struct PyramidCheck {
    PyramidInfo info;
    std::size_t appearanceTiles = 0, waterTiles = 0, elevationTiles = 0;
    std::uint64_t appearanceBytes = 0, waterBytes = 0, elevationBytes = 0;
    std::vector<PyramidTileProblem> problems;
    nlohmann::json json() const;
};

// Throws PyramidError when the file holds no pyramid or cannot be opened.
PyramidCheck checkPyramid(const std::string& path);

}  // namespace lacet
