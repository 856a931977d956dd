#pragma once
// The part of a scene file that a region's tiles need (§7, vector data out of core): the curves and
// areas found by bounding box through the R-trees of the feature tables (io/scene_features.h), and
// what their tiles depend on, so that the tiles of any quad inside the region are the same, bit for
// bit, as with the whole scene loaded. The rows read, the memory and the work on them follow the
// region, not the scene (see below for what does not yet).
//
// Each layer holds what was read and nothing else, in the file's order: its elements have ids from 0
// and Layer::sceneIds gives each one's id in the file (model/graph.h), which the digests and the
// appearance's seeds use. Such a document is never saved (saveScene refuses it). What is loaded:
//   - every curve and area whose feature box meets the quads of the level that meet the region
//     (closed boxes: a quad touching the region's border counts), dilated by the reach: the largest clipping margin
//     (RefineParams::curveMargin, areaMargin) of the file's curves and areas at the level's quad
//     size, plus the features' tolerance; an area brings its loop and axial curves;
//     the reach also holds the largest roundabout radius (a ring reaches that far beyond its roads);
//   - at both end nodes of those curves, every curve there (roundabouts, junctions, stop lines);
//   - for every road curve loaded, the river curves and areas whose boxes meet its box (the graph
//     step's bridges; for an imported bridge, kBridge, the roads too);
//   - for every river curve loaded, every river curve upstream of its end nodes (a river node is no
//     higher than any node upstream of it);
//   - for every river area loaded with an axial curve, the river its water follows on through the
//     area (raster/elevation_producer.h: axialRiver): every curve at the nodes of that walk and the
//     areas those curves border, and so on for those areas;
//   - the end nodes of every curve loaded, their lists of curves and the curves' lists of areas
//     keeping what was loaded; the attributes of what was loaded.
// The DEM is opened as loadScene opens it. Each row read is checked as loadScene checks it and the
// partial model is validated; the whole file's checksum is not (it needs every row).
//
// A file without the feature index (written before it) is loaded whole (stats.wholeScene) and its
// checksum checked (when the DEM is read: the checksum covers it), and, written before their
// indexes, its lacet_attributes and the ring nodes of lacet_nodes are scanned whole.
//
// Memory: SceneRegionOptions::budgetMiB bounds the vector data read: model/graph.h's memoryBytes of
// the layers and of each element read with its file id, summed as it is read, which is what the
// document returned holds (SceneRegionStats::bytes). Once the sum passes the budget the read stops
// and throws SceneBudgetError naming the file, the budget and what had been read, so a read far
// over its budget stops early. Not counted, so the peak while reading is higher: the reader's index
// of what it names and reads (about 100 bytes an element), the placeholders of elements named but
// not read, the element vectors' spare room while they grow (up to as much again), and the
// attributes. A file without the feature index is read whole and refused after.

#include <limits>
#include <string>
#include <vector>

#include "io/document.h"
#include "io/scene_file.h"
#include "io/scene_overlay.h"
#include "model/clip_and_refine.h"

namespace lacet {

// A region read refused by its memory budget (SceneRegionOptions::budgetMiB).
class SceneBudgetError : public SceneFileError {
public:
    using SceneFileError::SceneFileError;
};

struct SceneRegionStats {
    bool wholeScene = false;  // the file has no feature index: everything was loaded
    double reach = 0.0;       // m around the region's quads searched through the R-trees
    std::size_t found = 0;    // curves and areas found in the region through the R-trees
    std::size_t nodes = 0, curves = 0, areas = 0;                 // loaded
    std::size_t sceneNodes = 0, sceneCurves = 0, sceneAreas = 0;  // ids of the whole scene (max id + 1)
    std::string checksum;  // the whole file's stored checksum (loadScene checks it; a region load cannot)
    std::size_t bytes = 0;  // the loaded document's vector data in memory (model/graph.h: memoryBytes)
    double tolerance = 0.0;  // the feature tables' (io/scene_features.h), for their boxes
};

// What a region load starts from. By default every curve and area the R-trees find; with
// `elevationOnly`, only what the elevation producer draws (raster/elevation_producer.h): road and
// river curves at least `minCurveWidth` metres wide (two elevation samples of the deepest quads
// that will be made) and not whole bridges or tunnels, and lake and river areas; what those depend
// on is loaded as always. For tiles whose appearance is not made from vector data (the levels of a
// pyramid above its vector levels, pyramid/pyramid_build.h), whose elevation is then the same as
// with the whole scene.
struct SceneRegionOptions {
    bool elevationOnly = false;
    double minCurveWidth = 0.0;  // m, >= 0
    bool dem = true;  // open the DEM as loadScene does; false: none (the caller has it, e.g. for many regions)
    // SQLite's quick_check of every page of the file, as loadScene does: O(file) (99 s for a cold
    // 3.6 GB file), which a read of a small part must not cost, so off by default: SQLite still
    // checks each page it reads, and every row read is checked. A reader of most of the file (the
    // pyramid build, pyramid/pyramid_build.h) asks for it on its first read.
    bool wholeFileCheck = false;
    // MiB of vector data the read may hold (> 0; infinity: no bound); past it, SceneBudgetError.
    double budgetMiB = std::numeric_limits<double>::infinity();
    // Edits not saved (io/scene_overlay.h), read over the file: the region gets what it would get
    // from the file saved with them (or more). Must outlive the call.
    const SceneOverlay* overlay = nullptr;
    // Nodes (their ids in the file, with the overlay) loaded besides what the region finds, each
    // with every curve at it as a curve found is: a node without curves lies in no feature's box
    // (an edit that joins a curve to it reads it so; editor/lazy_edits.h). SceneFileError for a
    // node the file does not hold.
    std::vector<ElementRef> nodes{};
};

// Loads what the tiles of the quads of `level` (or deeper) that meet `region` need, clipped with
// `params` (above). Throws SceneFileError naming the file and the reason, std::invalid_argument for a
// level out of 0..30, an empty region or a bad filter.
SceneDocument loadSceneRegion(const std::string& path, const Box& region, const RefineParams& params, int level,
                              SceneRegionStats* stats = nullptr, const SceneRegionOptions& filter = {});
// The same over a connection kept open (io/scene_file.h: many reads of one file by one thread).
SceneDocument loadSceneRegion(SceneFileConnection& connection, const Box& region, const RefineParams& params, int level,
                              SceneRegionStats* stats = nullptr, const SceneRegionOptions& filter = {});

// Each layer's count of ids of `kind` in the scene file of `connection` (its largest id + 1,
// through the (layer, id) index; deleted elements count). Throws SceneFileError naming the file.
std::vector<std::size_t> loadSceneIdCounts(SceneFileConnection& connection, ElementKind kind);

// Where element `ref` (its id in the file) of the scene file at `path` lies, read with `overlay`
// (nullptr: none): a node's point, the box of a curve's vertices, of an area's loops' vertices.
// Throws SceneFileError naming the file and the element when the file has no such element.
Box loadSceneElementBox(const std::string& path, const ElementRef& ref, const SceneOverlay* overlay = nullptr);
Box loadSceneElementBox(SceneFileConnection& connection, const ElementRef& ref, const SceneOverlay* overlay = nullptr);

// The curves and areas (their ids in the file) of the layers of kind `kind` in the scene file of
// `connection` whose feature boxes meet `box` (closed), read with `overlay` (nullptr: none): what
// loadSceneRegion's searches through the R-trees find there. Throws SceneFileError naming the file
// (one without the feature index among the reasons).
std::vector<ElementRef> loadSceneFeaturesIn(SceneFileConnection& connection, const Box& box, LayerKind kind,
                                            const SceneOverlay* overlay = nullptr);

// The extent of the scene file at `path` (its root quad), read from its metadata alone. Throws
// SceneFileError naming the file.
Box loadSceneExtent(const std::string& path);

// The extent and the size of the scene file at `path`: its curves and areas, counted by their ids
// (each layer's largest + 1, through the (layer, id) index: deleted ones count, no table is
// scanned). Throws SceneFileError naming the file.
struct SceneOutline {
    Box extent;
    std::size_t elements = 0;  // curves and areas
    std::string checksum;      // the stored checksum (io/scene_checksum.h, in the file's format)
};
SceneOutline loadSceneOutline(const std::string& path);

}  // namespace lacet
