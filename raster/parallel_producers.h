#pragma once
// Runs a producer over many quads on TBB worker threads. Each tile depends only on its quad, the
// quadtree, the DEM and the curve data, so the results are the same for any number of threads.
// The DEM is one for every quad, or each quad's own from a DemSource (raster/dem_source.h: a
// window of a streamed DEM at the level the quad needs).

#include <span>
#include <vector>

#include "raster/appearance_producer.h"
#include "raster/dem_source.h"
#include "raster/elevation_producer.h"

namespace lacet {

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const Dem& dem,
                                                 const ElevationParams& params, ElevationCounters* counters = nullptr);

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const Dem& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters = nullptr);

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const DemSource& dem,
                                                 const ElevationParams& params, ElevationCounters* counters = nullptr);

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const DemSource& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters = nullptr);

}  // namespace lacet
