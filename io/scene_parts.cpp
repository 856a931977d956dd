#include "io/scene_parts.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "io/dem_stream.h"
#include "io/scene_file.h"
#include "io/scene_region.h"

namespace lacet {

ScenePartsRead forEachScenePart(const std::string& path, double partQuad, double budgetMiB, double demBudgetMiB, const ScenePartFn& f) {
    if (!(partQuad > 0.0)) throw std::invalid_argument("forEachScenePart: the part quad must be > 0 m");
    const Box extent = loadSceneExtent(path);
    const double width = std::max(extent.size().x, extent.size().y);
    if (!(extent.size().x > 0.0 && extent.size().y > 0.0) || !std::isfinite(width))
        throw SceneFileError(path + ": the scene's extent is empty: it has no parts");
    ScenePartsRead out;
    const int maxLevel = std::bit_width(kMaxSceneParts) / 2;  // 4^level parts
    while (width / double(std::int64_t(1) << out.level) > partQuad) {
        if (out.level == maxLevel)
            throw std::invalid_argument(path + ": parts of at most " + std::to_string(partQuad) + " m would be more than " +
                                        std::to_string(kMaxSceneParts) + "; the smallest part allowed is " +
                                        std::to_string(width / double(std::int64_t(1) << maxLevel)) + " m");
        ++out.level;
    }
    const std::int64_t n = std::int64_t(1) << out.level;
    const Vec2 side = extent.size() / double(n);
    const auto cellOf = [&](double v, double origin, double s) {
        return std::clamp(std::int64_t(std::floor((v - origin) / s)), std::int64_t(0), n - 1);
    };
    SceneDocument demDoc;
    demDoc.scene.extent = extent;
    std::unique_ptr<DemSource> dem;
    for (std::int64_t j = 0; j < n; ++j)
        for (std::int64_t i = 0; i < n; ++i) {
            // The quad inward by a hair: the quads of the level that meet it are this one alone
            // (io/scene_region.h takes closed boxes), read with the reach around it.
            const Box cell{extent.min + Vec2(double(i), double(j)) * side, extent.min + Vec2(double(i + 1), double(j + 1)) * side};
            const Box inside{cell.min + side * 1e-6, cell.max - side * 1e-6};
            const auto t0 = std::chrono::steady_clock::now();
            SceneRegionOptions read;
            read.budgetMiB = budgetMiB;
            read.dem = !dem;
            SceneRegionStats st;
            SceneDocument part = loadSceneRegion(path, inside, RefineParams{}, out.level, &st, read);
            out.ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            ++out.reads;
            out.largestBytes = std::max(out.largestBytes, st.bytes);
            out.wholeScene = st.wholeScene;
            if (!dem) {
                if (!part.dem) throw SceneFileError(path + ": the scene has no DEM: nothing to check against the terrain");
                demDoc.dem = std::move(part.dem);
                demDoc.demLod = std::move(part.demLod);
                dem = batchDemSource(demDoc, demBudgetMiB);
            }
            if (st.wholeScene) {  // no feature index: the whole scene was read, the one part
                f(part, *dem, [](Vec2) { return true; });
                return out;
            }
            f(part, *dem, [&](Vec2 p) { return cellOf(p.x, extent.min.x, side.x) == i && cellOf(p.y, extent.min.y, side.y) == j; });
        }
    return out;
}

}  // namespace lacet
