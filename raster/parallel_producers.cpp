#include "raster/parallel_producers.h"

#include <tbb/parallel_for.h>

namespace lacet {

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const Dem& dem,
                                                 const ElevationParams& params, ElevationCounters* counters) {
    std::vector<ElevationTile> tiles(quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        tiles[i] = produceElevation(*quads[i], quadtree, curveData, dem, params, counters);
    });
    return tiles;
}

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const Dem& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters) {
    std::vector<AppearanceTile> tiles(quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        tiles[i] = produceAppearance(*quads[i], quadtree, curveData, dem, params, counters);
    });
    return tiles;
}

}  // namespace lacet
