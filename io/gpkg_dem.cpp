#include "io/gpkg_dem.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "io/sqlite_db.h"

namespace lacet {
namespace {

void registerDrivers() {
    static const bool registered = [] {
        GDALAllRegister();
        return true;
    }();
    (void)registered;
}

// Collects GDAL's failure messages on this thread instead of printing them (the GPKG driver also
// warns about file names not ending in .gpkg, as the temporary file of a save does).
class GdalErrors {
public:
    GdalErrors() { CPLPushErrorHandlerEx(&GdalErrors::handler, this); }
    ~GdalErrors() { CPLPopErrorHandler(); }
    GdalErrors(const GdalErrors&) = delete;
    GdalErrors& operator=(const GdalErrors&) = delete;

    // True once GDAL has reported a failure: it reports an undecodable tile so, yet RasterIO
    // succeeds (with zeros).
    bool failed() const { return failed_; }
    [[noreturn]] void fail(const std::string& what) const {
        throw std::runtime_error(what + (last_.empty() ? std::string() : " (GDAL: " + last_ + ")"));
    }

private:
    static void CPL_STDCALL handler(CPLErr level, CPLErrorNum, const char* message) {
        auto* self = static_cast<GdalErrors*>(CPLGetErrorHandlerUserData());
        if (self && level >= CE_Failure) {
            self->failed_ = true;
            if (message) self->last_ = message;
        }
    }
    std::string last_;
    bool failed_ = false;
};

struct DatasetCloser {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

GDALDriver* driver(const char* name, const GdalErrors& errors) {
    registerDrivers();
    GDALDriver* d = GetGDALDriverManager()->GetDriverByName(name);
    if (!d) errors.fail(std::string("GDAL has no ") + name + " driver");
    return d;
}

// Closes `d`, reporting a failure to flush (GDALClose returns CE_Failure since GDAL 3.7 only, so
// also look at the error state).
void closeChecked(DatasetPtr& d, const GdalErrors& errors, const std::string& what) {
    CPLErrorReset();
    d.reset();
    if (CPLGetLastErrorType() >= CE_Failure) errors.fail(what);
}

}  // namespace

void createGpkgWithDem(const std::string& path, const Dem& dem, const std::string& crsWkt) {
    GdalErrors errors;
    GDALDriver* mem = driver("MEM", errors);
    GDALDriver* gpkg = driver("GPKG", errors);
    const int w = dem.width(), h = dem.height();
    DatasetPtr src(mem->Create("", w, h, 1, GDT_Float32, nullptr));
    if (!src) errors.fail("cannot create an in-memory raster of " + std::to_string(w) + " x " + std::to_string(h));
    const Box& e = dem.extent();
    const Vec2 cell = dem.cellSize();
    double gt[6] = {e.min.x, cell.x, 0.0, e.max.y, 0.0, -cell.y};
    src->SetGeoTransform(gt);
    if (!crsWkt.empty()) {
        OGRSpatialReference srs;
        srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        if (srs.importFromWkt(crsWkt.c_str()) == OGRERR_NONE) src->SetSpatialRef(&srs);
    }
    GDALRasterBand* band = src->GetRasterBand(1);
    band->SetUnitType("m");
    // GDAL skips tiles made only of the nodata value (0 when none is set: a tile of -0.0 would come
    // back as +0.0). A Dem holds no NaN, so NaN as nodata makes GDAL write every tile. (The GPKG
    // cannot record a NaN nodata: readers see none, and missing tiles read as 0.)
    band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
    for (int j = 0; j < h; ++j) {
        float* row = const_cast<float*>(dem.heights().data()) + std::size_t(j) * std::size_t(w);  // not written to
        if (band->RasterIO(GF_Write, 0, h - 1 - j, w, 1, row, w, 1, GDT_Float32, 0, 0, nullptr) != CE_None)
            errors.fail("cannot fill the in-memory raster");
    }
    const std::string table = std::string("RASTER_TABLE=") + kDemRasterTable;
    const std::string identifier = std::string("RASTER_IDENTIFIER=") + kDemRasterTable;
    const char* options[] = {table.c_str(), identifier.c_str(), "RASTER_DESCRIPTION=Lacet scene DEM (heights in metres)",
                             "TILE_FORMAT=TIFF", "VERSION=1.2", nullptr};
    DatasetPtr out(gpkg->CreateCopy(path.c_str(), src.get(), FALSE, const_cast<char**>(options), nullptr, nullptr));
    if (!out) errors.fail("cannot write the DEM raster");
    closeChecked(out, errors, "cannot write the DEM raster");
}

void createEmptyGpkg(const std::string& path) {
    GdalErrors errors;
    GDALDriver* gpkg = driver("GPKG", errors);
    const char* options[] = {"VERSION=1.2", nullptr};
    DatasetPtr out(gpkg->Create(path.c_str(), 0, 0, 0, GDT_Unknown, const_cast<char**>(options)));
    if (!out) errors.fail("cannot create a GeoPackage");
    closeChecked(out, errors, "cannot create a GeoPackage");
    // GDAL does not report every failed write of the new file's tables (a full disk): check them.
    bool whole = false;
    try {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        whole = db.hasTable("gpkg_contents") && db.hasTable("gpkg_spatial_ref_sys");
    } catch (const SqliteError&) {
    }
    if (!whole) throw std::runtime_error("cannot create a GeoPackage: its required tables are missing (a write failed: a full disk?)");
}

std::vector<float> readGpkgDem(const std::string& path, int width, int height) {
    GdalErrors errors;
    registerDrivers();
    const char* drivers[] = {"GPKG", nullptr};
    const std::string table = std::string("TABLE=") + kDemRasterTable;
    const char* openOptions[] = {table.c_str(), nullptr};
    DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, openOptions, nullptr));
    if (!ds) errors.fail(std::string("cannot open the DEM raster table '") + kDemRasterTable + "'");
    if (ds->GetRasterCount() < 1 || ds->GetRasterXSize() != width || ds->GetRasterYSize() != height)
        throw std::runtime_error("the DEM raster is " + std::to_string(ds->GetRasterXSize()) + " x " +
                                 std::to_string(ds->GetRasterYSize()) + " with " + std::to_string(ds->GetRasterCount()) +
                                 " band(s), expected " + std::to_string(width) + " x " + std::to_string(height));
    std::vector<float> heights(std::size_t(width) * std::size_t(height));
    GDALRasterBand* band = ds->GetRasterBand(1);
    for (int j = 0; j < height; ++j)
        if (band->RasterIO(GF_Read, 0, height - 1 - j, width, 1, heights.data() + std::size_t(j) * std::size_t(width),
                           width, 1, GDT_Float32, 0, 0, nullptr) != CE_None)
            errors.fail("cannot read the DEM raster");
    if (errors.failed()) errors.fail("cannot read the DEM raster");
    return heights;
}

}  // namespace lacet
