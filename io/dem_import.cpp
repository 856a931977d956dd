#include "io/dem_import.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <tuple>

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
using dem_detail::number;

// The most seam points compared per pair of rasters (a large overlap is sampled more sparsely).
constexpr double kMaxSeamPoints = 1 << 20;
// Footprints closer than this (samples) touch: their borders, computed from their own
// geotransforms, may differ by rounding.
constexpr double kSeamSlack = 1e-3;
// The largest source window read, samples (4 GiB of heights).
constexpr double kMaxWindowSamples = double(1u << 30);

std::string describe(const Box& lonLat) {
    return "lon " + number(lonLat.min.x) + " to " + number(lonLat.max.x) + ", lat " + number(lonLat.min.y) + " to " + number(lonLat.max.y);
}

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

Dataset openRaster(const std::string& path, const std::string& name) {
    std::string why;
    Dataset ds = tryOpenRaster(path, why);
    if (!ds) throw DemImportError(name + ": cannot open as a raster" + (why.empty() ? std::string() : " (" + why + ")"));
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

// Scene points to the source CRS, in place; ok[k] false where the transformation fails.
void toSource(const DemSourceInfo& src, std::vector<double>& xs, std::vector<double>& ys, std::vector<int>& ok) {
    ok.assign(xs.size(), 1);
    if (src.fromWgs84) src.fromWgs84->Transform(int(xs.size()), xs.data(), ys.data(), nullptr, ok.data());
    for (std::size_t k = 0; k < xs.size(); ++k) ok[k] = ok[k] && std::isfinite(xs[k]) && std::isfinite(ys[k]);
}

// The centres of columns [i0, i1] of grid row j in the source CRS: xs, ys (n = i1 - i0 + 1 each),
// ok[m] false where the transformation fails (toSource).
void rowToSource(const DemSourceInfo& src, const SceneFrame& frame, const dem_detail::SceneGrid& grid, int j, int i0, int i1,
                 std::vector<double>& xs, std::vector<double>& ys, std::vector<int>& ok) {
    const std::size_t n = std::size_t(i1 - i0 + 1);
    xs.resize(n), ys.resize(n);
    for (int i = i0; i <= i1; ++i) {
        const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
        xs[std::size_t(i - i0)] = ll.x, ys[std::size_t(i - i0)] = ll.y;
    }
    toSource(src, xs, ys, ok);
}

bool inFootprints(const DemSourceInfo& src, double x, double y) {
    for (const Box& f : src.footprints)
        if (f.contains(Vec2(x, y))) return true;
    return false;
}

glm::dvec2 sourceToLonLat(const DemSourceInfo& src, double x, double y) {
    if (src.toWgs84) src.toWgs84->Transform(1, &x, &y);
    return {x, y};
}

// A block of one band's samples, its top-left sample (x0, y0) in its raster.
struct Block {
    int x0 = 0, y0 = 0, width = 0, height = 0;
    std::vector<float> values;
    std::vector<std::uint8_t> valid;
};

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

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

SceneGrid makeSceneGrid(const std::string& name, const Box& extent, double cellSize, double maxSide) {
    if (!(extent.size().x > 0.0) || !(extent.size().y > 0.0))
        throw DemImportError(name + ": the scene extent must have a positive size");
    const double longSide = std::max(extent.size().x, extent.size().y), shortSide = std::min(extent.size().x, extent.size().y);
    const std::string range = "the DEM cell must be between " + number(longSide / maxSide) + " and " + number(shortSide / 1.5) +
                              " m over this " + number(extent.size().x) + " x " + number(extent.size().y) + " m extent";
    if (!std::isfinite(cellSize) || !(cellSize > 0.0)) throw DemImportError(name + ": " + range);
    const std::string aCell = name + ": a " + number(cellSize) + " m cell over this extent would make ";
    if (longSide / cellSize > maxSide)
        throw DemImportError(aCell + "more than " + number(maxSide) + " samples a side (" + range + ")");
    SceneGrid g;
    g.extent = extent;
    g.width = int(std::lround(extent.size().x / cellSize));
    g.height = int(std::lround(extent.size().y / cellSize));
    // round(side / cell) >= 2 for cell <= side / 1.5: the range's upper bound.
    if (g.width < 2 || g.height < 2) throw DemImportError(aCell + "fewer than 2 samples a side (" + range + ")");
    g.cell = extent.size() / Vec2(g.width, g.height);
    return g;
}

DemImportError notCovered(const std::string& name, const SceneFrame& frame, const Box& extent, const DemSourceInfo& src) {
    Box lonLat{{1e300, 1e300}, {-1e300, -1e300}};
    for (const Vec2 corner : {extent.min, extent.max, Vec2(extent.min.x, extent.max.y), Vec2(extent.max.x, extent.min.y)}) {
        const glm::dvec2 ll = frame.reverse(corner);
        lonLat = {glm::min(lonLat.min, ll), glm::max(lonLat.max, ll)};
    }
    return DemImportError(name + ": the DEM does not cover the scene: no scene cell centre falls inside its rasters (the scene spans " +
                          "about " + describe(lonLat) + "; the DEM " + describe(src.lonLat) + ")");
}

SourceWindow borderWindow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j0, int j1, int coveredBorder[4]) {
    const double* gt = src.geoTransform;
    std::vector<double> xs, ys;
    std::vector<int> ok, side;
    for (int i = 0; i < grid.width; ++i)
        for (int j : {j0, j1}) {
            const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
            xs.push_back(ll.x), ys.push_back(ll.y), side.push_back(j == j0 ? 0 : 1);
        }
    for (int j = j0 + 1; j < j1; ++j)
        for (int i : {0, grid.width - 1}) {
            const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
            xs.push_back(ll.x), ys.push_back(ll.y), side.push_back(i == 0 ? 2 : 3);
        }
    toSource(src, xs, ys, ok);
    if (coveredBorder)
        for (int k = 0; k < 4; ++k) coveredBorder[k] = 0;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (std::size_t k = 0; k < xs.size(); ++k)
        if (ok[k]) {
            const glm::dvec2 px((xs[k] - gt[0]) / gt[1], (ys[k] - gt[3]) / gt[5]);  // pixel edges at integers
            lo = glm::min(lo, px), hi = glm::max(hi, px);
            if (coveredBorder && inFootprints(src, xs[k], ys[k])) {
                ++coveredBorder[side[k]];
                // A corner is on two sides.
                const int i = int(k / 2);
                if (side[k] < 2 && (i == 0 || i == grid.width - 1)) ++coveredBorder[i == 0 ? 2 : 3];
            }
        }
    SourceWindow w;
    if (!(lo.x <= hi.x)) return w;
    const double wx0 = std::max(0.0, std::floor(lo.x) - kWindowMargin), wy0 = std::max(0.0, std::floor(lo.y) - kWindowMargin);
    const double wx1 = std::min(src.width - 1.0, std::floor(hi.x) + kWindowMargin);
    const double wy1 = std::min(src.height - 1.0, std::floor(hi.y) + kWindowMargin);
    if (!(wx0 <= wx1 && wy0 <= wy1)) return w;
    return {int(wx0), int(wy0), int(wx1), int(wy1)};
}

Box windowBox(const DemSourceInfo& src, const SourceWindow& w) {
    const double* gt = src.geoTransform;
    const double xa = gt[0] + w.x0 * gt[1], xb = gt[0] + (w.x1 + 1) * gt[1];
    const double ya = gt[3] + w.y0 * gt[5], yb = gt[3] + (w.y1 + 1) * gt[5];
    return {{std::min(xa, xb), std::min(ya, yb)}, {std::max(xa, xb), std::max(ya, yb)}};
}

std::size_t fillFromNeighbours(std::vector<float>& v, std::vector<std::uint8_t>& state, int width, int height, std::vector<int>* layerOf) {
    const std::size_t w = std::size_t(width);
    auto forNeighbours = [&](std::size_t k, auto&& f) {
        const int i = int(k % w), j = int(k / w);
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                const int x = i + di, y = j + dj;
                if ((di != 0 || dj != 0) && x >= 0 && y >= 0 && x < width && y < height) f(std::size_t(y) * w + std::size_t(x));
            }
    };
    if (layerOf) layerOf->assign(state.size(), 0);
    std::vector<std::size_t> layer, next;
    for (std::size_t k = 0; k < state.size(); ++k) {
        if (state[k] != kOpen) continue;
        bool touches = false;
        forNeighbours(k, [&](std::size_t q) { touches = touches || state[q] == kKnown; });
        if (touches) layer.push_back(k);
    }
    for (std::size_t k : layer) state[k] = kQueued;
    std::size_t filled = 0;
    int depth = 0;
    std::vector<float> values;
    while (!layer.empty()) {
        ++depth;
        values.clear();
        for (std::size_t k : layer) {
            double sum = 0.0;
            int n = 0;
            forNeighbours(k, [&](std::size_t q) {
                if (state[q] == kKnown) sum += v[q], ++n;
            });
            values.push_back(float(sum / n));
        }
        for (std::size_t m = 0; m < layer.size(); ++m) v[layer[m]] = values[m], state[layer[m]] = kKnown;
        if (layerOf)
            for (std::size_t k : layer) (*layerOf)[k] = depth;
        filled += layer.size();
        next.clear();
        for (std::size_t k : layer)
            forNeighbours(k, [&](std::size_t q) {
                if (state[q] == kOpen) state[q] = kQueued, next.push_back(q);
            });
        layer.swap(next);
    }
    return filled;
}

Dataset openSource(const DemSourceInfo& src, const std::string& name) {
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    Dataset ds(GDALDataset::Open(src.dataset.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    CPLPopErrorHandler();
    if (!ds) throw DemImportError(name + ": cannot open as a raster (" + std::string(CPLGetLastErrorMsg()) + ")");
    return ds;
}

WindowSamples readWindow(GDALDataset& ds, const DemSourceInfo& src, const std::string& name, const SourceWindow& w) {
    const double* gt = src.geoTransform;
    Block block = readBlock(ds, name, w.x0, w.y0, w.width(), w.height());
    WindowSamples out{w, std::move(block.values), std::vector<std::uint8_t>(block.valid.size(), kNoData)};
    const int ww = w.width(), wh = w.height();
    for (const Box& f : src.footprints) {
        // The window samples whose centres are inside f.
        const double ax = (f.min.x - gt[0]) / gt[1], bx = (f.max.x - gt[0]) / gt[1];
        const double ay = (f.min.y - gt[3]) / gt[5], by = (f.max.y - gt[3]) / gt[5];
        const int i0 = std::max(0, int(std::ceil(std::min(ax, bx) - 0.5)) - w.x0);
        const int i1 = std::min(ww - 1, int(std::floor(std::max(ax, bx) - 0.5)) - w.x0);
        const int j0 = std::max(0, int(std::ceil(std::min(ay, by) - 0.5)) - w.y0);
        const int j1 = std::min(wh - 1, int(std::floor(std::max(ay, by) - 0.5)) - w.y0);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(ww) + std::size_t(i);
                out.state[k] = block.valid[k] ? kKnown : kOpen;
            }
    }
    return out;
}

void resampleRow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, const WindowSamples& window, int j, int i0,
                 int i1, float* heights, std::uint8_t* covered) {
    const double* gt = src.geoTransform;
    const int ww = window.at.width(), wh = window.at.height();
    const std::size_t n = std::size_t(i1 - i0 + 1);
    std::vector<double> xs, ys;
    std::vector<int> ok;
    rowToSource(src, frame, grid, j, i0, i1, xs, ys, ok);
    for (std::size_t m = 0; m < n; ++m) {
        covered[m] = 0;
        if (!ok[m] || !inFootprints(src, xs[m], ys[m])) continue;
        // Sample coordinates in the window (centres at integers), clamped to it: beyond the
        // outermost samples of the source the edge continues.
        const double fi = std::clamp((xs[m] - gt[0]) / gt[1] - 0.5 - window.at.x0, 0.0, ww - 1.0);
        const double fj = std::clamp((ys[m] - gt[3]) / gt[5] - 0.5 - window.at.y0, 0.0, wh - 1.0);
        const int x0 = std::min(int(fi), ww - 1), y0 = std::min(int(fj), wh - 1);
        const int x1 = std::min(x0 + 1, ww - 1), y1 = std::min(y0 + 1, wh - 1);
        const double a = fi - x0, b = fj - y0;
        // Bilinear over the samples with data: at a footprint's border inside the mosaic (a
        // missing tile) the weights of the others are renormalised, continuing the edge.
        double sum = 0.0, weight = 0.0;
        for (const auto& [x, y, wgt] : {std::tuple{x0, y0, (1 - a) * (1 - b)}, std::tuple{x1, y0, a * (1 - b)},
                                        std::tuple{x0, y1, (1 - a) * b}, std::tuple{x1, y1, a * b}}) {
            const std::size_t k = std::size_t(y) * std::size_t(ww) + std::size_t(x);
            if (window.state[k] == kKnown && wgt > 0.0) sum += wgt * window.values[k], weight += wgt;
        }
        if (!(weight > 0.0)) continue;
        heights[m] = float(sum / weight);
        covered[m] = 1;
    }
}

void coveredCells(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j, int i0, int i1, std::uint8_t* covered) {
    const std::size_t n = std::size_t(i1 - i0 + 1);
    std::vector<double> xs, ys;
    std::vector<int> ok;
    rowToSource(src, frame, grid, j, i0, i1, xs, ys, ok);
    for (std::size_t m = 0; m < n; ++m) covered[m] = ok[m] && inFootprints(src, xs[m], ys[m]);
}

void initReport(const DemSourceInfo& src, DemImportReport& report) {
    report = {};
    for (const std::string& input : src.inputs) report.path += (report.path.empty() ? "" : ", ") + input;
    report.files = src.files;
    report.sourceWidth = src.width;
    report.sourceHeight = src.height;
    report.sourceResolution = src.resolution;
}

std::size_t filesMeeting(const DemSourceInfo& src, const Box& window) {
    std::size_t n = 0;
    for (const Box& f : src.footprints) n += f.intersects(window);
    return n;
}


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

using namespace dem_detail;


bool DemSourceInfo::covers(glm::dvec2 p) const {
    double x = p.x, y = p.y;
    int ok = 1;
    if (fromWgs84) fromWgs84->Transform(1, &x, &y, nullptr, &ok);
    return ok && std::isfinite(x) && std::isfinite(y) && inFootprints(*this, x, y);
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

Dem importDem(const DemSourceInfo& src, const SceneFrame& frame, const Box& extent, double cellSize, DemImportReport& report) {
    const auto t0 = std::chrono::steady_clock::now();
    initReport(src, report);
    const std::string& name = report.path;

    // The scene grid.
    const SceneGrid grid = makeSceneGrid(name, extent, cellSize, kMaxDemSide);
    const int width = grid.width, height = grid.height;
    const Vec2 cell = grid.cell;
    report.cellSize = cell.x;
    report.sceneWidth = width;
    report.sceneHeight = height;

    // The source window under the scene: its border cell centres' bounding box, in source samples.
    const SourceWindow win = borderWindow(src, frame, grid, 0, height - 1);
    if (win.empty()) throw notCovered(name, frame, extent, src);
    if (double(win.width()) * double(win.height()) > kMaxWindowSamples)
        throw DemImportError(name + ": the scene extent covers " + std::to_string(win.width()) + " x " + std::to_string(win.height()) +
                             " source samples, more than can be read at once: make a coarser copy of the DEM (gdal_translate -tr)");
    report.windowX = win.x0, report.windowY = win.y0;
    report.windowWidth = win.width(), report.windowHeight = win.height();

    // Read the window; voids are the invalid samples inside a footprint, filled.
    WindowSamples window = readWindow(*openSource(src, name), src, name, win);
    std::vector<std::uint8_t>& state = window.state;
    if (std::find(state.begin(), state.end(), std::uint8_t(kKnown)) == state.end()) {
        if (std::find(state.begin(), state.end(), std::uint8_t(kOpen)) == state.end()) throw notCovered(name, frame, extent, src);
        throw DemImportError(name + ": every sample under the scene extent is void (nodata)");
    }
    report.voids = fillFromNeighbours(window.values, state, win.width(), win.height());
    for (std::uint8_t& s : state)
        if (s == kOpen) s = kNoData;  // voids cut off from every valid sample in the window: no data
    report.filesRead = filesMeeting(src, windowBox(src, win));
    report.strips = 1;
    report.peakStripSamples = window.values.size() + std::size_t(width) * std::size_t(height);

    // Resample the scene grid; a cell is covered when its centre is inside a footprint.
    std::vector<float> heights(std::size_t(width) * std::size_t(height));
    std::vector<std::uint8_t> covered(heights.size(), 0);
    int ci0 = width, ci1 = -1, cj0 = height, cj1 = -1;
    for (int j = 0; j < height; ++j) {
        const std::size_t row = std::size_t(j) * std::size_t(width);
        resampleRow(src, frame, grid, window, j, 0, width - 1, heights.data() + row, covered.data() + row);
        for (int i = 0; i < width; ++i)
            if (covered[row + std::size_t(i)]) ci0 = std::min(ci0, i), ci1 = std::max(ci1, i), cj0 = std::min(cj0, j), cj1 = std::max(cj1, j);
    }
    if (ci1 < 0) throw notCovered(name, frame, extent, src);
    window = {};

    // The Dem: the covered cells' bounding box, the uncovered cells inside it filled.
    const int dw = ci1 - ci0 + 1, dh = cj1 - cj0 + 1;
    std::vector<float> demHeights(std::size_t(dw) * std::size_t(dh));
    std::vector<std::uint8_t> demState(demHeights.size());
    for (int j = 0; j < dh; ++j)
        for (int i = 0; i < dw; ++i) {
            const std::size_t from = std::size_t(j + cj0) * std::size_t(width) + std::size_t(i + ci0);
            const std::size_t to = std::size_t(j) * std::size_t(dw) + std::size_t(i);
            demHeights[to] = heights[from];
            demState[to] = covered[from] ? kKnown : kOpen;
        }
    heights = {};
    covered = {};
    report.uncoveredFilled = fillFromNeighbours(demHeights, demState, dw, dh);
    report.demExtent = {extent.min + Vec2(ci0, cj0) * cell,
                        {ci1 + 1 == width ? extent.max.x : extent.min.x + (ci1 + 1) * cell.x,
                         cj1 + 1 == height ? extent.max.y : extent.min.y + (cj1 + 1) * cell.y}};
    report.outsideFraction = 1.0 - double(dw) * double(dh) / (double(width) * double(height));
    report.width = dw;
    report.height = dh;
    const auto [lowest, highest] = std::minmax_element(demHeights.begin(), demHeights.end());
    report.minHeight = *lowest;
    report.maxHeight = *highest;

    if (src.files.size() > 1) checkSeams(src, windowBox(src, win), report);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return Dem(report.demExtent, dw, dh, std::move(demHeights));
}

}  // namespace lacet
