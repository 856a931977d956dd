#pragma once
// DEM import through GDAL (GeoTIFF, SRTM .hgt, also inside a zip through /vsizip/, anything GDAL
// reads): the first band, voids (nodata) filled, resampled onto a regular grid of the scene's
// projected CRS (io/scene_frame.h) by bilinear interpolation between source sample centres.
//
// Voids: filled from the outside in; each pass gives every void cell with valid neighbours the
// mean of its valid 8-neighbours from the previous pass (a discrete harmonic fill, continuous at
// the void's rim). Counted in the report.
// Outside the source: a scene cell whose centre falls outside the source raster takes the value of
// the nearest source sample (the raster's edge continued, as Dem::sample does beyond its extent);
// the fraction of such cells is reported.
// Source CRS: geographic WGS84 is read directly; any other CRS GDAL knows is reached through an OGR
// coordinate transformation from WGS84. Rotated geotransforms are refused.

#include <stdexcept>
#include <string>

#include "io/scene_frame.h"
#include "raster/dem.h"

namespace lacet {

class DemImportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DemImportReport {
    std::string path;
    int sourceWidth = 0, sourceHeight = 0;
    std::size_t voids = 0;          // source samples that were nodata (or NaN), all filled
    double outsideFraction = 0.0;   // of the scene cells, outside the source raster
    double cellSize = 0.0;          // metres, of the scene grid
    int width = 0, height = 0;      // scene grid
    double minHeight = 0.0, maxHeight = 0.0;
    double ms = 0.0;
};

struct DemSourceInfo {
    Box lonLat;  // (min lon, min lat) - (max lon, max lat), degrees
    int width = 0, height = 0;
};
// The source's bounds and size, without reading its samples.
DemSourceInfo demSourceInfo(const std::string& path);

// Throws DemImportError naming the file and the reason (missing, unreadable, no CRS, rotated,
// all void).
Dem importDem(const std::string& path, const SceneFrame& frame, const Box& extent, double cellSize, DemImportReport& report);

}  // namespace lacet
