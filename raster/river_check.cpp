#include "raster/river_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "model/graph_step.h"

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
    return checkRivers(scene, InMemoryDem(dem), profiles);
}

RiverCheckReport checkRivers(const Scene& scene, const DemSource& dem, const ZProfileParams& profiles) {
    RiverCheck check(profiles);
    check.add(scene, dem, [](Vec2) { return true; });
    return check.finish();
}

RiverCheck::RiverCheck(ZProfileParams profiles) : profiles_(profiles), t0_(std::chrono::steady_clock::now()) {}

void RiverCheck::add(const Scene& scene, const DemSource& dem, const std::function<bool(Vec2)>& owns) {
    const HeightField& heights = dem.heights();
    GraphStep step(scene);
    Quadtree qt(scene, {}, &step);
    CurveDataCache data(qt, heights, profiles_);
    for (LayerId l = 0; l < scene.layers.size(); ++l) {
        const Layer& layer = scene.layers[l];
        if (layer.kind != LayerKind::Rivers) continue;
        for (ElementId c = 0; c < layer.curves.size(); ++c) {
            const Curve& cv = layer.curves[c];
            if (!cv.alive || !cv.areas.empty() || cv.vertices.empty() || !owns(cv.vertices.front().p)) continue;
            ++r_.curves;
            const ZProfile& z = data.zProfile(l, c);
            const std::vector<Vec2> points = data.samplePoints(l, c);
            for (std::size_t i = 0; i < z.z.size() && i < points.size(); ++i) {
                above_.push_back(z.z[i] - heights.height(points[i]));
                r_.risingSamples += i > 0 && z.z[i] > z.z[i - 1];
            }
        }
        for (ElementId id = 0; id < layer.nodes.size(); ++id) {
            const Node& nd = layer.nodes[id];
            if (!nd.alive || nd.curves.empty() || !owns(nd.p)) continue;
            if (std::all_of(nd.curves.begin(), nd.curves.end(), [&](ElementId c) { return !layer.curves[c].areas.empty(); }))
                continue;  // a river area's ring node
            nodes_.push_back(data.nodeHeight(l, id) - heights.height(nd.p));
        }
    }
}

RiverCheckReport RiverCheck::finish() {
    RiverCheckReport r = r_;
    r.profileAboveDem = quantiles(std::move(above_), r.over);
    r.nodesAboveDem = quantiles(std::move(nodes_), r.over);
    above_.clear();
    nodes_.clear();
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0_).count();
    return r;
}

}  // namespace lacet
