// The DEM import's sources (io/dem_import.h): the inputs opened as rasters (files, directories,
// GDAL virtual paths), checked and mosaicked by GDALBuildVRT (DemSourceInfo), and the reads every
// step shares: a raster opened, a block of samples, whether a point is inside a footprint.
#include "io/dem_import.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>

#include <sys/stat.h>

#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include "io/dem_import_internal.h"

namespace lacet {
namespace {

using dem_detail::Dataset;
using dem_detail::openRaster;

bool isVsiPath(const std::string& path) { return path.rfind("/vsi", 0) == 0; }

// Opens `path` as a raster without GDAL printing anything; null, and the reason in `why`, if it cannot.
Dataset tryOpenRaster(const std::string& path, std::string& why) {
    GDALAllRegister();
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    CPLPopErrorHandler();
    why = CPLGetLastErrorMsg();
    return ds;
}

// What stat() says of a path: 0 (missing, with errno), 1 (a file), 2 (a directory).
int pathKind(const std::string& path) {
    if (isVsiPath(path)) {
        VSIStatBufL st;
        if (VSIStatL(path.c_str(), &st) != 0) {
            errno = ENOENT;
            return 0;
        }
        return VSI_ISDIR(st.st_mode) ? 2 : 1;
    }
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return 0;
    return S_ISDIR(st.st_mode) ? 2 : 1;
}

struct Raster {
    std::string name;    // as given, or the directory joined with the file's name
    std::string source;  // what GDAL opens
    Dataset ds;
};

// The rasters an input stands for (see the header), opened.
void addInput(const std::string& input, std::vector<Raster>& out) {
    const int kind = pathKind(input);
    if (kind == 0) throw DemImportError(input + ": " + std::strerror(errno));
    const std::string source = isVsiPath(input) ? input : std::filesystem::absolute(input).lexically_normal().string();
    if (kind == 1) {
        out.push_back({input, source, openRaster(source, input)});
        return;
    }
    std::vector<std::string> names;
    if (isVsiPath(input)) {
        char** list = VSIReadDir(input.c_str());
        for (int k = 0; list && list[k]; ++k) names.emplace_back(list[k]);
        CSLDestroy(list);
    } else {
        for (const auto& e : std::filesystem::directory_iterator(input))
            if (e.is_regular_file()) names.push_back(e.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    const std::size_t before = out.size();
    for (const std::string& n : names) {
        const std::string path = (std::filesystem::path(source) / n).string();
        if (pathKind(path) != 1) continue;
        std::string why;
        if (Dataset ds = tryOpenRaster(path, why)) out.push_back({(std::filesystem::path(input) / n).string(), path, std::move(ds)});
    }
    if (out.size() == before) throw DemImportError(input + ": no raster file in this directory");
}

std::string crsName(const OGRSpatialReference& srs) {
    const char* n = srs.GetName();
    return n && *n ? n : "an unnamed CRS";
}

// The footprint of a checked raster in its CRS (pixel-is-area bounds).
Box footprint(const double gt[6], int width, int height) {
    const double x0 = gt[0], x1 = gt[0] + gt[1] * width, y0 = gt[3], y1 = gt[3] + gt[5] * height;
    return {{std::min(x0, x1), std::min(y0, y1)}, {std::max(x0, x1), std::max(y0, y1)}};
}

// Throws unless the raster is georeferenced, not rotated, with a CRS and a band.
void checkRaster(const Raster& r, double gt[6]) {
    if (r.ds->GetRasterCount() < 1) throw DemImportError(r.name + ": no raster band");
    if (r.ds->GetGeoTransform(gt) != CE_None) throw DemImportError(r.name + ": no geotransform (the raster is not georeferenced)");
    for (int k = 0; k < 6; ++k)
        if (!std::isfinite(gt[k])) throw DemImportError(r.name + ": non-finite value in the geotransform");
    if (gt[2] != 0.0 || gt[4] != 0.0) throw DemImportError(r.name + ": rotated or sheared rasters are not supported");
    if (gt[1] == 0.0 || gt[5] == 0.0) throw DemImportError(r.name + ": zero pixel size in the geotransform");
    const OGRSpatialReference* srs = r.ds->GetSpatialRef();
    if (!srs || srs->IsEmpty()) throw DemImportError(r.name + ": no coordinate reference system");
}

// Metres per unit of the source CRS along (east, north) at `lat` degrees.
Vec2 metresPerUnit(const OGRSpatialReference& srs, double lat) {
    if (!srs.IsGeographic()) return Vec2(srs.GetLinearUnits());
    const double a = srs.GetSemiMajor(), invF = srs.GetInvFlattening();
    const double f = invF > 0.0 ? 1.0 / invF : 0.0, e2 = f * (2.0 - f);
    const double s = std::sin(lat * std::numbers::pi / 180.0), w = 1.0 - e2 * s * s;
    const double radiansPerUnit = srs.GetAngularUnits();
    const double east = a / std::sqrt(w) * std::cos(lat * std::numbers::pi / 180.0);  // parallel's radius
    const double north = a * (1.0 - e2) / (w * std::sqrt(w));                          // meridian's radius of curvature
    return Vec2(east, north) * radiansPerUnit;
}

// The mosaic of several rasters by GDALBuildVRT, as VRT XML, with its size and geotransform.
std::string buildMosaic(std::vector<Raster>& rasters, int& width, int& height, double gt[6]) {
    std::vector<GDALDatasetH> handles;
    for (Raster& r : rasters) handles.push_back(GDALDataset::ToHandle(r.ds.get()));
    const char* args[] = {"-strict", nullptr};
    GDALBuildVRTOptions* options = GDALBuildVRTOptionsNew(const_cast<char**>(args), nullptr);
    int usageError = 0;
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Dataset vrt(GDALDataset::FromHandle(GDALBuildVRT("", int(handles.size()), handles.data(), nullptr, options, &usageError)));
    CPLPopErrorHandler();
    GDALBuildVRTOptionsFree(options);
    if (!vrt) throw DemImportError(rasters.front().name + " and the other " + std::to_string(rasters.size() - 1) +
                                   " rasters: GDAL cannot make a mosaic of them (" + CPLGetLastErrorMsg() + ")");
    char** xml = vrt->GetMetadata("xml:VRT");
    if (!xml || !xml[0]) throw DemImportError(rasters.front().name + ": GDAL's mosaic has no VRT description");
    width = vrt->GetRasterXSize();
    height = vrt->GetRasterYSize();
    if (vrt->GetGeoTransform(gt) != CE_None) throw DemImportError(rasters.front().name + ": GDAL's mosaic has no geotransform");
    return xml[0];
}

}  // namespace

namespace dem_detail {

Dataset openRaster(const std::string& path, const std::string& name) {
    std::string why;
    Dataset ds = tryOpenRaster(path, why);
    if (!ds) throw DemImportError(name + ": cannot open as a raster" + (why.empty() ? std::string() : " (" + why + ")"));
    return ds;
}

Dataset openSource(const DemSourceInfo& src, const std::string& name) {
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Dataset ds(GDALDataset::Open(src.dataset.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    CPLPopErrorHandler();
    if (!ds) throw DemImportError(name + ": cannot open as a raster (" + std::string(CPLGetLastErrorMsg()) + ")");
    return ds;
}

bool inFootprints(const DemSourceInfo& src, double x, double y) {
    for (const Box& f : src.footprints)
        if (f.contains(Vec2(x, y))) return true;
    return false;
}

Block readBlock(GDALDataset& ds, const std::string& name, int x0, int y0, int width, int height) {
    Block b{x0, y0, width, height, {}, {}};
    GDALRasterBand* band = ds.GetRasterBand(1);
    int hasNoData = 0;
    const double noData = band->GetNoDataValue(&hasNoData);
    b.values.resize(std::size_t(width) * std::size_t(height));
    if (band->RasterIO(GF_Read, x0, y0, width, height, b.values.data(), width, height, GDT_Float32, 0, 0) != CE_None)
        throw DemImportError(name + ": read failed (" + std::string(CPLGetLastErrorMsg()) + ")");
    b.valid.resize(b.values.size());
    for (std::size_t k = 0; k < b.values.size(); ++k)
        b.valid[k] = std::isfinite(b.values[k]) && !(hasNoData && double(b.values[k]) == double(float(noData)));
    return b;
}

}  // namespace dem_detail

bool DemSourceInfo::covers(glm::dvec2 p) const {
    double x = p.x, y = p.y;
    int ok = 1;
    if (fromWgs84) fromWgs84->Transform(1, &x, &y, nullptr, &ok);
    return ok && std::isfinite(x) && std::isfinite(y) && dem_detail::inFootprints(*this, x, y);
}

DemSourceInfo demSourceInfo(const std::vector<std::string>& inputs) {
    if (inputs.empty()) throw DemImportError("no DEM given");
    std::vector<Raster> rasters;
    for (const std::string& input : inputs) addInput(input, rasters);
    DemSourceInfo info;
    info.inputs = inputs;
    // The same file twice: compared by their resolved paths.
    std::vector<std::pair<std::string, std::size_t>> seen;
    for (std::size_t k = 0; k < rasters.size(); ++k) {
        std::error_code ec;
        const std::string& source = rasters[k].source;
        const std::string id = isVsiPath(source) ? source : std::filesystem::weakly_canonical(source, ec).string();
        for (const auto& [other, at] : seen)
            if (other == id)
                throw DemImportError(rasters[k].name + ": the same file is given twice" +
                                     (rasters[at].name == rasters[k].name ? std::string() : " (also as " + rasters[at].name + ")"));
        seen.emplace_back(id, k);
    }
    OGRSpatialReference crs;
    for (std::size_t k = 0; k < rasters.size(); ++k) {
        double gt[6];
        checkRaster(rasters[k], gt);
        const OGRSpatialReference* srs = rasters[k].ds->GetSpatialRef();
        if (k == 0) crs = *srs;
        else if (!srs->IsSame(&crs))
            throw DemImportError(rasters[0].name + " (" + crsName(crs) + ") and " + rasters[k].name + " (" + crsName(*srs) +
                                 ") are in different CRS: reproject them to one first");
        info.files.push_back(rasters[k].name);
        info.sources.push_back(rasters[k].source);
        info.footprints.push_back(footprint(gt, rasters[k].ds->GetRasterXSize(), rasters[k].ds->GetRasterYSize()));
    }
    info.crsName = crsName(crs);
    if (rasters.size() == 1) {
        info.dataset = rasters[0].source;
        info.width = rasters[0].ds->GetRasterXSize();
        info.height = rasters[0].ds->GetRasterYSize();
        rasters[0].ds->GetGeoTransform(info.geoTransform);
    } else {
        info.dataset = buildMosaic(rasters, info.width, info.height, info.geoTransform);
    }

    OGRSpatialReference wgs84, source(crs);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (!(source.IsGeographic() && source.IsSame(&wgs84))) {
        info.fromWgs84.reset(OGRCreateCoordinateTransformation(&wgs84, &source));
        info.toWgs84.reset(OGRCreateCoordinateTransformation(&source, &wgs84));
        if (!info.fromWgs84 || !info.toWgs84)
            throw DemImportError(info.files[0] + ": no transformation between WGS84 and the raster's CRS (" + info.crsName + ")");
    }
    info.lonLat = {{1e300, 1e300}, {-1e300, -1e300}};
    for (std::size_t k = 0; k < info.footprints.size(); ++k) {
        Box b = info.footprints[k];
        if (info.toWgs84 && !info.toWgs84->TransformBounds(b.min.x, b.min.y, b.max.x, b.max.y, &b.min.x, &b.min.y, &b.max.x, &b.max.y, 21))
            throw DemImportError(info.files[k] + ": the raster's bounds do not transform to WGS84");
        info.lonLat = {glm::min(info.lonLat.min, b.min), glm::max(info.lonLat.max, b.max)};
    }
    info.resolution = Vec2(std::abs(info.geoTransform[1]), std::abs(info.geoTransform[5])) * metresPerUnit(source, info.lonLat.center().y);
    return info;
}

}  // namespace lacet
