#pragma once
// Where a scene's rivers stand against its DEM (issue 14): a river runs on its valley floor and
// never rises. For every river curve (a Rivers layer's curve that is not an area's border), its
// z-profile samples (CurveDataCache) less the DEM under them, and every river node's height less
// the DEM at it, as quantiles; and the samples where a profile rises downstream. `lacet check
// rivers` prints the report.
//
// By parts (RiverCheck): a scene larger than memory read a piece at a time (io/scene_region.h),
// each piece giving the curves whose first vertex, and the nodes whose point, it owns; the report
// is the whole scene's, exact (the samples kept, 8 bytes each, for the quantiles).

#include <chrono>
#include <cstddef>
#include <functional>
#include <vector>

#include "model/curve_data.h"
#include "raster/dem.h"
#include "raster/dem_source.h"

namespace lacet {

struct Quantiles {
    std::size_t count = 0;
    double min = 0.0, p01 = 0.0, p05 = 0.0, median = 0.0, p95 = 0.0, p99 = 0.0, max = 0.0;  // metres
    double fractionOver = 0.0;  // of the values over `over` below
};

struct RiverCheckReport {
    std::size_t curves = 0;
    Quantiles profileAboveDem;  // z-profile samples less the DEM under them
    Quantiles nodesAboveDem;    // river node heights less the DEM at the node
    std::size_t risingSamples = 0;  // samples higher than the one upstream of them
    double over = 0.01;             // m: fractionOver counts the values above this
    double ms = 0.0;
};

RiverCheckReport checkRivers(const Scene& scene, const Dem& dem, const ZProfileParams& profiles = {});

// The same summed over parts of a scene: add() each part (a scene read for a region) with `owns`,
// which must hold for each point of the whole scene in exactly one part, and only where that part
// holds what a river there depends on (its curves, their areas, the rivers upstream: a region read
// of a box holds them for the points inside the box); then finish().
class RiverCheck {
public:
    explicit RiverCheck(ZProfileParams profiles = {});
    void add(const Scene& part, const DemSource& dem, const std::function<bool(Vec2)>& owns);
    RiverCheckReport finish();

private:
    ZProfileParams profiles_;
    RiverCheckReport r_;
    std::vector<double> above_, nodes_;
    std::chrono::steady_clock::time_point t0_;
};
// The same on any DEM source: the profiles and the ground both from its heights (a streamed DEM's
// fixed profile level).
RiverCheckReport checkRivers(const Scene& scene, const DemSource& dem, const ZProfileParams& profiles = {});

}  // namespace lacet
