#include "io/scene_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include "io/dem_import_lod.h"
#include "io/scene_import_internal.h"
#include "model/validate.h"

namespace lacet {
namespace {

std::string numberText(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string joined(const std::vector<std::string>& paths) {
    std::string out;
    for (const std::string& p : paths) out += (out.empty() ? "" : ", ") + p;
    return out;
}

std::map<std::string, std::size_t> countByReason(const std::vector<FeatureProblem>& problems) {
    std::map<std::string, std::size_t> out;
    for (const FeatureProblem& p : problems) ++out[p.reason];
    return out;
}

// "3 zero-length way (fewer than 2 distinct points), 1 outside the DEM": the reasons, counted.
std::string reasonsText(const std::vector<FeatureProblem>& problems) {
    std::ostringstream s;
    for (const auto& [reason, n] : countByReason(problems)) s << (s.tellp() > 0 ? ", " : "") << n << " " << reason;
    return s.str();
}

std::string boxText(const Box& b) {
    std::ostringstream s;
    s << "(" << b.min.x << ", " << b.min.y << ") - (" << b.max.x << ", " << b.max.y << ")";
    return s.str();
}

// A lon/lat box's image in the frame (unshifted metres), sampled along its border: `outer` bounds
// it, `inner` is the axis-aligned rectangle inside it (the box's edges curve under the projection).
void projectBox(const SceneFrame& frame, const Box& lonLat, Box& outer, Box& inner) {
    constexpr int kSamples = 32;
    outer = {{1e300, 1e300}, {-1e300, -1e300}};
    inner = outer;
    inner.min = Vec2(-1e300);
    inner.max = Vec2(1e300);
    for (int k = 0; k <= kSamples; ++k) {
        const double f = double(k) / kSamples;
        const Vec2 west = frame.forward({lonLat.min.x, lonLat.min.y + f * lonLat.size().y});
        const Vec2 east = frame.forward({lonLat.max.x, lonLat.min.y + f * lonLat.size().y});
        const Vec2 south = frame.forward({lonLat.min.x + f * lonLat.size().x, lonLat.min.y});
        const Vec2 north = frame.forward({lonLat.min.x + f * lonLat.size().x, lonLat.max.y});
        for (const Vec2 q : {west, east, south, north}) outer = {glm::min(outer.min, q), glm::max(outer.max, q)};
        inner.min.x = std::max(inner.min.x, west.x);
        inner.max.x = std::min(inner.max.x, east.x);
        inner.min.y = std::max(inner.min.y, south.y);
        inner.max.y = std::min(inner.max.y, north.y);
    }
}

// The scene's square (unshifted frame metres). With features: around them by `margin`, moved
// along each axis to lie inside the DEM's coverage when its side fits there (still holding the
// features). Without: the largest square inside the DEM's coverage.
Box sceneSquare(const SceneFrame& frame, const std::optional<Box>& features, const std::optional<Box>& demLonLat, double margin) {
    Box demOuter, demInner;
    if (demLonLat) projectBox(frame, *demLonLat, demOuter, demInner);
    if (!features) {
        const double side = std::floor(std::max(std::min(demInner.size().x, demInner.size().y), 1.0));
        const Vec2 c = demInner.center();
        return {c - side / 2.0, c + side / 2.0};
    }
    Box f, unused;
    projectBox(frame, *features, f, unused);
    const Box wanted = f.dilated(margin);
    const double side = std::ceil(std::max({wanted.size().x, wanted.size().y, 1.0}));
    Vec2 min = wanted.center() - side / 2.0;
    if (demLonLat)
        for (int axis = 0; axis < 2; ++axis) {
            // The square must hold the features and their margin: min in [wanted.max - side,
            // wanted.min]; inside the DEM:
            // min in [inner.min, inner.max - side]. Take the nearest to centred in both, if any.
            const double lo = std::max(wanted.max[axis] - side, demInner.min[axis]);
            const double hi = std::min(wanted.min[axis], demInner.max[axis] - side);
            if (lo <= hi) min[axis] = std::clamp(min[axis], lo, hi);
        }
    return {min, min + side};
}

}  // namespace

const char* toString(DemStorage s) {
    switch (s) {
    case DemStorage::Auto: return "auto";
    case DemStorage::Grid: return "grid";
    case DemStorage::Lod: return "lod";
    }
    return "?";
}

DemStorage demStorageFromString(const std::string& s) {
    for (DemStorage d : {DemStorage::Auto, DemStorage::Grid, DemStorage::Lod})
        if (s == toString(d)) return d;
    throw ImportError("the DEM storage (--dem-storage) must be auto, grid or lod, not '" + s + "'");
}

void checkImportOptions(const ImportOptions& o) {
    auto range = [](double v, double lo, double hi, const char* what) {
        if (!(v >= lo && v <= hi))  // NaN fails too
            throw ImportError(std::string(what) + " must be in [" + numberText(lo) + ", " + numberText(hi) + "], not " + numberText(v));
    };
    range(o.fitTolerance, 0.0, kMaxFitTolerance, "the fit tolerance (--tolerance, metres)");
    if (o.demCell != 0.0) range(o.demCell, kMinDemCell, kMaxDemCell, "the DEM cell (--dem-cell, metres; 0: the source's)");
    range(o.margin, 0.0, kMaxMargin, "the margin (metres)");
    range(o.flatHeight, kMinFlatHeight, kMaxFlatHeight, "the flat ground's height (--flat-height, metres)");
    range(o.vectorBudgetMiB, 0.0, kMaxVectorBudgetMiB, "the vector budget (--vector-budget, MiB; 0: in memory)");
    if (o.vectorPartLevel < -1 || o.vectorPartLevel > kMaxVectorPartLevel)
        throw ImportError("the part level (--vector-part-level) must be in [0, " + std::to_string(kMaxVectorPartLevel) + "], not " +
                          std::to_string(o.vectorPartLevel));
    if (o.dem.empty() && o.vectors.empty()) throw ImportError("nothing to import: give a DEM (--dem), vector files (--vectors), or both");
}

namespace import_detail {

void FeatureBounds::grow(const std::vector<glm::dvec2>& pts) {
    for (const glm::dvec2& p : pts)
        if (insideDem && !insideDem(p)) return;
    for (const glm::dvec2& p : pts) box = {glm::min(box.min, p), glm::max(box.max, p)};
}

void startImport(const ImportOptions& o, ImportReport& report, ImportStart& start) {
    report = {};
    checkImportOptions(o);
    start.mapping = o.mapping.empty() ? defaultMapping() : loadMapping(o.mapping);
    // The DEM is checked (every file opened, CRS compared) before the vectors are read.
    if (!o.dem.empty()) start.demInfo = demSourceInfo(o.dem);
    if (start.demInfo) start.bounds.insideDem = [info = &*start.demInfo](glm::dvec2 p) { return info->covers(p); };
}

void readAllVectors(const ImportOptions& o, const FeatureMapping& mapping, VectorData& data, ImportReport& report, Progress* progress) {
    data.dedupOsmIds = o.vectors.size() > 1;
    for (std::size_t i = 0; i < o.vectors.size(); ++i) {
        progressBegin(progress, "reading " + o.vectors[i], 0, "features");
        const std::size_t before = data.featuresRead;
        readVectors(o.vectors[i], mapping, data);
        progressAdvance(progress, data.featuresRead - before);
        progressEnd(progress);
    }
    if (!data.fileErrors.empty()) {
        std::string why;
        for (const std::string& e : data.fileErrors) why += "\n  " + e;
        throw ImportError("cannot import: " + std::to_string(data.fileErrors.size()) + " input" +
                          (data.fileErrors.size() > 1 ? "s" : "") + " could not be read whole:" + why);
    }
    report.featuresRead = data.featuresRead;
    report.unmapped = data.unmapped;
    report.duplicateOsmIds = data.duplicateOsmIds;
    report.problems = data.problems;
    report.problemsNotListed = data.problemsNotListed;
    report.linesKept = data.linesKept;
    report.areasKept = data.areasKept;
}

SceneFrame frameAndDem(const ImportOptions& o, const ImportStart& start, const VectorData& data, ImportReport& report, SceneDocument& doc,
                       RemoveFileOnExit& lodFile, Progress* progress) {
    const std::optional<DemSourceInfo>& demInfo = start.demInfo;
    const Box& bounds = start.bounds.box;
    const bool anyFeature = start.bounds.any();
    if (!anyFeature && !o.vectors.empty() && !o.allowEmpty) {
        const std::string read = std::to_string(data.featuresRead) + " features read, " + std::to_string(data.unmapped) + " not mapped";
        if (data.linesKept + data.areasKept == 0)
            throw ImportError("nothing to import from " + joined(o.vectors) + ": no feature could be read as a line or an area (" + read +
                              (data.problems.empty() ? "" : "; problems: " + reasonsText(data.problems)) + "); --allow-empty accepts it");
        throw ImportError("no feature of " + joined(o.vectors) + " lies inside the DEM " + joined(o.dem) + " (" + read +
                          "): nothing to keep; --allow-empty accepts it");
    }
    if (!anyFeature && !demInfo) throw ImportError("no feature to import and no DEM: the scene would have no extent");
    const Box centreBox = anyFeature ? bounds : demInfo->lonLat;
    report.lon0 = centreBox.center().x;
    report.lat0 = centreBox.center().y;
    SceneFrame frame(report.lon0, report.lat0);
    const Box square = sceneSquare(frame, anyFeature ? std::optional<Box>(bounds) : std::nullopt,
                                   demInfo ? std::optional<Box>(demInfo->lonLat) : std::nullopt, o.margin);
    frame.setOriginShift(-square.min);
    report.extent = {{0.0, 0.0}, square.size()};
    report.largestScaleError = frame.largestScaleError(report.extent);
    if (!(report.largestScaleError <= kMaxScaleError))
        throw ImportError("the scene of " + joined(anyFeature ? o.vectors : o.dem) + " would be " +
                          numberText(report.extent.size().x / 1000.0) + " km across: one transverse Mercator frame would distort it by " +
                          numberText(report.largestScaleError * 100.0) + " % (the limit is " + numberText(kMaxScaleError * 100.0) +
                          " %); import a smaller region");

    if (demInfo) {
        const double cell = o.demCell > 0.0 ? o.demCell : std::max(1.0, std::min(demInfo->resolution.x, demInfo->resolution.y));
        const double side = std::max(report.extent.size().x, report.extent.size().y) / cell;
        const bool lod = o.demStorage == DemStorage::Lod || (o.demStorage == DemStorage::Auto && std::lround(side) > kInMemoryDemSide);
        if (lod) {
            if (o.demLodPath.empty()) throw ImportError("a DEM stored as lod needs a file to write it to (ImportOptions::demLodPath)");
            std::error_code ec;
            if (std::filesystem::symlink_status(o.demLodPath, ec).type() != std::filesystem::file_type::not_found)
                throw ImportError(o.demLodPath + ": exists: the DEM tree's file must be a new one (uniqueDemLodPath), not replaced");
            // importDemLod removes the file when it fails; this, when a later step does.
            DemLodOutput out = importDemLod(*demInfo, frame, report.extent, cell, o.demLodPath, report.dem, {}, progress);
            lodFile.path = o.demLodPath;
            report.demLodLayout = out.layout;
            report.demLodTiles = out.tiles;
            report.demLodBytes = out.bytes;
            report.demLodCoarseLevel = out.coarseLevel;
            doc.dem = std::move(out.coarse);
            doc.demLod = std::make_shared<const DemLodFile>(o.demLodPath);
        } else {
            progressBegin(progress, "reading the DEM", demInfo->files.size(), "files");
            doc.dem = importDem(*demInfo, frame, report.extent, cell, report.dem);
            progressAdvance(progress, demInfo->files.size());
            progressEnd(progress);
        }
        if (report.dem.outsideFraction > 0.0)
            report.warnings.push_back(numberText(report.dem.outsideFraction * 100.0) + " % of the scene lies outside the DEM (which covers " +
                                      boxText(report.dem.demExtent) + " m of " + boxText(report.extent) +
                                      " m): no heights are stored there; the ground continues the DEM's border and is shown as void");
        if (report.dem.uncoveredFilled > 0)
            report.warnings.push_back(std::to_string(report.dem.uncoveredFilled) +
                                      " DEM cells inside the DEM's extent have no data (a missing tile, or the border's curvature) and were "
                                      "filled from their neighbours");
    } else {
        report.flatGround = true;
        report.flatHeight = o.flatHeight;
        const int n = std::max(2, int(std::ceil(report.extent.size().x / kFlatGroundCell)));
        doc.dem.emplace(report.extent, n, n, std::vector<float>(std::size_t(n) * std::size_t(n), float(o.flatHeight)));
        report.warnings.push_back("no DEM: flat ground at " + numberText(o.flatHeight) + " m");
    }
    if (o.vectors.empty()) report.warnings.push_back("no vector files: a DEM-only scene");
    doc.georeference = frame.georeference();
    return frame;
}

std::size_t keptElements(const Scene& scene) {
    std::size_t kept = 0;
    for (const Layer& l : scene.layers) {
        for (const Curve& c : l.curves) kept += c.alive && c.areas.empty() && l.kind != LayerKind::Fields && l.kind != LayerKind::Forests &&
                                               l.kind != LayerKind::Lakes && l.kind != LayerKind::Other;
        for (const Area& a : l.areas) kept += a.alive;
    }
    return kept;
}

void checkKept(const ImportOptions& o, std::size_t kept, const ImportReport& report) {
    if (!o.vectors.empty() && kept < o.minKept && !o.allowEmpty)
        throw ImportError(joined(o.vectors) + " gave " + std::to_string(kept) + " curves and areas, fewer than " + std::to_string(o.minKept) +
                          " (" + std::to_string(report.featuresRead) + " features read, " + std::to_string(report.unmapped) + " not mapped" +
                          (report.problems.empty() ? "" : "; problems: " + reasonsText(report.problems)) + "); --allow-empty accepts it");
}

// Counts the river nodes whose DEM height is below the median of 16 samples on a 150 m circle.
void countRiverNodes(const Scene& s, const Dem& dem, std::size_t& below, std::size_t& checked) {
    for (const Layer& l : s.layers) {
        if (l.kind != LayerKind::Rivers) continue;
        for (const Node& n : l.nodes) {
            if (!n.alive || n.curves.empty()) continue;
            // A river area's ring node is on its border, not on a river.
            if (std::all_of(n.curves.begin(), n.curves.end(), [&](ElementId c) { return !l.curves[c].areas.empty(); })) continue;
            std::vector<double> ring;
            for (int k = 0; k < 16; ++k) {
                const double a = k * 3.14159265358979 / 8.0;
                ring.push_back(dem.sample(n.p + 150.0 * Vec2(std::cos(a), std::sin(a))));
            }
            std::nth_element(ring.begin(), ring.begin() + 8, ring.end());
            below += dem.sample(n.p) < ring[8];
            ++checked;
        }
    }
}

void setRiverCheck(ImportReport& r, std::size_t below, std::size_t checked) {
    r.riverNodesChecked = checked;
    r.riverNodesBelowSurroundings = checked ? double(below) / double(checked) : 0.0;
}

}  // namespace import_detail

SceneDocument importScene(const ImportOptions& o, ImportReport& report, Progress* progress) {
    using namespace import_detail;
    const auto t0 = std::chrono::steady_clock::now();
    ImportStart start;
    startImport(o, report, start);
    VectorData data;
    readAllVectors(o, start.mapping, data, report, progress);
    // Features inside the DEM's coverage (all of them on flat ground) frame the scene.
    for (const RawLine& l : data.lines) start.bounds.grow(l.lonLat);
    for (const RawArea& a : data.areas)
        for (const auto& ring : a.rings) start.bounds.grow(ring);
    // A lod DEM's file is removed when the import fails after writing it (after the document, which reads it).
    RemoveFileOnExit lodFile;
    SceneDocument doc;
    const SceneFrame frame = frameAndDem(o, start, data, report, doc, lodFile, progress);
    doc.scene = buildScene(data, start.mapping, frame, report.extent, start.bounds.insideDem, SplineFitParams{o.fitTolerance}, report.network,
                           &doc.attributes, progress);
    report.problems.insert(report.problems.end(), report.network.problems.begin(), report.network.problems.end());
    checkKept(o, keptElements(doc.scene), report);
    validateOrThrow(doc.scene);
    std::size_t below = 0, checked = 0;
    countRiverNodes(doc.scene, *doc.dem, below, checked);
    setRiverCheck(report, below, checked);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    lodFile.path.clear();  // the caller's now
    return doc;
}

namespace {

nlohmann::json demJson(const ImportReport& r) {
    const DemImportReport& dem = r.dem;
    nlohmann::json seams = nlohmann::json::array();
    for (const DemSeam& s : dem.seams)
        seams.push_back({{"files", {s.fileA, s.fileB}}, {"points", s.points}, {"largest_step_m", s.largestStep}, {"at_lon_lat", {s.where.x, s.where.y}}});
    nlohmann::json j = {{"path", dem.path},
            {"files", dem.files},
            {"source_size", {dem.sourceWidth, dem.sourceHeight}},
            {"window_read", {dem.windowX, dem.windowY, dem.windowWidth, dem.windowHeight}},
            {"source_resolution_m", {dem.sourceResolution.x, dem.sourceResolution.y}},
            {"voids_filled", dem.voids},
            {"uncovered_cells_filled", dem.uncoveredFilled},
            {"outside_fraction", dem.outsideFraction},
            {"dem_extent_m", {dem.demExtent.min.x, dem.demExtent.min.y, dem.demExtent.max.x, dem.demExtent.max.y}},
            {"cell_m", dem.cellSize},
            {"grid", {dem.width, dem.height}},
            {"height_range_m", {dem.minHeight, dem.maxHeight}},
            {"seams_checked", dem.seamsChecked},
            {"largest_seam_step_m", dem.largestSeamStep},
            {"seams", seams},
            {"files_read", dem.filesRead},
            {"storage", dem.storage},
            {"strips", dem.strips},
            {"peak_strip_samples", dem.peakStripSamples},
            {"voids_beyond_margin", dem.voidsBeyondMargin},
            {"uncovered_beyond_margin", dem.uncoveredBeyondMargin},
            {"ms", dem.ms}};
    if (dem.storage == "lod") {
        const DemLodLayout& l = r.demLodLayout;
        j["lod"] = {{"levels", l.levels}, {"block_side", l.blockSide}, {"grid", {l.width, l.height}}, {"cell_m", l.cell},
                    {"tiles", r.demLodTiles}, {"bytes", r.demLodBytes}, {"in_memory_level", r.demLodCoarseLevel},
                    {"in_memory_grid", {l.levelWidth(r.demLodCoarseLevel), l.levelHeight(r.demLodCoarseLevel)}}};
    }
    return j;
}

}  // namespace

std::size_t ImportReport::problemCount() const {
    std::size_t n = problems.size();
    for (const auto& [reason, count] : problemsNotListed) n += count;
    return n;
}

nlohmann::json ImportReport::json() const {
    std::map<std::string, std::size_t> byReason = countByReason(problems);
    for (const auto& [reason, count] : problemsNotListed) byReason[reason] += count;
    nlohmann::json layers = nlohmann::json::array();
    for (const LayerSummary& l : network.layers) {
        nlohmann::json byClass = nlohmann::json::object(), areas = nlohmann::json::object();
        for (const auto& [c, n] : l.curvesByClass) byClass[std::to_string(c)] = n;
        for (const auto& [c, n] : l.areasByClass) areas[std::to_string(c)] = n;
        layers.push_back({{"name", l.name}, {"kind", std::string(toString(l.kind))}, {"curves_by_class", byClass},
                          {"areas_by_class", areas}, {"nodes", l.nodes}, {"junctions", l.junctions}, {"bridges", l.bridges},
                          {"tunnels", l.tunnels}, {"holes", l.holes},
                          {"fit", {{"input_points", l.inputPoints}, {"output_vertices", l.outputVertices},
                                   {"output_on_curve_vertices", l.onCurveVertices}, {"max_hausdorff_m", l.maxFitError}}}});
    }
    nlohmann::json problemList = nlohmann::json::array();
    for (std::size_t i = 0; i < problems.size() && i < 200; ++i)
        problemList.push_back({{"where", problems[i].source.str()}, {"reason", problems[i].reason}, {"skipped", problems[i].skipped}});
    return {{"features_read", featuresRead},
            {"features_unmapped", unmapped},
            {"lines_read", linesKept},
            {"areas_read", areasKept},
            {"layers", layers},
            {"fit", {{"input_points", network.inputPoints},
                     {"output_vertices", network.outputVertices},
                     {"output_on_curve_vertices", network.onCurveVertices},
                     {"on_curve_reduction", network.inputPoints ? 1.0 - double(network.onCurveVertices) / double(network.inputPoints) : 0.0},
                     {"max_error_m", network.maxFitError},
                     {"max_error_is", "the largest Hausdorff distance between a curve and its source polyline, both ways, measured "
                                      "densely: an upper bound, within 1 cm of it (or the tolerance, which the fit proves, where "
                                      "the measure ran out of evaluations)"},
                     {"chains_merged", network.chainsMerged}}},
            {"duplicates", {{"osm_elements_in_several_files", duplicateOsmIds},
                            {"lines_skipped", network.duplicateLines},
                            {"line_segments_removed", network.duplicateLineSegments},
                            {"areas_skipped", network.duplicateAreas}}},
            {"dem", flatGround ? nlohmann::json{{"flat_ground_m", flatHeight}} : demJson(*this)},
            {"warnings", warnings},
            {"crs", {{"projection", "transverse Mercator (WGS84), scale 1 on the central meridian"}, {"lon0", lon0}, {"lat0", lat0},
                     {"largest_scale_error", largestScaleError}}},
            {"extent_m", {extent.min.x, extent.min.y, extent.max.x, extent.max.y}},
            {"river_areas", {{"count", network.riverAreas},
                             {"with_axial_curve", network.riverAreasWithAxial},
                             {"flat_without_axial_curve", network.riverAreas - network.riverAreasWithAxial}}},
            {"river_nodes_below_surroundings", riverNodesBelowSurroundings},
            {"river_nodes_checked", riverNodesChecked},
            {"problems_by_reason", byReason},
            {"problems", problemList},
            {"vectors_out_of_core", vectorPartLevel < 0 ? nlohmann::json(nullptr)
                                                        : nlohmann::json{{"part_level", vectorPartLevel},
                                                                         {"parts_per_side", 1 << vectorPartLevel},
                                                                         {"parts_with_features", vectorParts},
                                                                         {"border_nodes", borderNodes},
                                                                         {"spilled_features", spilledFeatures},
                                                                         {"spilled_bytes", spilledBytes},
                                                                         {"densest_part_bytes", densestPartBytes}}},
            {"ms", ms}};
}

}  // namespace lacet
