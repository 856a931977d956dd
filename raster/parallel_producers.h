#pragma once
// Runs a producer over many quads on TBB worker threads. Each tile depends only on its quad, the
// quadtree, the DEM and the curve data, so the results are the same for any number of threads.
// The DEM is one for every quad, or each quad's own (a window of a streamed DEM at the level the
// quad needs, io/dem_stream.h), given by a function any thread may call.

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "raster/appearance_producer.h"
#include "raster/elevation_producer.h"

namespace lacet {

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const Dem& dem,
                                                 const ElevationParams& params, ElevationCounters* counters = nullptr);

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const Dem& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters = nullptr);

using QuadDem = std::function<std::shared_ptr<const Dem>(const Quad&)>;

std::vector<ElevationTile> produceElevationTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                 const CurveDataCache& curveData, const QuadDem& dem,
                                                 const ElevationParams& params, ElevationCounters* counters = nullptr);

std::vector<AppearanceTile> produceAppearanceTiles(std::span<const Quad* const> quads, const Quadtree& quadtree,
                                                   const CurveDataCache& curveData, const QuadDem& dem,
                                                   const AppearanceParams& params, AppearanceCounters* counters = nullptr);

}  // namespace lacet
