#include "raster/parallel_producers.h"

#include <tbb/parallel_for.h>

namespace lacet {

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const Dem& dem,
                                                 const ElevationParams& params, ElevationCounters* counters) {
    return produceElevationTiles(quads, quadtree, curveData, InMemoryDem(dem), params, counters);
}

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const Dem& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters) {
    return produceAppearanceTiles(quads, quadtree, curveData, InMemoryDem(dem), params, counters);
}

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const DemSource& dem,
                                                 const ElevationParams& params, ElevationCounters* counters) {
    std::vector<ElevationTile> tiles(quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        const std::shared_ptr<const Dem> d = dem.quadDem(*quads[i]);
        tiles[i] = produceElevation(*quads[i], quadtree, curveData, *d, params, counters);
    });
    return tiles;
}

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const DemSource& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters) {
    std::vector<AppearanceTile> tiles(quads.size());
    tbb::parallel_for(std::size_t(0), quads.size(), [&](std::size_t i) {
        const std::shared_ptr<const Dem> d = dem.quadDem(*quads[i]);
        tiles[i] = produceAppearance(*quads[i], quadtree, curveData, *d, params, counters);
    });
    return tiles;
}

}  // namespace lacet
