#pragma once
// Topology and splines (§4.1) from imported GIS features: projected lines become the nodes and
// curves of their layers, polygons the areas.
//
// Lines (roads, rivers): a node wherever a way ends and wherever ways share a point (an OSM node
// shared by two ways, or a way passing twice through one), exactly; ways are split at nodes; then
// chains through nodes where exactly two pieces of the same rule and flags meet end to end are
// merged into one curve (for rivers only in the flow direction). Each curve is a spline fitted
// to its points within the tolerance (io/spline_fit.h) whose ends are its nodes, exactly.
// Polygons (lakes, fields, forests, river areas): each ring becomes one closed curve from a node to
// itself, fitted the same way; the outer ring and the holes make the area's loops. An area of a
// rivers layer gets as its axial curve (its elevation profile, §5.2) the river of the layer with
// the most length inside it, or none when no river runs through it (then it is flat at its lowest
// border height, as a lake); its ring curves are its border, not rivers (their `areas` say so). Borders shared between
// neighbouring polygons are not merged into shared curves (each polygon keeps its own).
// One feature, one curve: a way segment (two consecutive points) already imported in the layer is
// not imported again: a feature all of whose segments were seen (the same way in two files, an
// OSM route or waterway relation over its member ways) is skipped, one that partly overlaps keeps
// its new stretches; ways of single-line features are taken before parts of multi-line ones, so
// the ways keep their own attributes. An area whose rings repeat an earlier area's is skipped.
// All are counted and reported.
// Features with a point outside the DEM are skipped and reported. The attributes the mapping keeps
// (names, bridge, tunnel, layer...) go to `attributes`, per curve or area; chains merge only
// where they agree.

#include <functional>

#include "io/document.h"
#include "io/scene_frame.h"
#include "io/spline_fit.h"
#include "io/vector_import.h"
#include "model/progress.h"

namespace lacet {

struct LayerSummary {
    std::string name;
    LayerKind kind = LayerKind::Other;
    std::map<std::uint16_t, std::size_t> curvesByClass;  // roads and rivers
    std::map<std::uint16_t, std::size_t> areasByClass;   // area layers
    std::size_t nodes = 0, junctions = 0, bridges = 0, tunnels = 0, holes = 0;
    std::size_t inputPoints = 0, outputVertices = 0, onCurveVertices = 0;
    double maxFitError = 0.0;  // metres: the largest curve's Hausdorff distance to its source (SplineFitResult)
};

struct NetworkReport {
    std::vector<LayerSummary> layers;
    std::size_t inputPoints = 0;     // distinct points of the kept features
    std::size_t outputVertices = 0;  // on-curve and control vertices of the fitted curves
    std::size_t onCurveVertices = 0; // of which on-curve
    double maxFitError = 0.0;        // metres, measured
    std::size_t chainsMerged = 0;
    std::size_t duplicateLines = 0;          // skipped: every segment imported before
    std::size_t duplicateLineSegments = 0;   // removed from lines that partly overlap earlier ones
    std::size_t duplicateAreas = 0;          // skipped: the same rings as an earlier area
    std::size_t riverAreas = 0;              // areas of rivers layers (a large river's water)
    std::size_t riverAreasWithAxial = 0;     // of which with an axial curve (the others are flat, as lakes)
    std::vector<FeatureProblem> problems;
};

// One square part of a scene built alone (an import out of core, io/scene_import.h): the scene's
// square cut into `side` x `side` parts (row-major, y up), of which `part` is built. Each point
// belongs to the part its square holds (the last row and column hold their far edges). A way is cut
// where a segment has its two points in different parts: the segment goes to the lower-numbered
// of the two (so a segment, in either direction, always goes to one part, and duplicates are found
// there), and each of its points becomes a node in every part that has a curve through it, where it
// is a border node (PartCut::borderNodes). Nodes of the pieces never merge into chains through a
// border node, so the parts agree on them: the whole scene's junctions are all kept, exactly, and
// a chain through a part border stays two curves joined at a node. An area goes whole to the part
// of its outer ring's least point (by x, then y: the same part whatever the ring's start); a river
// area chooses its axial curve among that part's rivers.
// "outside the DEM" is reported by the part of a feature's first point only.
struct PartGrid {
    Box square;     // the scene's square (extent), scene metres
    int side = 1;   // parts per side
    int partOf(Vec2 p) const;
    Box partBox(int part) const;
};
struct PartCut {
    PartGrid grid;
    int part = 0;
    // Out: per layer, the nodes (layer ids) at border points: the same point's node in another
    // part is the same node of the scene (saveSceneInParts joins them, io/scene_file.h).
    std::vector<std::vector<ElementId>> borderNodes;
};

// `insideDem(lonLat)`: whether the DEM covers a point (null: no DEM check). With `cut`, the part
// cut->part of the features (see PartCut); `data` must hold at least every feature with a point in
// that part (more are ignored).
Scene buildScene(const VectorData& data, const FeatureMapping& mapping, const SceneFrame& frame, const Box& extent,
                 const std::function<bool(glm::dvec2)>& insideDem, const SplineFitParams& fit, NetworkReport& report,
                 std::vector<ElementAttribute>* attributes = nullptr, Progress* progress = nullptr, PartCut* cut = nullptr);

}  // namespace lacet
