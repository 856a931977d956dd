#pragma once
// Private to io/ (io/dem_import*.cpp, io/dem_import_lod.cpp): the steps of the DEM import shared by
// the in-memory importDem and the out-of-core importDemLod, so that both give the same samples from
// the same formulas: the scene grid, the source window under rows of it, the window read with its
// voids, the harmonic fill, the bilinear resampling of a row, the seams.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gdal_priv.h>

#include "io/dem_import.h"

namespace lacet::dem_detail {

struct GdalClose {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, GdalClose>;

std::string number(double v);

// Opens `path` as a raster, quietly; throws DemImportError naming `name` with GDAL's reason.
Dataset openRaster(const std::string& path, const std::string& name);

// Whether (x, y), in the source CRS, is inside one of the rasters' footprints.
bool inFootprints(const DemSourceInfo& src, double x, double y);

// A block of one band's samples, its top-left sample (x0, y0) in its raster.
struct Block {
    int x0 = 0, y0 = 0, width = 0, height = 0;
    std::vector<float> values;
    std::vector<std::uint8_t> valid;
};
// Reads a block of band 1 (invalid: non-finite or nodata); throws DemImportError naming `name`.
Block readBlock(GDALDataset& ds, const std::string& name, int x0, int y0, int width, int height);

// The scene grid over `extent`: width x height cells, sample (i, j) at the centre of cell (i, j),
// j growing with y (raster/dem.h's convention).
struct SceneGrid {
    Box extent;
    int width = 0, height = 0;
    Vec2 cell{0.0};  // metres
    Vec2 centre(int i, int j) const { return extent.min + (Vec2(i, j) + 0.5) * cell; }
};

// The grid of about `cellSize` metres over `extent` (round(extent / cellSize) cells a side, between
// 2 and `maxSide`). Throws DemImportError naming `name` with the valid range of the cell.
SceneGrid makeSceneGrid(const std::string& name, const Box& extent, double cellSize, double maxSide);

// The error of a scene the DEM does not cover.
DemImportError notCovered(const std::string& name, const SceneFrame& frame, const Box& extent, const DemSourceInfo& src);

// A window of source samples, bounds inclusive.
struct SourceWindow {
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
    int width() const { return x1 - x0 + 1; }
    int height() const { return y1 - y0 + 1; }
    bool empty() const { return x1 < x0 || y1 < y0; }
};

// The bounding box, in source samples, of the centres of the border cells of grid rows [j0, j1]
// (all columns), plus kWindowMargin samples, clamped to the source. Empty when no centre transforms
// to the source CRS. Also counts the border cell centres inside a footprint, per side (bottom row,
// top row, left column, right column), in `coveredBorder` when not null.
SourceWindow borderWindow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j0, int j1,
                          int coveredBorder[4] = nullptr);

// The window's box in the source CRS (pixel-is-area).
Box windowBox(const DemSourceInfo& src, const SourceWindow& w);

// Cell states of the fill.
enum CellState : std::uint8_t { kNoData = 0, kKnown = 1, kOpen = 2, kQueued = 3 };

// Fills the open cells of a width x height grid from the known ones, layer by layer (each layer
// takes the mean of its known 8-neighbours, then becomes known); no-data cells are neither read nor
// filled. Returns how many were filled; open cells that no layer reaches stay open. `layerOf`, when
// not null, gets each filled cell's layer (1: next to a known cell), 0 elsewhere.
std::size_t fillFromNeighbours(std::vector<float>& v, std::vector<std::uint8_t>& state, int width, int height,
                               std::vector<int>* layerOf = nullptr);

Dataset openSource(const DemSourceInfo& src, const std::string& name);

// A window of the source's first band: values, and states (kKnown: a valid sample whose centre is
// inside a footprint, kOpen: a void there, kNoData: outside every footprint).
struct WindowSamples {
    SourceWindow at;
    std::vector<float> values;
    std::vector<std::uint8_t> state;
};
WindowSamples readWindow(GDALDataset& ds, const DemSourceInfo& src, const std::string& name, const SourceWindow& w);

// Resamples columns [i0, i1] of grid row j bilinearly from `window` (whose voids are filled):
// heights[i - i0], covered[i - i0] (0 where the cell's centre is outside every footprint or no
// stencil sample has data; the height is then left as it was).
void resampleRow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, const WindowSamples& window, int j, int i0,
                 int i1, float* heights, std::uint8_t* covered);

// Whether the centres of columns [i0, i1] of grid row j lie inside a footprint: covered[i - i0].
void coveredCells(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j, int i0, int i1, std::uint8_t* covered);

// Compares every pair of rasters touching inside `window` (source CRS) along their shared border.
void checkSeams(const DemSourceInfo& src, const Box& window, DemImportReport& report);

// Resets `report` and fills what the source gives: path (the inputs, comma-separated: the name
// messages use), files, sourceWidth, sourceHeight, sourceResolution.
void initReport(const DemSourceInfo& src, DemImportReport& report);

// How many of the rasters' footprints meet `window` (source CRS): the files read.
std::size_t filesMeeting(const DemSourceInfo& src, const Box& window);

}  // namespace lacet::dem_detail
