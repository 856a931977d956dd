#pragma once
// A scene file read a square part at a time (§7, issue 23: the checks of a scene larger than
// memory): the quads of the level whose quads are at most `partQuad` metres wide, each read alone
// through the feature tables' R-trees (io/scene_region.h: what the tiles of the quad need, the
// rivers upstream of those it holds included), within a budget, and dropped before the next. Each
// point of the scene is one part's (its half-open cell's; the extent's far border the last cell's,
// what lies beyond the extent clamped to it), so that a check counting the elements whose points a
// part owns counts each element of the scene once. The DEM is opened with the first part and kept.

#include <cstddef>
#include <functional>
#include <string>

#include "io/document.h"
#include "raster/dem_source.h"

namespace lacet {

struct ScenePartsRead {
    int level = 0;             // the parts' quadtree level
    std::size_t reads = 0;     // parts read
    // The file has no feature index (saved before it): its first read was the whole scene, given
    // to `f` once as the one part (not read again per part).
    bool wholeScene = false;
    std::size_t largestBytes = 0;  // the largest part's vector data (SceneRegionStats::bytes)
    double ms = 0.0;           // reading
};

// Calls `f(part, dem, owns)` for each part of the scene file at `path`: `owns(p)` whether point p is
// the part's. partQuad > 0 (m), the parts no more than kMaxSceneParts (std::invalid_argument with
// the smallest partQuad allowed otherwise); a part over `budgetMiB` throws SceneBudgetError naming
// the file; a file without a DEM throws SceneFileError (there is nothing to check against the
// terrain); a streamed DEM's blocks are held within `demBudgetMiB`.
inline constexpr std::size_t kMaxSceneParts = std::size_t(1) << 20;
using ScenePartFn = std::function<void(const SceneDocument& part, const DemSource& dem, const std::function<bool(Vec2)>& owns)>;
ScenePartsRead forEachScenePart(const std::string& path, double partQuad, double budgetMiB, double demBudgetMiB, const ScenePartFn& f);

}  // namespace lacet
