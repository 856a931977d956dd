#pragma once
// DEM import at the source's resolution, out of core (issue 16): the scene grid is resampled in
// strips of rows from the top and written row by row into a DEM LOD tree (io/dem_lod.h) in a
// GeoPackage of its own, so that neither the source nor the scene grid is ever whole in memory.
// The scene file takes the tree from there when it is saved (SceneDocument::demLod).
//
// Order of calls: demSourceInfo(inputs) (io/dem_import.h), then importDemLod(info, frame, extent,
// cellSize, lodPath, report), then DemLodFile(lodPath) to read it. writeDemLodFile() is the writing
// half alone, for any producer of rows (the synthetic DEM of `lacet synth --dem-side`).
//
// Same samples as importDem. Every step is importDem's, through the same functions: the scene grid,
// the cell centres transformed to the source, the footprints, the harmonic void fill, the bilinear
// resampling, the seams (io/dem_import.h). What differs is what each step sees:
//   - The source window of a strip is the bounding box of its border cell centres plus kWindowMargin
//     samples (the bilinear stencil), then `voidMargin` more source rows above and below for the
//     void fill, within importDem's window of the whole scene (its columns whole). A void sample
//     filled at layer d (d samples from the nearest valid sample) gets importDem's value when the
//     window reaches 2 d rows beyond it on the sides where it was cut; a larger void is still filled
//     from what the strip's window holds (continuous with its rim there, not with the rim beyond),
//     and counted in DemImportReport::voidsBeyondMargin. A void cut off from every valid sample in
//     the strip's window is left void, as importDem leaves one cut off in its window.
//   - The Dem's extent is the bounding box of the scene cells whose centres lie inside a footprint
//     (importDem also leaves out a cell whose four stencil samples are all void: here it is filled as
//     an uncovered cell). When every side of the grid has such a cell it is the whole grid, found
//     from the border alone; otherwise one pass over the cell centres (transforms only) finds it.
//   - Uncovered cells inside it (a missing tile, the border's curvature) are filled like importDem's
//     over the strip and `uncoveredMargin` scene rows above and below, resampled again for that
//     (only for strips holding such cells); the same rule and count (uncoveredBeyondMargin) apply.
//   - Square cells: the grid has round(extent.x / cellSize) columns of extent.x / columns metres on
//     both axes (the tree has one cell); the rows cover extent.y to within half a cell. importDem's
//     grid is the same one for a square extent (what importScene makes).
// Memory: the strip's source window and scene rows (DemImportReport::peakStripSamples, about
// (stripRows + 2 voidMargin) x the window's width) and the writer's blockSide rows of each level
// (io/dem_lod.h), whatever the height; no limit of kMaxDemSide (the tree's, 2^30 samples a side).
//
// Units: scene positions in metres of the scene frame, heights in metres.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "io/dem_import.h"
#include "io/dem_lod.h"
#include "model/progress.h"
#include "raster/dem.h"

namespace lacet {

// The largest side of a scene grid stored as a tree, samples.
inline constexpr int kMaxLodDemSide = 1 << 30;

struct DemLodImportParams {
    int stripRows = 256;                   // scene rows resampled at once, >= 1
    int voidMargin = 64;                   // source rows read beyond a strip's window for the void fill, >= 0
    int uncoveredMargin = 32;              // scene rows resampled beyond a strip for its uncovered cells, >= 0
    int blockSide = kDefaultDemBlockSide;  // samples, even, >= 4 (DemLodLayout::make)
    int coarseSide = kInMemoryDemSide;     // samples a side, >= 1: the level kept in memory (levelAtMost)
};

// What writeDemLodFile made.
struct DemLodOutput {
    DemLodLayout layout;
    std::uint64_t tiles = 0, bytes = 0;  // tiles written and their encoded bytes
    std::string digest;                  // DemLodWriter::digest()
    int coarseLevel = 0;                 // levelAtMost(layout, coarseSide)
    std::optional<Dem> coarse;           // that level in memory, as readDemLevel() gives it
    double ms = 0.0;
};

// Makes the row of the finest grid `t` (from the top, called for t = 0, 1, ... height - 1 in order)
// into `heights` (layout.width finite values, metres, west to east).
using DemRowSource = std::function<void(int t, std::span<float> heights)>;

// A name for a tree's own GeoPackage beside `beside` (an output path) that no file has:
// beside + ".dem." + the process id + "." + 16 random hex digits + ".tmp", made sure of by creating
// it exclusively (O_CREAT | O_EXCL) and removing it at once (writeDemLodFile creates the file and
// needs the path free). A caller removes the file only once writeDemLodFile (or importScene) made
// it, never a file it found there. Throws std::runtime_error naming the path when none can be
// created (a missing or read-only directory). First removes the temporary files of this kind that
// killed imports left beside `beside` (their process no longer runs).
std::string uniqueDemLodPath(const std::string& beside);
// The same for another temporary file of an import, named beside + "." + `kind` + ".PID.HEX.tmp"
// (an import out of core's spill of features: kind "vectors"), stale ones of that kind removed.
std::string uniqueImportTempPath(const std::string& beside, const std::string& kind);
// Removes the temporary files of every kind that killed imports left beside `beside` (as above).
void removeStaleImportTempFiles(const std::string& beside);

// Removes the file at `path` when destroyed, unless `path` is empty (errors ignored): a tree's file
// this run made, set once it exists (never a file found there), removed after the save or when a
// later step fails.
struct RemoveFileOnExit {
    std::string path;
    RemoveFileOnExit() = default;
    RemoveFileOnExit(const RemoveFileOnExit&) = delete;
    RemoveFileOnExit& operator=(const RemoveFileOnExit&) = delete;
    ~RemoveFileOnExit();
};

// Creates a GeoPackage at `path` (which must not exist: std::invalid_argument, the file untouched) holding the tree of `layout` (srs_id -1,
// GeoPackage's undefined Cartesian: scene metres; the scene file gives it the scene's CRS when it
// copies the tree), its rows from `rowAt`, in one transaction, keeping level
// levelAtMost(layout, coarseSide) in memory as it goes.
// On failure the file is removed and the exception passed on (rowAt's, DemImportError, SqliteError,
// std::invalid_argument from DemLodWriter).
DemLodOutput writeDemLodFile(const std::string& path, const DemLodLayout& layout, const DemRowSource& rowAt,
                             int coarseSide = kInMemoryDemSide, Progress* progress = nullptr);

// importDem's work (io/dem_import.h) written as a tree into a new GeoPackage at `lodPath` (see the
// header): fills `report` as importDem does (storage "lod", strips, peakStripSamples, the margins'
// counts) and returns the tree's figures with its coarse level (the Dem old code paths use).
// Throws DemImportError as importDem does (the cell's range up to kMaxLodDemSide samples a side),
// also when a strip and its margins hold no DEM data at all; std::invalid_argument naming
// DemLodImportParams for parameters out of range.
DemLodOutput importDemLod(const DemSourceInfo& source, const SceneFrame& frame, const Box& extent, double cellSize,
                          const std::string& lodPath, DemImportReport& report, const DemLodImportParams& params = {},
                          Progress* progress = nullptr);

}  // namespace lacet
