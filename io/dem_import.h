#pragma once
// DEM import through GDAL: one raster or a mosaic of tiles, resampled onto the scene's grid.
//
// Order of calls: demSourceInfo(inputs) checks every input and describes the source without
// reading its samples (bounds, size, resolution, which lon/lat points it covers); the caller
// chooses its scene frame and extent from it, then importDem(info, frame, extent, cellSize, report)
// reads the part of the source under the extent and returns the Dem of the part the data covers.
//
// Inputs: each is a raster file (anything GDAL reads: GeoTIFF, SRTM .hgt, also inside a zip
// through /vsizip/), a .vrt, or a directory, standing for its raster files (non-recursive, sorted
// by name; the files GDAL does not open as rasters are ignored). Every raster must exist, be
// georeferenced (not rotated) and have a CRS; no file may be given twice (directly or through a
// directory); several rasters must share one CRS. They are combined by GDAL's own mosaic
// (GDALBuildVRT, in memory): where rasters overlap the later one in the list wins, at the
// resolution GDAL chooses (the average of the inputs'). The first band is read, in metres.
//
// Window: importDem transforms the scene grid's border cell centres to the source CRS, takes their
// bounding box in source samples plus kWindowMargin samples (the bilinear stencil's reach), clamped
// to the source, and reads that window only.
// Voids (nodata or NaN samples inside the data) in the window are filled from the outside in; each
// pass gives every void sample with valid neighbours the mean of its valid 8-neighbours from the
// previous pass (a discrete harmonic fill, continuous at the void's rim). Counted in the report.
// Resampling: bilinear between source sample centres; within the half sample between the
// outermost sample centres and a raster's border, the outermost samples are continued.
//
// Coverage: a point is covered when it lies inside the footprint (the pixel-is-area bounds) of one
// of the rasters: a mosaic with a missing tile has a hole there, which is not covered. The returned
// Dem's extent is the bounding box of the scene cells whose centres are covered, on the scene grid
// (its cells are exactly scene cells); what lies outside it is not invented but reported (the
// fraction of the scene extent's area, and the Dem's extent): the caller decides what to do with
// the scene beyond the DEM. Cells inside that box but not covered (slivers where the projection
// curves the DEM's border, holes of missing tiles) are filled like voids from their covered
// neighbours, on the scene grid, and counted apart.
//
// Seams: for a mosaic, every pair of rasters whose footprints touch or overlap is compared along
// their shared border inside the window (SRTM tiles share their border row or column): both are
// sampled there (bilinear; on a border that they only touch, each continued linearly from its two
// outermost samples) and the largest height difference is reported, per seam and overall.
//
// Units: heights in metres (the band's values as they are; no scale, offset or vertical unit is
// applied), scene positions in metres of the scene frame (io/scene_frame.h), lon/lat in degrees.

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "io/scene_frame.h"
#include "raster/dem.h"

class OGRCoordinateTransformation;

namespace lacet {

class DemImportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct DemSourceInfo {
    std::vector<std::string> inputs;  // as given
    std::vector<std::string> files;   // the rasters, in mosaic order (a later one wins where they overlap)
    Box lonLat;                       // union of the rasters' bounds: (min lon, min lat) - (max lon, max lat), degrees
    int width = 0, height = 0;        // the mosaic's size, samples
    Vec2 resolution{0.0};             // metres per source sample (east, north) at the centre latitude
    std::string crsName;              // the rasters' CRS

    // True when `lonLat` (degrees) is inside one of the rasters' footprints (see the header).
    // Not thread-safe when the source CRS is not WGS84 lon/lat (it shares one transformation).
    bool covers(glm::dvec2 lonLat) const;

    // What importDem reads; filled by demSourceInfo.
    std::vector<std::string> sources;  // the files' paths as GDAL opens them (absolute)
    std::string dataset;              // the single raster's path, or the mosaic's VRT as XML
    double geoTransform[6] = {0, 1, 0, 0, 0, -1};  // the mosaic's (GDAL's convention)
    std::vector<Box> footprints;      // per file, in the source CRS
    std::shared_ptr<OGRCoordinateTransformation> fromWgs84;  // null when the source is WGS84 lon/lat
    std::shared_ptr<OGRCoordinateTransformation> toWgs84;
};

// Checks every input (see the header) and describes the source without reading its samples.
// Throws DemImportError naming the file and the reason: no such file, not a raster, not
// georeferenced, no CRS, rotated, given twice, CRS differing from another file's (naming both),
// an empty directory, or GDAL's mosaic refusing the set.
DemSourceInfo demSourceInfo(const std::vector<std::string>& inputs);

// One seam of a mosaic: two rasters compared along their shared border inside the window read.
struct DemSeam {
    std::string fileA, fileB;
    std::size_t points = 0;       // compared (points where either raster is void are skipped)
    double largestStep = 0.0;     // metres, the largest |height A - height B|
    glm::dvec2 where{0.0};        // lon/lat of the largest step, degrees
};

struct DemImportReport {
    std::string path;                    // the inputs, comma-separated
    std::vector<std::string> files;      // the rasters read
    int sourceWidth = 0, sourceHeight = 0;  // the mosaic's size, samples
    int windowX = 0, windowY = 0, windowWidth = 0, windowHeight = 0;  // the source window read, samples
    Vec2 sourceResolution{0.0};          // metres per source sample (east, north)
    std::size_t voids = 0;               // void source samples in the window, filled (those no valid sample reaches are left uncovered)
    std::size_t uncoveredFilled = 0;     // Dem cells inside its extent not covered by data, filled
    double outsideFraction = 0.0;        // of the scene extent's area, outside the Dem's extent
    Box demExtent;                       // the Dem's extent, scene metres
    double cellSize = 0.0;               // metres, of the scene grid (the resolution kept)
    int sceneWidth = 0, sceneHeight = 0;  // the scene grid over the whole extent
    int width = 0, height = 0;           // the Dem's grid (the covered part of the scene grid)
    double minHeight = 0.0, maxHeight = 0.0;
    std::vector<DemSeam> seams;          // one per pair of rasters touching inside the window
    std::size_t seamsChecked = 0;        // seams with at least one point compared
    double largestSeamStep = 0.0;        // metres, over every seam
    glm::dvec2 largestSeamStepAt{0.0};   // lon/lat, degrees
    std::size_t filesRead = 0;           // rasters whose footprint meets the window read
    // How the grid was made: "grid" (importDem, in memory) or "lod" (importDemLod, in strips of rows).
    std::string storage = "grid";
    int strips = 0;                      // strips of scene rows resampled (1 for importDem)
    std::size_t peakStripSamples = 0;    // the most source and scene samples held at once (window read + scene rows)
    std::size_t voidsBeyondMargin = 0;   // lod: void samples filled whose fill may differ from importDem's (see io/dem_import_lod.h)
    std::size_t uncoveredBeyondMargin = 0;  // lod: the same for uncovered cells
    double ms = 0.0;
};

// Samples of margin around the window read, beyond the scene's border cell centres.
inline constexpr int kWindowMargin = 2;
// The largest scene grid side, samples.
inline constexpr int kMaxDemSide = 16384;

// Reads the window of `source` under `extent` (scene metres, max > min) and resamples it onto the
// scene grid of about `cellSize` metres (the extent divided into round(extent / cellSize) cells a
// side, between 2 and kMaxDemSide). Returns the Dem of the covered cells (see the header) and fills
// `report`. Throws DemImportError when the grid would be degenerate or too large (with the valid
// range of cellSize), when no scene cell is covered, or when reading fails.
Dem importDem(const DemSourceInfo& source, const SceneFrame& frame, const Box& extent, double cellSize, DemImportReport& report);

}  // namespace lacet
