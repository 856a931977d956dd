#include "raster/river_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "model/graph_step.h"
#include "raster/dem_height_field.h"

namespace lacet {
namespace {

Quantiles quantiles(std::vector<double> v, double over) {
    Quantiles q;
    q.count = v.size();
    if (v.empty()) return q;
    std::sort(v.begin(), v.end());
    auto at = [&](double f) { return v[std::size_t(f * double(v.size() - 1))]; };
    q.p01 = at(0.01);
    q.p05 = at(0.05);
    q.median = at(0.5);
    q.p95 = at(0.95);
    q.p99 = at(0.99);
    q.max = v.back();
    q.min = v.front();
    q.fractionOver = double(std::count_if(v.begin(), v.end(), [&](double x) { return x > over; })) / double(v.size());
    return q;
}

}  // namespace

RiverCheckReport checkRivers(const Scene& scene, const Dem& dem, const ZProfileParams& profiles) {
    const auto t0 = std::chrono::steady_clock::now();
    RiverCheckReport r;
    DemHeightField heights(dem);
    GraphStep step(scene);
    Quadtree qt(scene, {}, &step);
    CurveDataCache data(qt, heights, profiles);
    std::vector<double> above, nodes;
    for (LayerId l = 0; l < scene.layers.size(); ++l) {
        const Layer& layer = scene.layers[l];
        if (layer.kind != LayerKind::Rivers) continue;
        for (ElementId c = 0; c < layer.curves.size(); ++c) {
            const Curve& cv = layer.curves[c];
            if (!cv.alive || !cv.areas.empty()) continue;
            ++r.curves;
            const ZProfile& z = data.zProfile(l, c);
            // The samples' points as the profile places them: regular in length along a dense
            // polyline (a quarter of the sample spacing at most between its points).
            std::vector<Vec2> pts;
            std::vector<double> cum;
            forEachPiece(cv.vertices, [&](const BezierPiece& b, std::size_t) {
                const int n = std::max(16, int(std::ceil(arcLength(b, 1.0) / (0.25 * profiles.sampleSpacing))));
                for (int i = pts.empty() ? 0 : 1; i <= n; ++i) {
                    const Vec2 p = evaluate(b, double(i) / n);
                    cum.push_back(pts.empty() ? 0.0 : cum.back() + glm::length(p - pts.back()));
                    pts.push_back(p);
                }
            });
            const std::size_t n = z.z.size();
            if (pts.size() < 2) continue;
            std::size_t seg = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const double target = n > 1 ? cum.back() * double(i) / double(n - 1) : 0.0;
                while (seg + 2 < cum.size() && cum[seg + 1] < target) ++seg;
                const double span = cum[seg + 1] - cum[seg];
                const double f = span > 0.0 ? std::clamp((target - cum[seg]) / span, 0.0, 1.0) : 0.0;
                above.push_back(z.z[i] - dem.sample(pts[seg] + (pts[seg + 1] - pts[seg]) * f));
                r.risingSamples += i > 0 && z.z[i] > z.z[i - 1];
            }
        }
        for (ElementId id = 0; id < layer.nodes.size(); ++id) {
            const Node& nd = layer.nodes[id];
            if (!nd.alive || nd.curves.empty()) continue;
            if (std::all_of(nd.curves.begin(), nd.curves.end(), [&](ElementId c) { return !layer.curves[c].areas.empty(); }))
                continue;  // a river area's ring node
            nodes.push_back(data.nodeHeight(l, id) - dem.sample(nd.p));
        }
    }
    r.profileAboveDem = quantiles(std::move(above), r.over);
    r.nodesAboveDem = quantiles(std::move(nodes), r.over);
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

}  // namespace lacet
