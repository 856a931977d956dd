#include "io/scene_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "model/validate.h"

namespace lacet {
namespace {

// Metres per source sample, from the DEM's bounds and size (for the default grid).
double sourceResolution(const Box& lonLat, int width, int height, double lat) {
    constexpr double kMetresPerDegree = 111320.0;
    const double dx = lonLat.size().x / width * kMetresPerDegree * std::cos(lat * 3.14159265358979 / 180.0);
    const double dy = lonLat.size().y / height * kMetresPerDegree;
    return std::max(1.0, std::min(dx, dy));
}

std::map<std::string, std::size_t> countByReason(const std::vector<FeatureProblem>& problems) {
    std::map<std::string, std::size_t> out;
    for (const FeatureProblem& p : problems) ++out[p.reason];
    return out;
}

// Fraction of river nodes whose DEM height is below the median of 16 samples on a 150 m circle.
void checkRivers(const Scene& s, const Dem& dem, ImportReport& r) {
    std::size_t below = 0, checked = 0;
    for (const Layer& l : s.layers) {
        if (l.kind != LayerKind::Rivers) continue;
        for (const Node& n : l.nodes) {
            if (!n.alive || n.curves.empty()) continue;
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
    r.riverNodesChecked = checked;
    r.riverNodesBelowSurroundings = checked ? double(below) / double(checked) : 0.0;
}

}  // namespace

SceneDocument importScene(const ImportOptions& o, ImportReport& report, const std::function<void(const std::string&)>& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    auto say = [&](const std::string& s) {
        if (progress) progress(s);
    };
    report = {};
    if (!std::isfinite(o.fitTolerance) || o.fitTolerance < 0.0)
        throw std::invalid_argument("the spline fitting tolerance must be a finite number of metres >= 0");
    if (!std::isfinite(o.demCell) || o.demCell < 0.0)
        throw std::invalid_argument("the DEM cell must be a finite number of metres >= 0 (0: the source's resolution)");
    if (!std::isfinite(o.margin) || o.margin < 0.0) throw std::invalid_argument("the margin must be a finite number of metres >= 0");
    const FeatureMapping mapping = o.mapping.empty() ? defaultMapping() : loadMapping(o.mapping);
    VectorData data;
    for (std::size_t i = 0; i < o.vectors.size(); ++i) {
        say("reading " + o.vectors[i] + " (" + std::to_string(i + 1) + "/" + std::to_string(o.vectors.size()) + ")");
        readVectors(o.vectors[i], mapping, data);
    }
    report.featuresRead = data.featuresRead;
    report.unmapped = data.unmapped;
    report.problems = data.problems;
    say("projecting");
    const DemSourceInfo demInfo = demSourceInfo({o.dem});
    const Box demLonLat = demInfo.lonLat;
    auto insideDem = [&](glm::dvec2 p) { return demLonLat.contains(p); };
    Box bounds{{1e300, 1e300}, {-1e300, -1e300}};
    auto grow = [&](const std::vector<glm::dvec2>& pts) {
        bool in = true;
        for (const glm::dvec2& p : pts) in = in && insideDem(p);
        if (!in) return;
        for (const glm::dvec2& p : pts) bounds = {glm::min(bounds.min, p), glm::max(bounds.max, p)};
    };
    for (const RawLine& l : data.lines) grow(l.lonLat);
    for (const RawArea& a : data.areas)
        for (const auto& ring : a.rings) grow(ring);
    if (!(bounds.min.x <= bounds.max.x)) bounds = demLonLat;  // no feature inside the DEM: the DEM's own bounds
    report.lon0 = bounds.center().x;
    report.lat0 = bounds.center().y;
    SceneFrame frame(report.lon0, report.lat0);
    Box projected{{1e300, 1e300}, {-1e300, -1e300}};
    for (int j = 0; j <= 16; ++j)
        for (int i = 0; i <= 16; ++i) {
            const Vec2 q = frame.forward(bounds.min + bounds.size() * glm::dvec2(i / 16.0, j / 16.0));
            projected = {glm::min(projected.min, q), glm::max(projected.max, q)};
        }
    projected = projected.dilated(o.margin);
    const double side = std::ceil(std::max(projected.size().x, projected.size().y));
    const Vec2 centre = projected.center();
    frame.setOriginShift(Vec2(side / 2.0) - centre);
    report.extent = {{0.0, 0.0}, {side, side}};
    report.largestScaleError = frame.largestScaleError(report.extent);

    say("reading the DEM " + o.dem);
    double cell = o.demCell;
    if (!(cell > 0.0)) cell = sourceResolution(demLonLat, demInfo.width, demInfo.height, report.lat0);
    SceneDocument doc;
    doc.dem = importDem(demInfo, frame, report.extent, cell, report.dem);
    say("building the network and fitting splines");
    doc.scene = buildScene(data, mapping, frame, report.extent, insideDem, SplineFitParams{o.fitTolerance}, report.network,
                           &doc.attributes);
    report.problems.insert(report.problems.end(), report.network.problems.begin(), report.network.problems.end());
    report.linesKept = data.lines.size();
    report.areasKept = data.areas.size();
    say("validating");
    validateOrThrow(doc.scene);
    doc.georeference = frame.georeference();
    checkRivers(doc.scene, *doc.dem, report);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return doc;
}

nlohmann::json ImportReport::json() const {
    nlohmann::json layers = nlohmann::json::array();
    for (const LayerSummary& l : network.layers) {
        nlohmann::json byClass = nlohmann::json::object(), areas = nlohmann::json::object();
        for (const auto& [c, n] : l.curvesByClass) byClass[std::to_string(c)] = n;
        for (const auto& [c, n] : l.areasByClass) areas[std::to_string(c)] = n;
        layers.push_back({{"name", l.name}, {"kind", std::string(toString(l.kind))}, {"curves_by_class", byClass},
                          {"areas_by_class", areas}, {"nodes", l.nodes}, {"junctions", l.junctions}, {"bridges", l.bridges},
                          {"tunnels", l.tunnels}, {"holes", l.holes}});
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
                     {"chains_merged", network.chainsMerged}}},
            {"dem", {{"path", dem.path}, {"source_size", {dem.sourceWidth, dem.sourceHeight}}, {"voids_filled", dem.voids},
                     {"outside_fraction", dem.outsideFraction}, {"cell_m", dem.cellSize}, {"grid", {dem.width, dem.height}},
                     {"height_range_m", {dem.minHeight, dem.maxHeight}}, {"ms", dem.ms}}},
            {"crs", {{"projection", "transverse Mercator (WGS84), scale 1 on the central meridian"}, {"lon0", lon0}, {"lat0", lat0},
                     {"largest_scale_error", largestScaleError}}},
            {"extent_m", {extent.min.x, extent.min.y, extent.max.x, extent.max.y}},
            {"river_nodes_below_surroundings", riverNodesBelowSurroundings},
            {"river_nodes_checked", riverNodesChecked},
            {"problems_by_reason", countByReason(problems)},
            {"problems", problemList},
            {"ms", ms}};
}

}  // namespace lacet
