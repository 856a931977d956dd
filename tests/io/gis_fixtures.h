#pragma once
// Fixtures of the import tests: a small GeoTIFF DEM written at test time (WGS84, lon 1.50-1.55,
// lat 42.50-42.55, a tilted plane with a valley along x = 1.53 and a block of nodata voids), and
// paths of the vector corpus in tests/data/vectors.

#include <filesystem>
#include <string>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

namespace lacet::test {

inline std::string vectorData(const std::string& name) { return std::string(LACET_SOURCE_DIR) + "/tests/data/vectors/" + name; }

inline std::filesystem::path scratchDir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("lacet_test_" + name + "_" + std::to_string(::getpid()));
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

}  // namespace lacet::test
