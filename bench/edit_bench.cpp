// `lacet bench edit`: edit latency of the window-less session (issue: the 3D editor). A fixed view
// near the ground: a camera `altitude` metres above the terrain, 80 m from the edited road control
// point and looking at it (1280 x 800, 52 degrees vertical field of view); a road control point
// dragged in 60 steps, then a field corner node, three times each (undone in between): for each
// step, the time from the command to every visible dirty tile (in the view frustum) being made
// again (both producers, TBB worker threads), against the number of tiles made. Dirty tiles outside the frustum are left for when
// they come into view. Also reported: the same without frustum culling (every leaf of the view).
#include <algorithm>
#include <cmath>

#include <tbb/info.h>

#include <glm/geometric.hpp>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "editor/camera.h"
#include "editor/edit_session.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

struct Drag {
    std::vector<double> ms, tiles, updateMs, produceMs, dirty, uniform;
    nlohmann::json json() const {
        return {{"steps", ms.size()},
                {"median_ms", median(ms)},
                {"p95_ms", quantile(ms, 0.95)},
                {"max_ms", quantile(ms, 1.0)},
                {"tiles_median", median(tiles)},
                {"tiles_max", quantile(tiles, 1.0)},
                {"update_median_ms", median(updateMs)},
                {"produce_median_ms", median(produceMs)},
                {"dirty_tiles_median", median(dirty)},
                {"uniform_tiles_median", median(uniform)}};
    }
};

// `repeats` drags of `steps` commands made by `command(i)`, each command followed by a frame
// that makes every dirty tile of the view; after each drag, undo and a frame (not timed) bring
// the scene and the tiles back, so every drag starts from the same state. The steps of all the
// drags are pooled (this machine's noise is about 10 % from run to run).
template <class F>
Drag drag(EditSession& session, glm::dvec3 viewer, const QuadVisibility& visible, int steps, int repeats, F&& command) {
    Drag d;
    for (int rep = 0; rep < repeats; ++rep) {
        for (int i = 0; i < steps; ++i) {
            std::uint64_t version = 0;
            for (const auto& [key, t] : session.tiles()) version = std::max(version, t.version);
            const auto t0 = Clock::now();
            const CommandReport c = session.execute(command(i), true);
            const FrameReport f = session.frame(viewer, 0.0, visible);
            d.ms.push_back(msSince(t0));
            d.tiles.push_back(double(f.produced));
            d.updateMs.push_back(c.updateMs);
            d.produceMs.push_back(f.produceMs);
            d.dirty.push_back(double(c.dirtyTiles));
            std::size_t uniform = 0;  // of the tiles made: those a single area or river covers
            for (const auto& [key, t] : session.tiles()) uniform += t.version > version && t.appearance.uniform;
            d.uniform.push_back(double(uniform));
        }
        session.undo();  // the drag is one undo step
        session.frame(viewer, 0.0, visible);
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

    // The camera: south-west of the point, `altitude` above the ground, looking at it.
    const glm::dvec2 zRange = frustumHeightRange(*doc.dem);
    auto viewOf = [&](Vec2 target) {
        Camera camera;
        camera.fly = true;
        const Vec2 from = target + Vec2(-56.0, -56.0);
        camera.flyPosition = glm::dvec3(from.x, from.y, doc.dem->sample(from) + o.altitude);
        const glm::dvec3 look = glm::dvec3(target.x, target.y, doc.dem->sample(target)) - camera.flyPosition;
        camera.yaw = std::atan2(look.x, look.y);
        camera.pitch = std::atan2(-look.z, glm::length(glm::dvec2(look)));
        return std::pair{frustumVisibility(camera, 1280.0 / 800.0, Camera::clipRange(o.altitude), zRange),
                         glm::dvec3(from.x, from.y, o.altitude)};
    };
    const auto [visible, viewer] = viewOf(at);

    nlohmann::json runs;
    std::size_t viewQuads = 0, visibleQuads = 0;
    double firstMs = 0.0;
    for (const bool cull : {true, false}) {
        SessionParams params;
        params.cacheTiles = 1u << 20;
        if (!o.objects) {
            params.objects.bridges = false;
            params.objects.trees.clear();
        }
        t0 = Clock::now();
        EditSession session{SceneDocument(doc), params};
        const FrameReport first = session.frame(viewer, 0.0, cull ? visible : QuadVisibility{});
        if (cull) firstMs = msSince(t0), viewQuads = first.viewQuads + first.culled, visibleQuads = first.viewQuads;
        const QuadVisibility& v = cull ? visible : QuadVisibility{};
        const Drag roadDrag = drag(session, viewer, v, o.steps, o.repeats, [&](int i) -> Command {
            const double f = double(i + 1) / o.steps;
            return MoveVertexCmd{kRoadsLayer, road, index, at + Vec2(30.0, 20.0) * f};
        });
        const Drag fieldDrag = drag(session, viewer, v, o.steps, o.repeats, [&](int i) -> Command {
            const double f = double(i + 1) / o.steps;
            return MoveNodeCmd{kFieldsLayer, field, fieldAt + Vec2(8.0, -6.0) * f};
        });
        runs[cull ? "frustum_culled" : "every_leaf"] = {{"road_control_point", roadDrag.json()}, {"field_border", fieldDrag.json()}};
        if (!cull) continue;
        // A road over a river (issue 14): the bridge nearest the centre; the road's vertex nearest
        // the bridge's middle dragged 60 m across the road's direction, so that the crossing moves
        // and the graph step re-makes the road's bridge at every step (the bridge, its deck and
        // the river under it are in the view).
        const Quadtree& qt = session.quadtree();
        Vec2 bridgeAt(0.0);
        ElementId bridged = kNoElement;
        best = 1e300;
        for (ElementId id = 0; id < s.layers[kRoadsLayer].curves.size(); ++id)
            for (AncestorId a : qt.expansionOf(kRoadsLayer, id)) {
                const Curve& b = qt.ancestorCurve(kRoadsLayer, a);
                if (!(b.flags & kBridge)) continue;
                const Vec2 mid = 0.5 * (b.vertices.front().p + b.vertices.back().p);
                if (glm::length(mid - centre) < best) best = glm::length(mid - centre), bridged = id, bridgeAt = mid;
            }
        if (bridged == kNoElement) continue;
        const Curve& r = s.layers[kRoadsLayer].curves[bridged];
        // An inner vertex (the road alone moves, as with the control point above) when the road
        // has one, else its end node (its junction's other roads move too).
        std::size_t vi = 0;
        best = 1e300;
        const bool inner = r.vertices.size() > 2;
        for (std::size_t i = inner ? 1 : 0; i < (inner ? r.vertices.size() - 1 : r.vertices.size()); ++i)
            if (glm::length(r.vertices[i].p - bridgeAt) < best) best = glm::length(r.vertices[i].p - bridgeAt), vi = i;
        const Vec2 along = glm::normalize(r.vertices.back().p - r.vertices.front().p);
        const Vec2 across(-along.y, along.x);
        const Vec2 from = r.vertices[vi].p;
        const bool isNode = vi == 0 || vi + 1 == r.vertices.size();
        const ElementId node = vi == 0 ? r.start : r.end;
        const auto [riverVisible, riverViewer] = viewOf(bridgeAt);
        session.frame(riverViewer, 0.0, riverVisible);
        const std::size_t bridgesBefore = qt.proceduralCount(kBridge);
        const Drag riverDrag = drag(session, riverViewer, riverVisible, o.steps, o.repeats, [&](int i) -> Command {
            const Vec2 p = from + across * (60.0 * double(i + 1) / o.steps);
            if (isNode) return MoveNodeCmd{kRoadsLayer, node, p};
            return MoveVertexCmd{kRoadsLayer, bridged, vi, p};
        });
        runs["road_over_river"] = riverDrag.json();
        runs["road_over_river"]["bridge_distance_from_centre_m"] = glm::length(bridgeAt - centre);
        runs["road_over_river"]["dragged"] = isNode ? "end node" : r.vertices[vi].onCurve ? "inner on-curve vertex" : "control point";
        runs["road_over_river"]["dragged_distance_from_bridge_m"] = best;
        runs["road_over_river"]["bridges_in_scene"] = bridgesBefore;
    }
    return {{"curves", count(doc.scene).curves},
            {"threads", tbb::info::default_concurrency()},
            {"viewer_altitude_m", o.altitude},
            {"steps_per_drag", o.steps},
            {"drags", o.repeats},
            {"K", SessionParams{}.view.K},
            {"object_meshes", o.objects},
            {"appearance_resolution", RefineParams{}.resolution},
            {"view_quads", viewQuads},
            {"visible_quads", visibleQuads},
            {"prepare_ms", prepareMs},
            {"first_frame_ms", firstMs},
            {"field_node_distance_m", glm::length(fieldAt - at)},
            {"runs", runs},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
