// `lacet bench edit`: edit latency of the window-less session (issue: the 3D editor). A fixed view
// near the ground; a road control point dragged in 60 steps, then a field corner node: for each
// step, the time from the command to every dirty tile of the view being made again (both
// producers, TBB worker threads), against the number of tiles made.
#include <tbb/info.h>

#include <glm/geometric.hpp>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "editor/edit_session.h"
#include "model/synthetic_scene.h"
#include "raster/synthetic_dem.h"

namespace lacet::bench {
namespace {

struct Drag {
    std::vector<double> ms;
    std::vector<double> tiles;
    nlohmann::json json() const {
        return {{"steps", ms.size()},       {"median_ms", median(ms)},      {"p95_ms", quantile(ms, 0.95)},
                {"max_ms", quantile(ms, 1.0)}, {"tiles_median", median(tiles)}, {"tiles_max", quantile(tiles, 1.0)}};
    }
};

// One drag: `steps` commands made by `command(i)`, each followed by a frame that makes every
// dirty tile of the view.
template <class F>
Drag drag(EditSession& session, glm::dvec3 viewer, int steps, F&& command) {
    Drag d;
    for (int i = 0; i < steps; ++i) {
        const auto t0 = Clock::now();
        session.execute(command(i));
        const FrameReport f = session.frame(viewer, 0.0);
        d.ms.push_back(msSince(t0));
        d.tiles.push_back(double(f.produced));
    }
    return d;
}

}  // namespace

nlohmann::json benchEdit(const EditBenchOptions& o) {
    auto t0 = Clock::now();
    SceneDocument doc;
    doc.scene = makeSyntheticScene({o.seed, o.curves});
    doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    const double prepareMs = msSince(t0);
    // The road control point nearest the scene centre, and the field node nearest to it.
    const Scene& s = doc.scene;
    const Vec2 centre = s.extent.center();
    ElementId road = kNoElement;
    std::size_t index = 0;
    double best = 1e300;
    for (ElementId id = 0; id < s.layers[kRoadsLayer].curves.size(); ++id) {
        const auto& v = s.layers[kRoadsLayer].curves[id].vertices;
        for (std::size_t i = 1; i + 1 < v.size(); ++i)
            if (!v[i].onCurve && glm::length(v[i].p - centre) < best) best = glm::length(v[i].p - centre), road = id, index = i;
    }
    if (road == kNoElement) throw std::runtime_error("bench edit: the scene has no road control point");
    const Vec2 at = s.layers[kRoadsLayer].curves[road].vertices[index].p;
    ElementId field = kNoElement;
    best = 1e300;
    for (ElementId id = 0; id < s.layers[kFieldsLayer].nodes.size(); ++id)
        if (glm::length(s.layers[kFieldsLayer].nodes[id].p - at) < best) best = glm::length(s.layers[kFieldsLayer].nodes[id].p - at), field = id;
    const Vec2 fieldAt = s.layers[kFieldsLayer].nodes[field].p;

    SessionParams params;
    params.cacheTiles = 1u << 20;
    t0 = Clock::now();
    EditSession session(std::move(doc), params);
    const glm::dvec3 viewer(at.x, at.y, o.altitude);
    const FrameReport first = session.frame(viewer, 0.0);
    const double firstMs = msSince(t0);
    const Drag roadDrag = drag(session, viewer, o.steps, [&](int i) -> Command {
        const double f = double(i + 1) / o.steps;
        return MoveVertexCmd{kRoadsLayer, road, index, at + Vec2(30.0, 20.0) * f};
    });
    const Drag fieldDrag = drag(session, viewer, o.steps, [&](int i) -> Command {
        const double f = double(i + 1) / o.steps;
        return MoveNodeCmd{kFieldsLayer, field, fieldAt + Vec2(8.0, -6.0) * f};
    });
    return {{"curves", count(session.document().scene).curves},
            {"threads", tbb::info::default_concurrency()},
            {"viewer_altitude_m", o.altitude},
            {"K", params.K},
            {"appearance_resolution", params.refine.resolution},
            {"view_quads", first.viewQuads},
            {"prepare_ms", prepareMs},
            {"first_frame_ms", firstMs},
            {"field_node_distance_m", glm::length(fieldAt - at)},
            {"road_control_point", roadDrag.json()},
            {"field_border", fieldDrag.json()},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
