#pragma once
// The DEM of a scene file as a GeoPackage raster (2D gridded coverage, Float32, lossless TIFF
// tiles), written and read through GDAL's GPKG driver, so that gdalinfo and GIS tools open it.
// Also the creation of a GeoPackage with no raster, for scenes without a DEM.
//
// Every tile of the raster is written (none is skipped as empty), so a missing tile means a damaged
// file.
//
// Grid mapping: GeoPackage rows run from the top (max y) down, Dem rows (j) grow with y, so Dem row j
// is raster row height - 1 - j. The raster's geotransform is that of dem.extent() divided into
// width x height cells (pixel is area, values at cell centres); its heights are in metres.
// Errors throw std::runtime_error with the reason only (GDAL's message); callers add the file name.

#include <string>
#include <vector>

#include "raster/dem.h"

namespace lacet {

// Name of the raster table (and of its gpkg_contents entry).
inline constexpr const char* kDemRasterTable = "dem";

// Creates a new GeoPackage 1.2 at `path` (which must not exist) holding `dem` as raster table
// kDemRasterTable. `crsWkt`, when not empty and understood by GDAL, is the raster's CRS;
// otherwise the raster's CRS is left undefined.
void createGpkgWithDem(const std::string& path, const Dem& dem, const std::string& crsWkt);

// Creates a new, empty GeoPackage 1.2 at `path` (which must not exist): the required tables only.
void createEmptyGpkg(const std::string& path);

// Reads the heights of raster table kDemRasterTable of the GeoPackage at `path`, row by row in
// Dem order (heights[j * width + i], j growing with y). Throws if the raster is missing or is not
// width x height.
std::vector<float> readGpkgDem(const std::string& path, int width, int height);

}  // namespace lacet
