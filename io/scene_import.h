#pragma once
// `lacet import`: a DEM and GIS vector files into one georeferenced scene (§4.1) with its DEM:
// features read and mapped (io/vector_import.h), a transverse Mercator frame centred on them
// (io/scene_frame.h), the DEM resampled onto the scene's grid (io/dem_import.h), topology and
// splines (io/network_builder.h), the scene validated. The report says what came in, what was
// skipped and why, the fit error (a measured Hausdorff distance) per layer and the vertex
// reduction, duplicates dropped, voids, what lies outside the DEM, the scale error, the river
// areas and how many got an axial curve (network.riverAreas, riverAreasWithAxial) and the time.
//
// What a user can give:
//   - a DEM (one raster, several tiles, a directory or a VRT) and vectors: the scene's square
//     extent surrounds the features the DEM covers, by `margin`, and is moved (never shrunk) to lie
//     inside the DEM when it can; what still lies outside is reported, not invented;
//   - vectors without a DEM: flat ground at `flatHeight` metres, said so in the report;
//   - a DEM without vectors: the largest square the DEM covers, an empty network, said so.
// Failures (an ImportError naming the files and reasons, before anything is written): nothing to
// import, an input that could not be read (truncated, no CRS, undeclared projected coordinates),
// knob values out of range (their range in the message), an extent too large for one transverse
// Mercator frame, or vectors that keep fewer than `minKept` features (by default: nothing kept)
// unless `allowEmpty`.

#include <cstdint>
#include <functional>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "io/dem_import.h"
#include "io/dem_lod.h"
#include "io/network_builder.h"
#include "io/document.h"
#include "model/progress.h"

namespace lacet {

class ImportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// How the imported DEM is held (--dem-storage): in memory (importDem), as a LOD tree written out of
// core (importDemLod, io/dem_import_lod.h), or lod when the scene grid would be more than
// kInMemoryDemSide samples a side (io/dem_lod.h).
enum class DemStorage { Auto, Grid, Lod };
const char* toString(DemStorage s);
// "auto", "grid" or "lod"; throws ImportError naming the valid values otherwise.
DemStorage demStorageFromString(const std::string& s);

struct ImportOptions {
    std::vector<std::string> dem;      // rasters, VRTs or directories; empty: flat ground
    std::vector<std::string> vectors;  // empty: a DEM-only scene
    std::string mapping;               // empty: the default OSM mapping
    double fitTolerance = 0.5;         // metres, in [0, kMaxFitTolerance] (SplineFitParams::tolerance)
    double demCell = 0.0;              // metres, 0 (the source's resolution) or in [kMinDemCell, kMaxDemCell]
    double margin = 200.0;             // metres of scene around the features, in [0, kMaxMargin]
    double flatHeight = 0.0;           // metres: the ground's height when no DEM is given, in [kMinFlatHeight, kMaxFlatHeight]
    std::size_t minKept = 1;           // features (curves and areas) the vectors must give, or the import fails
    bool allowEmpty = false;           // accept fewer than minKept (an explicit choice)
    DemStorage demStorage = DemStorage::Auto;
    // Where a lod DEM is written (a GeoPackage of its own, beside the output: the caller's
    // uniqueDemLodPath(out), io/dem_import_lod.h); required when the DEM is stored as lod, and must
    // not exist (ImportError: importScene never replaces a file). importScene removes the file it
    // wrote when it fails; after it succeeds the caller removes it (SceneDocument::demLod's path)
    // once the document is saved.
    std::string demLodPath;
    // Vectors out of core (importSceneToFile only; --vector-budget, MiB; 0: in memory). The features
    // are written to a spill file (io/vector_spill.h) as they are read, and the scene is built and
    // written a square part at a time (io/network_builder.h: PartCut; io/scene_file.h:
    // saveSceneInParts), the parts made small enough that one part's features fit the budget: so
    // the memory the vectors take follows the densest part, not the extract. What this changes in
    // the scene: a way crossing a part border is two curves joined at a node there, fitted apart.
    double vectorBudgetMiB = 0.0;
    // The parts, 2^level a side (--vector-part-level, 0 to VectorSpill::kGridLevel); -1: the
    // coarsest level whose densest part fits vectorBudgetMiB. Either makes the import out of core.
    int vectorPartLevel = -1;
};

inline constexpr double kMaxFitTolerance = 100.0;  // metres
inline constexpr double kMinDemCell = 0.1;         // metres
inline constexpr double kMaxDemCell = 10000.0;     // metres
inline constexpr double kMaxMargin = 100000.0;     // metres
inline constexpr double kMinFlatHeight = -500.0;   // metres (the Dead Sea shore is at -430)
inline constexpr double kMaxFlatHeight = 9000.0;   // metres
// The largest |scale - 1| of the transverse Mercator frame over the scene (about 570 km across on
// the central meridian's sides): beyond it distances and areas drift by more than 0.1 %.
inline constexpr double kMaxScaleError = 1e-3;
// Cell of the flat ground made when no DEM is given (metres): heights are constant, any cell works.
inline constexpr double kFlatGroundCell = 100.0;
// What a part's features take in memory while it is built (fitting, topology, the part's model and
// its rows), per byte they take in the spill file: measured on Andorra (see importSceneToFile).
inline constexpr double kVectorMemoryPerSpillByte = 12.0;
inline constexpr double kMaxVectorBudgetMiB = 1 << 20;
inline constexpr std::size_t kMaxListedProblems = 100000;
inline constexpr int kMaxVectorPartLevel = 8;  // 256 x 256 parts (VectorSpill::kGridLevel)

struct ImportReport {
    DemImportReport dem;
    // A lod DEM (dem.storage == "lod"): the tree written to ImportOptions::demLodPath.
    DemLodLayout demLodLayout;
    std::uint64_t demLodTiles = 0, demLodBytes = 0;
    int demLodCoarseLevel = 0;  // the level held in SceneDocument::dem
    bool flatGround = false;  // no DEM given: flat at flatHeight
    double flatHeight = 0.0;
    NetworkReport network;
    std::size_t featuresRead = 0, unmapped = 0, linesKept = 0, areasKept = 0;
    std::size_t duplicateOsmIds = 0;
    std::vector<FeatureProblem> problems;  // reading and building
    // An import out of core lists the first kMaxListedProblems and counts the others by reason.
    std::map<std::string, std::size_t> problemsNotListed;
    std::size_t problemCount() const;
    std::vector<std::string> warnings;     // things the user must know (the scene beyond the DEM...)
    double largestScaleError = 0.0;
    double riverNodesBelowSurroundings = 0.0;  // fraction of river nodes lower than the median around them
    std::size_t riverNodesChecked = 0;
    Box extent;
    double lon0 = 0.0, lat0 = 0.0;
    // An import out of core: the parts (2^level a side; -1 for an import in memory), those with
    // features, the border nodes joined, the features and bytes spilled, the densest part's bytes.
    int vectorPartLevel = -1;
    std::size_t vectorParts = 0, borderNodes = 0;
    std::uint64_t spilledFeatures = 0, spilledBytes = 0, densestPartBytes = 0;
    double ms = 0.0;
    nlohmann::json json() const;
};

// Checks the knobs of `options` (ImportError with the valid range).
void checkImportOptions(const ImportOptions& options);

// With a lod DEM (see DemStorage) the document's demLod reads ImportOptions::demLodPath and its dem
// is the tree's level levelAtMost(layout, kInMemoryDemSide) (the river check and the report use it).
// Throws ImportError (see the header), DemImportError, VectorImportError, MappingError or
// ValidationError; per-feature problems go to the report.
SceneDocument importScene(const ImportOptions& options, ImportReport& report, Progress* progress = nullptr);

// `lacet import`: importScene then saveScene to `out` (io/scene_file.h), or, when options ask for
// vectors out of core, the same made and written a part at a time, with its spill file beside `out`
// (removed at the end, and by the next import beside `out` when this one was killed). A lod DEM's
// file (ImportOptions::demLodPath) is removed once the scene is saved or the import failed. Refuses
// a budget smaller than the densest part at the finest level with the figures. Throws as
// importScene and saveScene do.
void importSceneToFile(const ImportOptions& options, const std::string& out, ImportReport& report, Progress* progress = nullptr);

}  // namespace lacet
