#pragma once
// `lacet import`: a DEM and GIS vector files into one georeferenced scene (§4.1) with its DEM:
// features read and mapped (io/vector_import.h), a transverse Mercator frame centred on them
// (io/scene_frame.h), the DEM resampled onto the scene's grid (io/dem_import.h), topology and
// splines (io/network_builder.h), the scene validated. The report says what came in, what was
// skipped and why, the fit error and the vertex reduction, voids, the scale error and the time.

#include <functional>

#include <nlohmann/json.hpp>

#include "io/dem_import.h"
#include "io/network_builder.h"
#include "io/scene_file.h"

namespace lacet {

struct ImportOptions {
    std::string dem;
    std::vector<std::string> vectors;
    std::string mapping;           // empty: the default OSM mapping
    double fitTolerance = 0.5;     // metres (SplineFitParams::tolerance)
    double demCell = 0.0;          // metres; 0: the source's own resolution
    double margin = 200.0;         // metres of scene around the features
};

struct ImportReport {
    DemImportReport dem;
    NetworkReport network;
    std::size_t featuresRead = 0, unmapped = 0, linesKept = 0, areasKept = 0;
    std::vector<FeatureProblem> problems;  // reading and building
    double largestScaleError = 0.0;
    double riverNodesBelowSurroundings = 0.0;  // fraction of river nodes lower than the median around them
    std::size_t riverNodesChecked = 0;
    Box extent;
    double lon0 = 0.0, lat0 = 0.0;
    double ms = 0.0;
    nlohmann::json json() const;
};

// Throws std::invalid_argument for bad options, DemImportError, VectorImportError, MappingError
// or ValidationError (file-level problems); per-feature problems go to the report.
SceneDocument importScene(const ImportOptions& options, ImportReport& report,
                          const std::function<void(const std::string& stage)>& progress = {});

}  // namespace lacet
