// The DEM import's seam check (io/dem_import.h): every pair of rasters of a mosaic that touch,
// compared along their shared border.
#include <algorithm>
#include <cmath>
#include <tuple>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "io/dem_import_internal.h"

namespace lacet {
namespace {

using dem_detail::Block;
using dem_detail::Dataset;

// The most seam points compared per pair of rasters (a large overlap is sampled more sparsely).
constexpr double kMaxSeamPoints = 1 << 20;
// Footprints closer than this (samples) touch: their borders, computed from their own
// geotransforms, may differ by rounding.
constexpr double kSeamSlack = 1e-3;

glm::dvec2 sourceToLonLat(const DemSourceInfo& src, double x, double y) {
    if (src.toWgs84) src.toWgs84->Transform(1, &x, &y);
    return {x, y};
}

// The height of a raster at a point of the seam (sample coordinates in its block, centres at
// integers): bilinear inside, continued linearly from the two outermost samples beyond them; NaN
// where a sample used is void.
double seamHeight(const Block& b, double fi, double fj) {
    const int i0 = b.width < 2 ? 0 : std::clamp(int(std::floor(fi)), 0, b.width - 2);
    const int j0 = b.height < 2 ? 0 : std::clamp(int(std::floor(fj)), 0, b.height - 2);
    const int i1 = std::min(i0 + 1, b.width - 1), j1 = std::min(j0 + 1, b.height - 1);
    const double a = b.width < 2 ? 0.0 : fi - i0, c = b.height < 2 ? 0.0 : fj - j0;
    double sum = 0.0;
    for (const auto& [i, j, wgt] : {std::tuple{i0, j0, (1 - a) * (1 - c)}, std::tuple{i1, j0, a * (1 - c)},
                                    std::tuple{i0, j1, (1 - a) * c}, std::tuple{i1, j1, a * c}}) {
        if (wgt == 0.0) continue;
        const std::size_t k = std::size_t(j) * std::size_t(b.width) + std::size_t(i);
        if (!b.valid[k]) return std::nan("");
        sum += wgt * b.values[k];
    }
    return sum;
}

}  // namespace

namespace dem_detail {

// Compares every pair of rasters touching inside `window` (source CRS) along their shared border.
void checkSeams(const DemSourceInfo& src, const Box& window, DemImportReport& report) {
    std::vector<Dataset> opened(src.files.size());
    auto raster = [&](std::size_t f) -> GDALDataset& {
        if (!opened[f]) opened[f] = openRaster(src.sources[f], src.files[f]);
        return *opened[f];
    };
    const double stepX = std::abs(src.geoTransform[1]), stepY = std::abs(src.geoTransform[5]);
    for (std::size_t a = 0; a < src.files.size(); ++a)
        for (std::size_t b = a + 1; b < src.files.size(); ++b) {
            const Box& fa = src.footprints[a];
            const Box& fb = src.footprints[b];
            Box shared{glm::max(glm::max(fa.min, fb.min), window.min), glm::min(glm::min(fa.max, fb.max), window.max)};
            const glm::dvec2 slack = kSeamSlack * glm::dvec2(stepX, stepY);
            if (shared.min.x > shared.max.x + slack.x || shared.min.y > shared.max.y + slack.y) continue;
            // Footprints that touch within the slack share a line.
            for (int axis = 0; axis < 2; ++axis)
                if (shared.min[axis] > shared.max[axis]) shared.min[axis] = shared.max[axis] = (shared.min[axis] + shared.max[axis]) / 2;
            double nx = std::max(1.0, std::round(shared.size().x / stepX)), ny = std::max(1.0, std::round(shared.size().y / stepY));
            if (nx * ny > kMaxSeamPoints) {
                const double thin = std::sqrt(nx * ny / kMaxSeamPoints);
                nx = std::max(1.0, std::floor(nx / thin)), ny = std::max(1.0, std::floor(ny / thin));
            }
            std::vector<glm::dvec2> points;
            for (int j = 0; j < int(ny); ++j)
                for (int i = 0; i < int(nx); ++i) points.push_back(shared.min + shared.size() * glm::dvec2((i + 0.5) / nx, (j + 0.5) / ny));
            // Each raster's samples around the points, as sample coordinates in a block.
            std::vector<double> heights[2];
            int side = 0;
            for (std::size_t f : {a, b}) {
                GDALDataset& ds = raster(f);
                double gt[6];
                ds.GetGeoTransform(gt);
                std::vector<glm::dvec2> at(points.size());
                glm::dvec2 lo(1e300), hi(-1e300);
                for (std::size_t k = 0; k < points.size(); ++k) {
                    at[k] = {(points[k].x - gt[0]) / gt[1] - 0.5, (points[k].y - gt[3]) / gt[5] - 0.5};
                    lo = glm::min(lo, at[k]), hi = glm::max(hi, at[k]);
                }
                const int x0 = std::max(0, int(std::floor(lo.x)) - 1), y0 = std::max(0, int(std::floor(lo.y)) - 1);
                const int x1 = std::min(ds.GetRasterXSize() - 1, int(std::floor(hi.x)) + 2);
                const int y1 = std::min(ds.GetRasterYSize() - 1, int(std::floor(hi.y)) + 2);
                const Block block = readBlock(ds, src.files[f], x0, y0, x1 - x0 + 1, y1 - y0 + 1);
                for (const glm::dvec2& p : at) heights[side].push_back(seamHeight(block, p.x - x0, p.y - y0));
                ++side;
            }
            DemSeam seam{src.files[a], src.files[b], 0, 0.0, {0.0, 0.0}};
            for (std::size_t k = 0; k < points.size(); ++k) {
                const double step = std::abs(heights[0][k] - heights[1][k]);
                if (!std::isfinite(step)) continue;
                ++seam.points;
                if (seam.points == 1 || step > seam.largestStep)
                    seam.largestStep = step, seam.where = sourceToLonLat(src, points[k].x, points[k].y);
            }
            if (seam.points > 0) {
                ++report.seamsChecked;
                if (report.seamsChecked == 1 || seam.largestStep > report.largestSeamStep)
                    report.largestSeamStep = seam.largestStep, report.largestSeamStepAt = seam.where;
            }
            report.seams.push_back(std::move(seam));
        }
}

}  // namespace dem_detail
}  // namespace lacet
