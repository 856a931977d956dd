// Hostile sizes through `lacet import` (issue 26): a way of 10^6 points, a polygon with 10^5 holes
// and a DEM of 1 x 10^6 samples are imported whole, within 2 GiB of peak memory (the import's own,
// measured as its child's maximum resident size); a 400 km scene at 0.1 m cells is refused with the
// figures (tests/app/import_cli_test.cpp: dem_cell_too_fine_for_the_disk). Each input is made here.
// (A way of 10^6 OSM nodes is refused by GDAL's OSM driver, naming the way: "Too many nodes
// referenced"; GeoJSON has no such limit.)
#include <sys/resource.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ogr_spatialref.h>

#include "tests/io/gis_fixtures.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// The sanitized lacet's bound: AddressSanitizer's shadow and quarantine on top.
constexpr double kMemoryBoundKiB = (test::kSanitized ? 8.0 : 2.0) * 1024 * 1024;

// The hostile sizes: a tenth of them under the sanitizers, which import the same way ten to
// twenty-five times slower (the Release suite imports them whole, and the peak memory bound above
// is theirs).
const int kWayPoints = test::sanitizedOr(1000000, 100000);
const int kHoles = test::sanitizedOr(100000, 10000);

struct Imported {
    int code = -1;
    nlohmann::json report;
    std::string err;
    double peakKiB = 0.0;  // the import's maximum resident size
};

// Runs `lacet import args --json` in a child of its own, so that its peak memory is its own.
Imported import(const fs::path& dir, const std::string& args) {
    Imported r;
    const fs::path out = dir / "report.json", err = dir / "import.err";
    const std::string cmd = "cd '" + dir.string() + "' && exec " + LACET_BINARY + " import " + args + " --json > report.json 2> import.err";
    const pid_t child = ::fork();
    if (child == 0) {
        ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    rusage usage{};
    ::wait4(child, &status, 0, &usage);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.peakKiB = double(usage.ru_maxrss);
    std::ifstream e(err);
    r.err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
    if (r.code == 0) r.report = nlohmann::json::parse(std::ifstream(out));
    return r;
}

const nlohmann::json& layer(const nlohmann::json& report, const std::string& name) {
    for (const auto& l : report["layers"])
        if (l["name"] == name) return l;
    static const nlohmann::json none;
    return none;
}

TEST(HostileSizes, AWayOfAMillionPointsIsImportedWithinItsMemory) {
    const fs::path dir = test::scratchDir("hostile_way");
    {
        std::ofstream f(dir / "way.geojson");
        f << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": 1, "properties": {"highway": "primary"},
 "geometry": {"type": "LineString", "coordinates": [)";
        const int n = kWayPoints;
        char point[64];
        for (int i = 0; i < n; ++i) {
            const double t = double(i) / n;
            std::snprintf(point, sizeof point, "%s[%.7f, %.7f]", i ? ", " : "", 1.50 + 0.04 * t + 0.002 * std::sin(t * 400.0),
                          42.50 + 0.03 * t + 0.002 * std::cos(t * 400.0));
            f << point;
        }
        f << "]}}]}\n";
    }
    const Imported r = import(dir, "--vectors way.geojson --out way.gpkg");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.report["fit"]["input_points"], kWayPoints);
    EXPECT_EQ(layer(r.report, "roads")["curves_by_class"].size(), 1u);
    EXPECT_LE(r.report["fit"]["max_error_m"].get<double>(), 0.5);
    EXPECT_LT(r.peakKiB, kMemoryBoundKiB);
    std::printf("[ figures ] a way of %d points: %.0f MiB peak, %.1f s\n", kWayPoints, r.peakKiB / 1024.0, r.report["ms"].get<double>() / 1000.0);
    fs::remove_all(dir);
}

TEST(HostileSizes, APolygonWithAHundredThousandHolesIsImportedWithinItsMemory) {
    const fs::path dir = test::scratchDir("hostile_holes");
    constexpr int side = 317;  // holes on a side-by-side lattice, up to 100,489
    const int holes = kHoles;
    {
        std::ofstream f(dir / "holes.geojson");
        f << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "id": 1, "properties": {"landuse": "forest"},
 "geometry": {"type": "Polygon", "coordinates": [[[1.45, 42.45], [1.55, 42.45], [1.55, 42.55], [1.45, 42.55], [1.45, 42.45]])";
        char ring[256];
        int made = 0;
        for (int a = 0; a < side && made < holes; ++a)
            for (int b = 0; b < side && made < holes; ++b, ++made) {
                const double x = 1.45 + 0.1 * (a + 0.3) / side, y = 42.45 + 0.1 * (b + 0.3) / side, d = 0.1 * 0.4 / side;
                std::snprintf(ring, sizeof ring, ", [[%.8f, %.8f], [%.8f, %.8f], [%.8f, %.8f], [%.8f, %.8f], [%.8f, %.8f]]", x, y, x,
                              y + d, x + d, y + d, x + d, y, x, y);
                f << ring;
            }
        f << "]}}]}\n";
    }
    const Imported r = import(dir, "--vectors holes.geojson --out holes.gpkg");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json& forests = layer(r.report, "forests");
    EXPECT_EQ(forests["holes"], holes);
    EXPECT_EQ(forests["areas_by_class"].size(), 1u);
    EXPECT_LT(r.peakKiB, kMemoryBoundKiB);
    std::printf("[ figures ] a polygon with %d holes: %.0f MiB peak, %.1f s\n", holes, r.peakKiB / 1024.0, r.report["ms"].get<double>() / 1000.0);
    fs::remove_all(dir);
}

TEST(HostileSizes, ADemOfAMillionByOneSamplesIsImportedWithinItsMemory) {
    const fs::path dir = test::scratchDir("hostile_dem");
    {
        GDALAllRegister();
        GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create((dir / "line.tif").c_str(), 1000000, 1, 1,
                                                                                   GDT_Float32, nullptr);
        ASSERT_NE(ds, nullptr);
        const double gt[6] = {1.4, 0.2 / 1000000, 0.0, 42.6, 0.0, -0.2};
        ds->SetGeoTransform(const_cast<double*>(gt));
        OGRSpatialReference wgs84;
        wgs84.SetWellKnownGeogCS("WGS84");
        ds->SetSpatialRef(&wgs84);
        std::vector<float> row(1000000);
        for (std::size_t i = 0; i < row.size(); ++i) row[i] = float(1000.0 + 100.0 * std::sin(double(i) * 1e-4));
        ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 1000000, 1, row.data(), 1000000, 1, GDT_Float32, 0, 0), CE_None);
        GDALClose(ds);
    }
    fs::copy_file(test::vectorData("good.geojson"), dir / "good.geojson");
    const Imported r = import(dir, "--dem line.tif --vectors good.geojson --dem-storage lod --dem-cell 20 --out line.gpkg");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.report["dem"]["source_size"][0], 1000000);
    EXPECT_EQ(r.report["dem"]["source_size"][1], 1);
    EXPECT_LT(r.peakKiB, kMemoryBoundKiB);
    std::printf("[ figures ] a DEM of 10^6 x 1 samples: %.0f MiB peak, %.1f s\n", r.peakKiB / 1024.0, r.report["ms"].get<double>() / 1000.0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lacet
