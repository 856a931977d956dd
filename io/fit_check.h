#pragma once
// `lacet check fit`: how far a scene's curves and area borders lie from the GIS features they were
// imported from, measured independently of the import's own bookkeeping. The source files are
// read again with the same mapping (io/vector_import.h) and projected with the scene's
// georeference; then, per layer,
//   - curve to source: the largest distance from any point of any curve of the layer to the
//     nearest source segment of the layer (every Bezier piece, densely, model/hausdorff.h);
//   - source to curve: the largest distance from any point of any source feature of the layer to
//     the nearest curve of the layer.
// Both are Hausdorff measures within `precision`; DESIGN.md invariant 6 asks both to stay within
// the import's fit tolerance. Source features with a point outside the scene's DEM are not
// measured (the import skips them) and are counted; features the import skipped for a reason
// (an invalid polygon, say) show up as sources far from every curve and are listed by name.
//
// Units: metres (scene CRS).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/document.h"
#include "io/vector_import.h"

namespace lacet {

struct FitCheckParams {
    double tolerance = 0.5;   // metres (>= 0): a curve or source feature farther than this is listed
    double precision = 0.01;  // metres (> 0): of the measures
    std::size_t listed = 20;  // at most this many worst curves and sources per layer
};

struct FitCheckItem {
    std::string what;  // "curve 12", "area 3 border", or the source feature (file, layer, id)
    double distance = 0.0;  // metres: proven farther than this (a lower bound)
    Vec2 at{0.0};           // scene metres: where
};

struct FitCheckLayer {
    std::string name;
    std::size_t curves = 0, sourceFeatures = 0, sourceSegments = 0, vertices = 0, onCurveVertices = 0;
    // Metres: bounds of the largest distance each way (true value in [lower, upper]).
    double curveToSourceLower = 0.0, curveToSourceUpper = 0.0;
    double sourceToCurveLower = 0.0, sourceToCurveUpper = 0.0;
    std::size_t curvesOver = 0, sourcesOver = 0;  // proven farther than the tolerance
    std::vector<FitCheckItem> worstCurves, worstSources;
};

struct FitCheckReport {
    FitCheckParams params;
    std::vector<FitCheckLayer> layers;
    std::size_t sourcesOutside = 0;  // not measured: a point outside the scene's DEM
    double ms = 0.0;
    // Nothing proven farther than the tolerance either way, and nothing undecided (an upper
    // bound beyond tolerance + precision). A layer with curves and no source fails.
    bool passed() const;
    nlohmann::json json() const;
};

// Throws std::invalid_argument when the scene has no georeference (a synthetic scene) or the
// params are out of range. Layers are matched by name; a source layer the scene lacks is skipped.
FitCheckReport checkFit(const SceneDocument& doc, const VectorData& sources, const FeatureMapping& mapping,
                        const FitCheckParams& params);

}  // namespace lacet
