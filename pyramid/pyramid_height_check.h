#pragma once
// Whether a pyramid's elevation tiles were made from the DEM level their quads need: `lacet check
// heights` (issue 23: "full resolution everywhere", the deep tiles from the LOD tree's finest
// samples, never a fixed coarse level).
//
// A stored elevation cell is the mean of its four corners' z_m (pyramid/pyramid_tiles.h:
// elevationCells), and away from the footprints z_m is the DEM's bilinear height z_o at the corner
// (raster/elevation_producer.h). So each checked tile is made again from the DEM alone, once per
// level of the LOD tree (every level, the root to the finest), and each cell is compared with the
// stored one. The level whose cells agree within `toleranceM` most often, when a tenth of them at
// least do, is the tile's source; the cells under roads, rivers and lakes differ from every level
// and only lower the counts. A tile whose best levels tie (a flat place: every level gives the same
// heights), or that agrees with no level, is undecided and proves nothing; the check passes when
// every decided tile is the needed level's and one tile at least decided. A level the check
// cannot read (a corrupt block) is refused by name.
//
// A scene whose DEM is held in memory (no LOD tree) has one level: the tiles must agree with it.
//
// Units: metres.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace lacet {

// The most tiles one check compares (their cells' differences are kept for the quantiles: 4096
// tiles of 24^2 cells are 9 MiB a DEM level).
inline constexpr int kMaxHeightCheckTiles = 4096;

struct PyramidHeightCheckParams {
    int level = -1;            // the pyramid level checked (-1: its deepest)
    int tiles = 64;            // tiles of that level checked, spread evenly over it (1 to kMaxHeightCheckTiles)
    double toleranceM = 1e-3;  // a cell agrees with a level when within this (m, > 0)
    double demBudgetMiB = 512.0;
};

// How one DEM level agrees with the checked tiles' cells.
struct HeightLevelMatch {
    int demLevel = 0;               // level of the LOD tree (0: the root); 0 for a DEM in memory
    double cellM = 0.0;             // metres between its samples
    std::size_t cellsWithin = 0;    // cells within the tolerance, over all checked tiles
    double medianM = 0.0, p90M = 0.0, maxM = 0.0;  // of |stored - made from this level|
    std::size_t tilesBest = 0;      // tiles this level agrees with best
};

struct PyramidHeightCheck {
    int level = 0;           // pyramid level checked
    int demLevels = 1;       // levels of the LOD tree (1: a DEM in memory)
    int neededLevel = 0;     // the tree level the quads of `level` read (DemLodLayout::levelFor)
    bool streamed = false;   // whether the DEM is a LOD tree
    std::size_t tilesChecked = 0, tilesMissing = 0, tilesUndecided = 0, cells = 0;
    std::vector<HeightLevelMatch> levels;  // coarsest first
    double toleranceM = 0.0;
    double ms = 0.0;
    // Every decided tile agrees best with the needed level, and at least one tile decided.
    bool passed() const;
    // Tiles agreeing best with a level other than the needed one.
    std::size_t tilesElsewhere() const;
    nlohmann::json json() const;
};

// Throws PyramidError (the file holds no complete pyramid with elevation, one made for another
// extent or state of the scene, a level it does not store), SceneFileError for the scene, and
// std::invalid_argument for bad parameters.
PyramidHeightCheck checkPyramidHeights(const std::string& scenePath, const std::string& pyramidPath,
                                       const PyramidHeightCheckParams& params = {});

}  // namespace lacet
