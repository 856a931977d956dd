#include "io/fit_check.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "io/scene_frame.h"
#include "model/box_grid.h"
#include "model/hausdorff.h"

namespace lacet {
namespace {

struct Source {
    std::vector<Vec2> points;
    const SourceRef* ref;
};

struct FitPiece {
    BezierPiece piece;
    ElementId curve;
};

// Keeps the `n` largest items (by distance).
void keepWorst(std::vector<FitCheckItem>& list, FitCheckItem item, std::size_t n) {
    list.push_back(std::move(item));
    std::sort(list.begin(), list.end(), [](const FitCheckItem& a, const FitCheckItem& b) { return a.distance > b.distance; });
    if (list.size() > n) list.resize(n);
}

void checkLayer(const Layer& layer, const std::vector<Source>& sources, const FitCheckParams& p, FitCheckLayer& out) {
    std::vector<Vec2> a, b;  // segment ends
    std::vector<Box> segmentBoxes;
    for (const Source& s : sources)
        for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
            a.push_back(s.points[i]);
            b.push_back(s.points[i + 1]);
            segmentBoxes.push_back({glm::min(s.points[i], s.points[i + 1]), glm::max(s.points[i], s.points[i + 1])});
        }
    std::vector<FitPiece> pieces;
    std::vector<Box> pieceBoxes;
    for (std::size_t c = 0; c < layer.curves.size(); ++c) {
        const Curve& curve = layer.curves[c];
        if (!curve.alive) continue;
        ++out.curves;
        out.vertices += curve.vertices.size();
        for (const Vertex& v : curve.vertices) out.onCurveVertices += v.onCurve;
        forEachPiece(curve.vertices, [&](const BezierPiece& bp, std::size_t) {
            pieces.push_back({bp, ElementId(c)});
            pieceBoxes.push_back(controlBounds(bp));
        });
    }
    out.sourceFeatures = sources.size();
    out.sourceSegments = a.size();
    const BoxGrid segments(segmentBoxes), curves(pieceBoxes);
    const double oraclePrecision = 0.25 * p.precision;

    auto toSource = [&](Vec2 q) {
        Nearest n;
        segments.visitNear(q, n.distance, [&](std::size_t i) {
            if (segmentBoxes[i].distanceTo(q) >= n.distance) return;
            const double d = distanceToSegment(q, a[i], b[i]);
            if (d < n.distance) n = {d, i, true};
        });
        return n;
    };
    auto toCurve = [&](Vec2 q) {
        Nearest n;
        curves.visitNear(q, n.distance, [&](std::size_t i) {
            if (pieceBoxes[i].distanceTo(q) >= n.distance - oraclePrecision) return;
            const double d = distanceUpperBound(pieces[i].piece, q, oraclePrecision);
            if (d < n.distance) n = {d, i, pieces[i].piece.degree == 1};
        });
        return n;
    };

    // Per curve (and per source feature): a fresh bound, with stretches that cannot beat the
    // layer's largest distance so far (or the tolerance, when a curve is over it) left unrefined.
    auto measure = [&](auto&& alongAll, double& lower, double& upper, std::size_t& over, std::vector<FitCheckItem>& worst,
                       const std::string& what) {
        HausdorffParams hp;
        hp.precision = p.precision;
        hp.goodEnough = std::min(lower, p.tolerance);
        DistanceBound bound;
        alongAll(hp, bound);
        lower = std::max(lower, bound.lower);
        upper = std::max(upper, bound.upper);
        if (bound.lower > p.tolerance) ++over;
        if (bound.lower > 0.5 * p.tolerance) keepWorst(worst, {what, bound.lower, bound.where}, p.listed);
    };

    // A layer with curves but no source (or sources but no curve) measures infinity: it fails.
    {
        std::size_t k = 0;
        while (k < pieces.size()) {
            const ElementId c = pieces[k].curve;
            std::size_t end = k;
            while (end < pieces.size() && pieces[end].curve == c) ++end;
            measure([&](const HausdorffParams& hp, DistanceBound& bound) {
                        for (std::size_t i = k; i < end; ++i) maxAlongPiece(pieces[i].piece, toSource, 0.0, hp, bound);
                    },
                    out.curveToSourceLower, out.curveToSourceUpper, out.curvesOver, out.worstCurves, "curve " + std::to_string(c));
            k = end;
        }
    }
    for (const Source& s : sources)
            measure([&](const HausdorffParams& hp, DistanceBound& bound) {
                        for (std::size_t i = 0; i + 1 < s.points.size(); ++i)
                            maxAlongSegment(s.points[i], s.points[i + 1], toCurve, oraclePrecision, hp, bound);
                    },
                    out.sourceToCurveLower, out.sourceToCurveUpper, out.sourcesOver, out.worstSources, s.ref->str());
}

}  // namespace

bool FitCheckReport::passed() const {
    // Nothing proven farther than the tolerance, and nothing left undecided (an upper bound past
    // the tolerance by more than the measure's precision).
    for (const FitCheckLayer& l : layers)
        if (l.curvesOver > 0 || l.sourcesOver > 0 || !(l.curveToSourceUpper <= params.tolerance + params.precision) ||
            !(l.sourceToCurveUpper <= params.tolerance + params.precision))
            return false;
    return true;
}

FitCheckReport checkFit(const SceneDocument& doc, const VectorData& data, const FeatureMapping& mapping,
                        const FitCheckParams& params) {
    const auto t0 = std::chrono::steady_clock::now();
    if (!doc.georeference.valid) throw std::invalid_argument("the scene has no georeference (a synthetic scene?): nothing to compare");
    if (!(params.tolerance >= 0.0) || !std::isfinite(params.tolerance))
        throw std::invalid_argument("the tolerance must be a finite number of metres >= 0");
    if (!(params.precision > 0.0) || !std::isfinite(params.precision))
        throw std::invalid_argument("the precision must be a finite number of metres > 0");
    const SceneFrame frame(doc.georeference);
    FitCheckReport report;
    report.params = params;
    std::vector<std::vector<Source>> byLayer(mapping.layers.size());
    // The import keeps the features the DEM covers: a source beyond the DEM is not measured.
    const Box covered = doc.dem ? doc.dem->extent() : doc.scene.extent;
    auto add = [&](std::size_t rule, const std::vector<glm::dvec2>& lonLat, const SourceRef& ref) {
        Source s{{}, &ref};
        for (const glm::dvec2& ll : lonLat) {
            const Vec2 q = frame.forward(ll);
            if (!covered.contains(q)) {
                ++report.sourcesOutside;
                return;
            }
            if (s.points.empty() || s.points.back() != q) s.points.push_back(q);
        }
        if (!s.points.empty()) byLayer[mapping.rules[rule].layer].push_back(std::move(s));
    };
    for (const RawLine& l : data.lines) add(l.rule, l.lonLat, l.source);
    for (const RawArea& area : data.areas)
        for (const auto& ring : area.rings) add(area.rule, ring, area.source);
    for (std::size_t m = 0; m < mapping.layers.size(); ++m) {
        const auto it = std::find_if(doc.scene.layers.begin(), doc.scene.layers.end(),
                                     [&](const Layer& l) { return l.name == mapping.layers[m].name; });
        if (it == doc.scene.layers.end()) continue;
        FitCheckLayer out;
        out.name = it->name;
        checkLayer(*it, byLayer[m], params, out);
        report.layers.push_back(std::move(out));
    }
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return report;
}

nlohmann::json FitCheckReport::json() const {
    nlohmann::json layerList = nlohmann::json::array();
    auto items = [](const std::vector<FitCheckItem>& v) {
        nlohmann::json j = nlohmann::json::array();
        for (const FitCheckItem& i : v) j.push_back({{"what", i.what}, {"distance_m", i.distance}, {"at", {i.at.x, i.at.y}}});
        return j;
    };
    for (const FitCheckLayer& l : layers)
        layerList.push_back({{"name", l.name},
                             {"curves", l.curves},
                             {"vertices", l.vertices},
                             {"on_curve_vertices", l.onCurveVertices},
                             {"source_features", l.sourceFeatures},
                             {"source_segments", l.sourceSegments},
                             {"curve_to_source_m", {l.curveToSourceLower, l.curveToSourceUpper}},
                             {"source_to_curve_m", {l.sourceToCurveLower, l.sourceToCurveUpper}},
                             {"hausdorff_m", std::max(l.curveToSourceUpper, l.sourceToCurveUpper)},
                             {"curves_over_tolerance", l.curvesOver},
                             {"sources_over_tolerance", l.sourcesOver},
                             {"worst_curves", items(l.worstCurves)},
                             {"worst_sources", items(l.worstSources)}});
    return {{"tolerance_m", params.tolerance},
            {"precision_m", params.precision},
            {"passed", passed()},
            {"sources_outside_scene", sourcesOutside},
            {"layers", layerList},
            {"ms", ms}};
}

}  // namespace lacet
