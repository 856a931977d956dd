#pragma once
// The steps of `lacet import` (io/scene_import.h) that the import in memory (scene_import.cpp) and
// the one out of core (scene_import_parts.cpp) share.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "io/dem_import.h"
#include "io/dem_import_lod.h"
#include "io/feature_mapping.h"
#include "io/scene_frame.h"
#include "io/scene_import.h"
#include "io/vector_import.h"

namespace lacet::import_detail {

// The lon/lat box of the features the DEM covers (all of them on flat ground): the scene's frame.
struct FeatureBounds {
    std::function<bool(glm::dvec2)> insideDem;  // null: no DEM
    Box box{Vec2(1e300), Vec2(-1e300)};
    // Grows the box by `pts` when the DEM covers each of them.
    void grow(const std::vector<glm::dvec2>& pts);
    bool any() const { return box.min.x <= box.max.x; }
};

struct ImportStart {
    FeatureMapping mapping;
    std::optional<DemSourceInfo> demInfo;
    FeatureBounds bounds;  // its insideDem reads demInfo: the struct stays where it is made
    ImportStart() = default;
    ImportStart(const ImportStart&) = delete;
    ImportStart& operator=(const ImportStart&) = delete;
};

// Checks the options, reads the mapping and opens the DEM's files, into `start`.
void startImport(const ImportOptions& o, ImportReport& report, ImportStart& start);
// Reads every vector file into `data` (or its sinks); ImportError when a file could not be read whole.
void readAllVectors(const ImportOptions& o, const FeatureMapping& mapping, VectorData& data, ImportReport& report, Progress* progress);
// The scene's frame and extent from start.bounds (or the DEM's coverage), checked, and its DEM read
// into doc (a lod tree's file named in lodFile once written) with its georeference.
SceneFrame frameAndDem(const ImportOptions& o, const ImportStart& start, const VectorData& data, ImportReport& report, SceneDocument& doc,
                       RemoveFileOnExit& lodFile, Progress* progress);
// The curves and areas an import counts as kept (ImportOptions::minKept), and the check.
std::size_t keptElements(const Scene& scene);
void checkKept(const ImportOptions& o, std::size_t kept, const ImportReport& report);
// The river check of the report: nodes below the median of their surroundings, summed over parts.
void countRiverNodes(const Scene& s, const Dem& dem, std::size_t& below, std::size_t& checked);
void setRiverCheck(ImportReport& r, std::size_t below, std::size_t checked);

}  // namespace lacet::import_detail
