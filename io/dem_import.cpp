#include "io/dem_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>


namespace lacet {
namespace {

struct GdalClose {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, GdalClose>;

struct Source {
    int width = 0, height = 0;
    double gt[6] = {0, 1, 0, 0, 0, -1};
    std::vector<float> values;
    std::vector<std::uint8_t> valid;
    std::unique_ptr<OGRCoordinateTransformation> fromWgs84;  // null: the source is WGS84 lon/lat
};

Dataset openRaster(const std::string& path) {
    GDALAllRegister();
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    CPLPopErrorHandler();
    if (!ds) {
        const std::string why = CPLGetLastErrorMsg();
        throw DemImportError(path + ": cannot open as a raster" + (why.empty() ? std::string() : " (" + why + ")"));
    }
    if (ds->GetRasterCount() < 1) throw DemImportError(path + ": no raster band");
    return ds;
}

Source readSource(const std::string& path) {
    Dataset ds = openRaster(path);
    Source s;
    s.width = ds->GetRasterXSize();
    s.height = ds->GetRasterYSize();
    if (ds->GetGeoTransform(s.gt) != CE_None) throw DemImportError(path + ": no geotransform (the raster is not georeferenced)");
    if (s.gt[2] != 0.0 || s.gt[4] != 0.0) throw DemImportError(path + ": rotated or sheared rasters are not supported");
    for (double g : s.gt)
        if (!std::isfinite(g)) throw DemImportError(path + ": non-finite value in the geotransform");
    if (s.gt[1] == 0.0 || s.gt[5] == 0.0) throw DemImportError(path + ": zero pixel size in the geotransform");
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    if (!srs) throw DemImportError(path + ": no coordinate reference system");
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRSpatialReference source(*srs);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (!(source.IsGeographic() && source.IsSame(&wgs84))) {
        s.fromWgs84.reset(OGRCreateCoordinateTransformation(&wgs84, &source));
        if (!s.fromWgs84) throw DemImportError(path + ": no transformation from WGS84 to the raster's CRS");
    }
    GDALRasterBand* band = ds->GetRasterBand(1);
    int hasNoData = 0;
    const double noData = band->GetNoDataValue(&hasNoData);
    s.values.resize(std::size_t(s.width) * std::size_t(s.height));
    if (band->RasterIO(GF_Read, 0, 0, s.width, s.height, s.values.data(), s.width, s.height, GDT_Float32, 0, 0) != CE_None)
        throw DemImportError(path + ": read failed (" + std::string(CPLGetLastErrorMsg()) + ")");
    s.valid.resize(s.values.size());
    for (std::size_t k = 0; k < s.values.size(); ++k)
        s.valid[k] = std::isfinite(s.values[k]) && !(hasNoData && double(s.values[k]) == double(float(noData)));
    return s;
}

// Fills the void samples from the outside in (see the header); returns how many there were.
std::size_t fillVoids(Source& s, const std::string& path) {
    std::size_t voids = std::size_t(std::count(s.valid.begin(), s.valid.end(), std::uint8_t(0)));
    if (voids == s.valid.size()) throw DemImportError(path + ": every sample is void (nodata)");
    std::vector<std::size_t> open;
    for (std::size_t k = 0; k < s.valid.size(); ++k)
        if (!s.valid[k]) open.push_back(k);
    std::vector<std::pair<std::size_t, float>> fills;
    while (!open.empty()) {
        fills.clear();
        std::vector<std::size_t> still;
        for (std::size_t k : open) {
            const int i = int(k % std::size_t(s.width)), j = int(k / std::size_t(s.width));
            double sum = 0.0;
            int n = 0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int x = i + di, y = j + dj;
                    if ((di == 0 && dj == 0) || x < 0 || y < 0 || x >= s.width || y >= s.height) continue;
                    const std::size_t q = std::size_t(y) * std::size_t(s.width) + std::size_t(x);
                    if (s.valid[q]) sum += s.values[q], ++n;
                }
            if (n > 0) fills.push_back({k, float(sum / n)});
            else still.push_back(k);
        }
        for (const auto& [k, v] : fills) s.values[k] = v, s.valid[k] = 1;
        open.swap(still);
    }
    return voids;
}

}  // namespace

DemSourceInfo demSourceInfo(const std::string& path) {
    Dataset ds = openRaster(path);
    DemSourceInfo info;
    info.width = ds->GetRasterXSize();
    info.height = ds->GetRasterYSize();
    double gt[6];
    if (ds->GetGeoTransform(gt) != CE_None) throw DemImportError(path + ": no geotransform (the raster is not georeferenced)");
    const double x0 = gt[0], x1 = gt[0] + gt[1] * ds->GetRasterXSize();
    const double y0 = gt[3], y1 = gt[3] + gt[5] * ds->GetRasterYSize();
    for (double g : gt)
        if (!std::isfinite(g)) throw DemImportError(path + ": non-finite value in the geotransform");
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    if (!srs) throw DemImportError(path + ": no coordinate reference system");
    OGRSpatialReference wgs84, source(*srs);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (source.IsGeographic() && source.IsSame(&wgs84)) {  // the same test as readSource()
        info.lonLat = {{std::min(x0, x1), std::min(y0, y1)}, {std::max(x0, x1), std::max(y0, y1)}};
        return info;
    }
    std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&source, &wgs84));
    if (!t) throw DemImportError(path + ": no transformation from the raster's CRS to WGS84");
    double xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
    if (!t->Transform(4, xs, ys)) throw DemImportError(path + ": the raster's corners do not transform to WGS84");
    info.lonLat = {{std::min({xs[0], xs[1], xs[2], xs[3]}), std::min({ys[0], ys[1], ys[2], ys[3]})},
                   {std::max({xs[0], xs[1], xs[2], xs[3]}), std::max({ys[0], ys[1], ys[2], ys[3]})}};
    return info;
}

Dem importDem(const std::string& path, const SceneFrame& frame, const Box& extent, double cellSize, DemImportReport& report) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!(cellSize > 0.0) || !(extent.size().x > 0.0) || !(extent.size().y > 0.0))
        throw DemImportError(path + ": the scene extent and the DEM cell size must be positive");
    Source s = readSource(path);
    report = {};
    report.path = path;
    report.sourceWidth = s.width;
    report.sourceHeight = s.height;
    report.voids = fillVoids(s, path);

    constexpr double kMaxSide = 16384.0;  // samples per side of the scene grid
    if (extent.size().x / cellSize > kMaxSide || extent.size().y / cellSize > kMaxSide)
        throw DemImportError(path + ": a " + std::to_string(cellSize) + " m cell over this extent would make more than 16384 samples a side");
    const int width = std::max(1, int(std::lround(extent.size().x / cellSize)));
    const int height = std::max(1, int(std::lround(extent.size().y / cellSize)));
    const Vec2 cell = extent.size() / Vec2(width, height);
    std::vector<float> heights(std::size_t(width) * std::size_t(height));
    std::size_t outside = 0;
    std::vector<double> xs(static_cast<std::size_t>(width)), ys(static_cast<std::size_t>(width));
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const glm::dvec2 ll = frame.reverse(extent.min + (Vec2(i, j) + 0.5) * cell);
            xs[std::size_t(i)] = ll.x;
            ys[std::size_t(i)] = ll.y;
        }
        if (s.fromWgs84 && !s.fromWgs84->Transform(std::size_t(width), xs.data(), ys.data()))
            throw DemImportError(path + ": scene points do not transform to the raster's CRS");
        for (int i = 0; i < width; ++i) {
            // Fractional source sample index (sample centres at integers).
            const double fi = (xs[std::size_t(i)] - s.gt[0]) / s.gt[1] - 0.5;
            const double fj = (ys[std::size_t(i)] - s.gt[3]) / s.gt[5] - 0.5;
            if (fi < -0.5 || fj < -0.5 || fi > s.width - 0.5 || fj > s.height - 0.5 || !std::isfinite(fi) || !std::isfinite(fj)) ++outside;
            const double ci = std::isfinite(fi) ? std::clamp(fi, 0.0, double(s.width - 1)) : 0.0;
            const double cj = std::isfinite(fj) ? std::clamp(fj, 0.0, double(s.height - 1)) : 0.0;
            const int i0 = std::min(int(ci), s.width - 1), j0 = std::min(int(cj), s.height - 1);
            const int i1 = std::min(i0 + 1, s.width - 1), j1 = std::min(j0 + 1, s.height - 1);
            const double a = ci - i0, b = cj - j0;
            auto v = [&](int x, int y) { return double(s.values[std::size_t(y) * std::size_t(s.width) + std::size_t(x)]); };
            heights[std::size_t(j) * std::size_t(width) + std::size_t(i)] =
                float((v(i0, j0) * (1 - a) + v(i1, j0) * a) * (1 - b) + (v(i0, j1) * (1 - a) + v(i1, j1) * a) * b);
        }
    }
    report.outsideFraction = double(outside) / double(heights.size());
    report.cellSize = cell.x;
    report.width = width;
    report.height = height;
    const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
    report.minHeight = *lo;
    report.maxHeight = *hi;
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return Dem(extent, width, height, std::move(heights));
}

}  // namespace lacet
