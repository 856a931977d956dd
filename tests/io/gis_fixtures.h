#pragma once
// Fixtures of the import tests: a small GeoTIFF DEM written at test time (WGS84, lon 1.50-1.55,
// lat 42.50-42.55, a tilted plane with a valley along x = 1.53 and a block of nodata voids),
// SRTM-like tiles of the same height function over any lon/lat window (for mosaics), and paths of
// the vector corpus in tests/data/vectors.

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

namespace lacet::test {

inline std::string vectorData(const std::string& name) { return std::string(LACET_SOURCE_DIR) + "/tests/data/vectors/" + name; }

// A folder of its own for the running test: its name, the test's and the process id, so that the
// tests of a suite, which run in one process (tests/list_suites.cmake), never share one.
inline std::filesystem::path scratchDir(const std::string& name) {
    std::string test = "none";
    if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info()) {
        test = std::string(info->test_suite_name()) + "_" + info->name();
        for (char& c : test)
            if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    const auto dir = std::filesystem::temp_directory_path() / ("lacet_test_" + name + "_" + test + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
}

// Height of the fixture DEM at (lon, lat): a plane rising to the north-east with a valley.
inline double fixtureHeight(double lon, double lat) {
    return 1000.0 + 2000.0 * (lat - 42.5) + 1000.0 * (lon - 1.5) + 200.0 * std::min(1.0, std::abs(lon - 1.53) / 0.005);
}

// Writes the fixture DEM (100 x 100 samples, voids in a 6 x 6 block) and returns its path.
inline std::string writeFixtureDem(const std::filesystem::path& dir, bool withVoids = true) {
    GDALAllRegister();
    const std::string path = (dir / (withVoids ? "dem_voids.tif" : "dem.tif")).string();
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = gtiff->Create(path.c_str(), 100, 100, 1, GDT_Float32, nullptr);
    double gt[6] = {1.50, 0.0005, 0.0, 42.55, 0.0, -0.0005};
    ds->SetGeoTransform(gt);
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    ds->SetSpatialRef(&wgs84);
    std::vector<float> v(100 * 100);
    for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i) {
            const double lon = 1.50 + (i + 0.5) * 0.0005, lat = 42.55 - (j + 0.5) * 0.0005;
            v[std::size_t(j * 100 + i)] = float(fixtureHeight(lon, lat));
            if (withVoids && i >= 40 && i < 46 && j >= 60 && j < 66) v[std::size_t(j * 100 + i)] = -32768.0f;
        }
    GDALRasterBand* b = ds->GetRasterBand(1);
    b->SetNoDataValue(-32768.0);
    if (b->RasterIO(GF_Write, 0, 0, 100, 100, v.data(), 100, 100, GDT_Float32, 0, 0) != CE_None) std::abort();
    GDALClose(ds);
    return path;
}

// Writes an SRTM-like GeoTIFF tile at `path`: (nx + 1) x (ny + 1) samples `step` degrees apart,
// from (lonWest, latSouth) to (lonWest + nx step, latSouth + ny step), its footprint half a step
// beyond (pixel-is-area, as SRTM's), so that tiles nx steps apart share their border column and
// tiles ny steps apart their border row, as SRTM's do. Heights: fixtureHeight + `offset` metres
// (float32, nodata -32768). `crs`: the CRS written, WGS84 when empty, else any string
// OGRSpatialReference::SetFromUserInput takes (the geotransform stays in degrees).
inline std::string writeDemTile(const std::filesystem::path& path, double lonWest, double latSouth, int nx, int ny, double step,
                                double offset = 0.0, const std::string& crs = "") {
    GDALAllRegister();
    GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDataset* ds = gtiff->Create(path.string().c_str(), nx + 1, ny + 1, 1, GDT_Float32, nullptr);
    if (!ds) std::abort();
    double gt[6] = {lonWest - step / 2, step, 0.0, latSouth + ny * step + step / 2, 0.0, -step};
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    if (crs.empty()) srs.SetWellKnownGeogCS("WGS84");
    else if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE) std::abort();
    ds->SetSpatialRef(&srs);
    std::vector<float> v(std::size_t(nx + 1) * std::size_t(ny + 1));
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
            v[std::size_t(j) * std::size_t(nx + 1) + std::size_t(i)] =
                float(fixtureHeight(lonWest + i * step, latSouth + (ny - j) * step) + offset);
    GDALRasterBand* b = ds->GetRasterBand(1);
    b->SetNoDataValue(-32768.0);
    if (b->RasterIO(GF_Write, 0, 0, nx + 1, ny + 1, v.data(), nx + 1, ny + 1, GDT_Float32, 0, 0) != CE_None) std::abort();
    GDALClose(ds);
    return path.string();
}

// Writes a line Shapefile at `path` with one primary road in UTM 31N metres near the fixture DEM
// (about lon 1.51, lat 42.52), with its CRS (.prj) or without.
inline std::string writeRoadShapefile(const std::filesystem::path& path, bool withCrs) {
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("ESRI Shapefile");
    GDALDataset* ds = drv->Create(path.string().c_str(), 0, 0, 0, GDT_Unknown, nullptr);
    if (!ds) std::abort();
    OGRSpatialReference utm;
    utm.importFromEPSG(32631);  // UTM 31N, a projected CRS the reader must transform from
    OGRLayer* layer = ds->CreateLayer("roads", withCrs ? &utm : nullptr, wkbLineString, nullptr);
    OGRFieldDefn field("highway", OFTString);
    layer->CreateField(&field);
    OGRFeature* f = OGRFeature::CreateFeature(layer->GetLayerDefn());
    f->SetField("highway", "primary");
    OGRLineString line;
    line.addPoint(376000.0, 4708000.0);
    line.addPoint(377000.0, 4708500.0);
    f->SetGeometry(&line);
    if (layer->CreateFeature(f) != OGRERR_NONE) std::abort();
    OGRFeature::DestroyFeature(f);
    GDALClose(ds);
    return path.string();
}

}  // namespace lacet::test
