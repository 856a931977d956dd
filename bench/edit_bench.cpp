// `lacet bench edit`: edit latency of the window-less session (issue: the 3D editor). A fixed view
// near the ground: a camera `altitude` metres above the terrain, 80 m from the edited road control
// point and looking at it (1280 x 800, 52 degrees vertical field of view); a road control point
// dragged in 60 steps, then a field corner node, three times each (undone in between): for each
// step, the time from the command to every visible dirty tile (in the view frustum) being made
// again (both producers, TBB worker threads), against the number of tiles made. Dirty tiles outside the frustum are left for when
// they come into view. Also reported: the same without frustum culling (every leaf of the view),
// and a new road drawn beside the point (two nodes and a curve, as the draw tool makes them),
// three times per drag repeat, each timed with its frame and undone.
// With `--scene F --vector-budget M [--pyramid P]`: a scene file read lazily (issue 23), its edits
// kept over the file; the drags from the view only (the frustum). With `--save` too, a road and a
// field node dragged and kept, saved into the file, undone and saved again (the file's content as
// it was), then a new road saved and taken back: what a save in place costs (io/scene_save_edits.h).
#include <algorithm>
#include <cmath>

#include <tbb/info.h>

#include <glm/geometric.hpp>

#include "bench/bench_util.h"
#include "bench/tasks.h"
#include "editor/camera.h"
#include "editor/edit_session.h"
#include "io/scene_region.h"
#include "model/graph_step.h"
#include "pyramid/pyramid_reader.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::bench {
namespace {

struct Drag {
    std::vector<double> ms, tiles, applyMs, updateMs, produceMs, dirty, uniform;
    std::size_t topReadAgain = 0;  // lazily: steps that read the top tree again
    nlohmann::json json() const {
        return {{"steps", ms.size()},
                {"median_ms", median(ms)},
                {"p95_ms", quantile(ms, 0.95)},
                {"max_ms", quantile(ms, 1.0)},
                {"tiles_median", median(tiles)},
                {"tiles_max", quantile(tiles, 1.0)},
                {"apply_median_ms", median(applyMs)},
                {"update_median_ms", median(updateMs)},
                {"top_read_again_steps", topReadAgain},
                {"produce_median_ms", median(produceMs)},
                {"dirty_tiles_median", median(dirty)},
                {"uniform_tiles_median", median(uniform)}};
    }
};

// Times `step` (commands, returning their reports summed) with the frame that makes every dirty
// tile of the view, into `d`.
template <class F>
void timeStep(EditSession& session, glm::dvec3 viewer, const QuadVisibility& visible, Drag& d, F&& step) {
    std::uint64_t version = 0;
    for (const auto& [key, t] : session.tiles()) version = std::max(version, t.version);
    const auto t0 = Clock::now();
    const CommandReport c = step();
    const FrameReport f = session.frame(viewer, 0.0, visible);
    d.ms.push_back(msSince(t0));
    d.tiles.push_back(double(f.produced));
    d.applyMs.push_back(c.applyMs);
    d.updateMs.push_back(c.updateMs);
    d.topReadAgain += c.topReadAgain;
    d.produceMs.push_back(f.produceMs);
    d.dirty.push_back(double(c.dirtyTiles));
    std::size_t uniform = 0;  // of the tiles made: those a single area or river covers
    for (const auto& [key, t] : session.tiles()) uniform += t.version > version && t.appearance.uniform;
    d.uniform.push_back(double(uniform));
}

// `repeats` drags of `steps` commands made by `command(i)`, each command followed by a frame
// that makes every dirty tile of the view; after each drag, undo and a frame (not timed) bring
// the scene and the tiles back, so every drag starts from the same state. The steps of all the
// drags are pooled (this machine's noise is about 10 % from run to run).
template <class F>
Drag drag(EditSession& session, glm::dvec3 viewer, const QuadVisibility& visible, int steps, int repeats, F&& command) {
    Drag d;
    for (int rep = 0; rep < repeats; ++rep) {
        for (int i = 0; i < steps; ++i) timeStep(session, viewer, visible, d, [&] { return session.execute(command(i), true); });
        session.undo();  // the drag is one undo step
        session.frame(viewer, 0.0, visible);
    }
    return d;
}

// A new road drawn beside `at` as the draw tool makes one: two new nodes and a curve between
// them, one group (ids from EditSession::nextId: the file's, lazily).
// Returns the three commands' reports summed.
CommandReport drawRoad(EditSession& session, Vec2 at) {
    const Vec2 a = at + Vec2(40.0, -30.0), b = a + Vec2(120.0, 50.0);
    CommandReport sum;
    const auto add = [&](const CommandReport& r) {
        sum.applyMs += r.applyMs;
        sum.updateMs += r.updateMs;
        sum.changedQuads += r.changedQuads;
        sum.dirtyTiles += r.dirtyTiles;
        sum.topReadAgain = sum.topReadAgain || r.topReadAgain;
    };
    session.beginGroup();
    Curve c;
    c.start = session.nextId(kRoadsLayer, ElementKind::Node);
    add(session.execute(AddNodeCmd{kRoadsLayer, a}));
    c.end = session.nextId(kRoadsLayer, ElementKind::Node);
    add(session.execute(AddNodeCmd{kRoadsLayer, b}));
    c.w = 6.0f;
    c.wf = 14.0f;
    c.vertices = {Vertex{a, true, false}, Vertex{(a + b) * 0.5 + Vec2(-15.0, 15.0), false, false}, Vertex{b, true, false}};
    add(session.execute(AddCurveCmd{kRoadsLayer, c}));
    session.endGroup();
    return sum;
}


// nearest to it, and (issue 14) the bridge nearest the centre: the road's vertex nearest the
// bridge's middle dragged 60 m across the road's direction, so that the crossing moves and the
// graph step re-makes the road's bridge at every step. `s` is the whole scene or a part of the file
// read around the centre, `qt` its quadtree (its graph step's bridges).
struct Targets {
    ElementId road = kNoElement;
    std::size_t index = 0;
    Vec2 at{0.0};
    ElementId field = kNoElement;
    Vec2 fieldAt{0.0};
    bool river = false;
    ElementId bridged = kNoElement, node = kNoElement;
    std::size_t vertex = 0;
    bool isNode = false;
    Vec2 from{0.0}, across{0.0}, bridgeAt{0.0};
    double bridgeDistance = 0.0, vertexDistance = 0.0;
    std::string dragged;
};

Targets pickTargets(const Scene& s, const Quadtree& qt, Vec2 centre) {
    Targets t;
    const Layer& roads = s.layers.at(kRoadsLayer);
    const Layer& fields = s.layers.at(kFieldsLayer);
    double best = 1e300;
    for (ElementId id = 0; id < roads.curves.size(); ++id) {
        const auto& v = roads.curves[id].vertices;
        if (!roads.curves[id].alive) continue;
        for (std::size_t i = 1; i + 1 < v.size(); ++i)
            if (!v[i].onCurve && glm::length(v[i].p - centre) < best) best = glm::length(v[i].p - centre), t.road = id, t.index = i;
    }
    if (t.road == kNoElement) throw std::runtime_error("bench edit: the scene has no road control point");
    t.at = roads.curves[t.road].vertices[t.index].p;
    best = 1e300;
    for (ElementId id = 0; id < fields.nodes.size(); ++id)
        if (fields.nodes[id].alive && glm::length(fields.nodes[id].p - t.at) < best) best = glm::length(fields.nodes[id].p - t.at), t.field = id;
    if (t.field == kNoElement) throw std::runtime_error("bench edit: the scene has no field node");
    t.fieldAt = fields.nodes[t.field].p;
    best = 1e300;
    for (ElementId id = 0; id < roads.curves.size(); ++id)
        for (AncestorId a : qt.expansionOf(kRoadsLayer, id)) {
            const Curve& b = qt.ancestorCurve(kRoadsLayer, a);
            if (!(b.flags & kBridge)) continue;
            const Vec2 mid = 0.5 * (b.vertices.front().p + b.vertices.back().p);
            if (glm::length(mid - centre) < best) best = glm::length(mid - centre), t.bridged = id, t.bridgeAt = mid;
        }
    if (t.bridged != kNoElement) {
        t.river = true;
        t.bridgeDistance = best;
        const Curve& r = roads.curves[t.bridged];
        // An inner vertex (the road alone moves, as with the control point above) when the road
        // has one, else its end node (its junction's other roads move too).
        best = 1e300;
        const bool inner = r.vertices.size() > 2;
        for (std::size_t i = inner ? 1 : 0; i < (inner ? r.vertices.size() - 1 : r.vertices.size()); ++i)
            if (glm::length(r.vertices[i].p - t.bridgeAt) < best) best = glm::length(r.vertices[i].p - t.bridgeAt), t.vertex = i;
        t.vertexDistance = best;
        const Vec2 along = glm::normalize(r.vertices.back().p - r.vertices.front().p);
        t.across = Vec2(-along.y, along.x);
        t.from = r.vertices[t.vertex].p;
        t.isNode = t.vertex == 0 || t.vertex + 1 == r.vertices.size();
        t.node = roads.sceneNodeId(t.vertex == 0 ? r.start : r.end);
        t.dragged = t.isNode ? "end node" : r.vertices[t.vertex].onCurve ? "inner on-curve vertex" : "control point";
        t.bridged = roads.sceneCurveId(t.bridged);
    }
    t.road = roads.sceneCurveId(t.road);
    t.field = fields.sceneNodeId(t.field);
    return t;
}

// The camera south-west of `target`, `altitude` above the ground, looking at it.
std::pair<QuadVisibility, glm::dvec3> viewOf(Vec2 target, const Dem& dem, double altitude) {
    const glm::dvec2 zRange = frustumHeightRange(dem);
    Camera camera;
    camera.fly = true;
    const Vec2 from = target + Vec2(-56.0, -56.0);
    camera.flyPosition = glm::dvec3(from.x, from.y, dem.sample(from) + altitude);
    const glm::dvec3 look = glm::dvec3(target.x, target.y, dem.sample(target)) - camera.flyPosition;
    camera.yaw = std::atan2(look.x, look.y);
    camera.pitch = std::atan2(-look.z, glm::length(glm::dvec2(look)));
    return {frustumVisibility(camera, 1280.0 / 800.0, Camera::clipRange(altitude), zRange), glm::dvec3(from.x, from.y, altitude)};
}

// `times` new roads drawn beside the dragged road point (drawRoad), each timed with the frame that
// makes the view's dirty tiles, then undone (a frame, not timed).
Drag drawRun(EditSession& session, const Targets& t, glm::dvec3 viewer, const QuadVisibility& visible, int times) {
    Drag d;
    for (int k = 0; k < times; ++k) {
        timeStep(session, viewer, visible, d, [&] { return drawRoad(session, t.at); });
        session.undo();
        session.frame(viewer, 0.0, visible);
    }
    return d;
}

// The road and field drags from the view of the road's point (`visible` or every leaf), and, with
// `river`, the road over the river from the view of its bridge.
nlohmann::json dragRuns(EditSession& session, const Targets& t, const EditBenchOptions& o, const QuadVisibility& visible,
                        glm::dvec3 viewer, bool river) {
    const Drag roadDrag = drag(session, viewer, visible, o.steps, o.repeats, [&](int i) -> Command {
        const double f = double(i + 1) / o.steps;
        return MoveVertexCmd{kRoadsLayer, t.road, t.index, t.at + Vec2(30.0, 20.0) * f};
    });
    const Drag fieldDrag = drag(session, viewer, visible, o.steps, o.repeats, [&](int i) -> Command {
        const double f = double(i + 1) / o.steps;
        return MoveNodeCmd{kFieldsLayer, t.field, t.fieldAt + Vec2(8.0, -6.0) * f};
    });
    nlohmann::json runs = {{"road_control_point", roadDrag.json()}, {"field_border", fieldDrag.json()}};
    runs["new_road"] = drawRun(session, t, viewer, visible, o.repeats * 3).json();
    if (!river || !t.river) return runs;
    const auto [riverVisible, riverViewer] = viewOf(t.bridgeAt, *session.document().dem, o.altitude);
    session.frame(riverViewer, 0.0, riverVisible);
    const Drag riverDrag = drag(session, riverViewer, riverVisible, o.steps, o.repeats, [&](int i) -> Command {
        const Vec2 p = t.from + t.across * (60.0 * double(i + 1) / o.steps);
        if (t.isNode) return MoveNodeCmd{kRoadsLayer, t.node, p};
        return MoveVertexCmd{kRoadsLayer, t.bridged, t.vertex, p};
    });
    runs["road_over_river"] = riverDrag.json();
    runs["road_over_river"]["bridge_distance_from_centre_m"] = t.bridgeDistance;
    runs["road_over_river"]["dragged"] = t.dragged;
    runs["road_over_river"]["dragged_distance_from_bridge_m"] = t.vertexDistance;
    return runs;
}

SessionParams benchParams(const EditBenchOptions& o) {
    SessionParams params;
    params.cacheTiles = 1u << 20;
    if (!o.objects) {
        params.objects.bridges = false;
        params.objects.trees.clear();
    }
    return params;
}

// `--scene F --vector-budget M`: the scene file read lazily (editor/lazy_forest.h), its edits kept
// over the file (editor/lazy_edits.h); the targets picked from the part of the file around its
// centre.
nlohmann::json benchEditLazy(const EditBenchOptions& o) {
    auto t0 = Clock::now();
    LazyParams lazy;
    lazy.vectorBudgetMiB = o.vectorBudgetMiB;
    lazy.partLevel = o.partLevel;
    lazy.topElevationOnly = !o.pyramid.empty();
    lazy.background = false;  // the view's parts read in the first frame: the drags time the edits alone
    EditSession session(o.scene, lazy, benchParams(o));
    const double openMs = msSince(t0);
    const Box extent = session.document().scene.extent;
    if (!o.pyramid.empty())
        session.setPyramid(std::make_shared<PyramidReader>(o.pyramid, extent,
                                                           session.document().georeference.valid ? session.document().georeference.crsWkt
                                                                                                 : std::string(),
                                                           session.storedChecksum()));
    const Vec2 centre = extent.center();
    Targets targets;
    {
        SceneRegionOptions filter;
        filter.dem = false;
        SceneDocument near = loadSceneRegion(o.scene, Box{centre - 1500.0, centre + 1500.0}, RefineParams{}, 12, nullptr, filter);
        GraphStep step(near.scene);
        Quadtree qt(near.scene, {}, &step);
        targets = pickTargets(near.scene, qt, centre);
    }
    const auto [visible, viewer] = viewOf(targets.at, *session.document().dem, o.altitude);
    t0 = Clock::now();
    const FrameReport first = session.frame(viewer, 0.0, visible);
    const double firstMs = msSince(t0);
    nlohmann::json runs = {{"frustum_culled", dragRuns(session, targets, o, visible, viewer, false)}};
    runs["road_over_river"] = dragRuns(session, targets, o, visible, viewer, true)["road_over_river"];
    nlohmann::json saves;
    if (o.save) {
        // The road and the field node dragged (kept), their edits saved into the file; then undone
        // and saved again, so that the file holds what it held (io/scene_save_edits.h).
        const auto saved = [&](const char* what) {
            const SceneEditsSaved s = session.saveEdits();
            saves[what] = {{"rows", s.nodes + s.curves + s.areas},
                           {"features_updated", s.features.updated},
                           {"features_inserted", s.features.inserted},
                           {"features_deleted", s.features.deleted},
                           {"rows_added", s.added},
                           {"rows_removed", s.removed},
                           {"head_summed", s.headSummed},
                           {"write_ms", s.writeMs},
                           {"checksum_ms", s.checksumMs},
                           {"total_ms", s.totalMs}};
        };
        session.beginGroup();
        for (int i = 1; i <= o.steps; ++i) {
            const double f = double(i) / o.steps;
            session.execute(MoveVertexCmd{kRoadsLayer, targets.road, targets.index, targets.at + Vec2(30.0, 20.0) * f}, true);
            session.execute(MoveNodeCmd{kFieldsLayer, targets.field, targets.fieldAt + Vec2(8.0, -6.0) * f}, true);
        }
        session.endGroup();
        saved("edits");
        session.undo();
        saved("undone");
        // A new road (rows inserted, the checksum's head summed again), then taken back (deleted).
        drawRoad(session, targets.at);
        saved("drawn");
        session.undo();
        saved("drawn_undone");
    }
    const LazyStats& st = session.lazyForest()->stats();
    return {{"scene", o.scene},
            {"lazy",
             {{"vector_budget_mib", o.vectorBudgetMiB},
              {"part_level", st.partLevel},
              {"top_mib", st.topMiB},
              {"parts_read", st.partsRead},
              {"parts_renewed", st.partsRenewed},
              {"parts_updated_in_place", st.partsUpdated},
              {"parts_moved_in_memory", st.partsMoved},
              {"parts_grown_in_memory", st.partsGrown},
              {"parts_held_peak", st.partsHeldPeak},
              {"held_mib_peak", st.peakMiB},
              {"pyramid", o.pyramid}}},
            {"threads", tbb::info::default_concurrency()},
            {"viewer_altitude_m", o.altitude},
            {"steps_per_drag", o.steps},
            {"drags", o.repeats},
            {"object_meshes", o.objects},
            {"visible_quads", first.viewQuads},
            {"open_ms", openMs},
            {"first_frame_ms", firstMs},
            {"field_node_distance_m", glm::length(targets.fieldAt - targets.at)},
            {"runs", runs},
            {"saves", saves},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace

nlohmann::json benchEdit(const EditBenchOptions& o) {
    if (!o.scene.empty()) {
        if (!(o.vectorBudgetMiB > 0.0)) throw std::invalid_argument("bench edit: --scene takes --vector-budget (MiB, > 0): it is read lazily");
        return benchEditLazy(o);
    }
    if (!o.pyramid.empty()) throw std::invalid_argument("bench edit: --pyramid goes with --scene");
    if (o.save) throw std::invalid_argument("bench edit: --save goes with --scene (a scene file read lazily)");
    auto t0 = Clock::now();
    SceneDocument doc;
    doc.scene = makeSyntheticScene({o.seed, o.curves});
    doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    const double prepareMs = msSince(t0);
    const Vec2 centre = doc.scene.extent.center();
    nlohmann::json runs;
    std::size_t viewQuads = 0, visibleQuads = 0;
    double firstMs = 0.0, fieldDistance = 0.0;
    for (const bool cull : {true, false}) {
        t0 = Clock::now();
        EditSession session{SceneDocument(doc), benchParams(o)};
        const Targets targets = pickTargets(doc.scene, session.quadtree(), centre);
        fieldDistance = glm::length(targets.fieldAt - targets.at);
        const auto [visible, viewer] = viewOf(targets.at, *doc.dem, o.altitude);
        const FrameReport first = session.frame(viewer, 0.0, cull ? visible : QuadVisibility{});
        if (cull) firstMs = msSince(t0), viewQuads = first.viewQuads + first.culled, visibleQuads = first.viewQuads;
        const std::size_t bridges = session.quadtree().proceduralCount(kBridge);
        const nlohmann::json r = dragRuns(session, targets, o, cull ? visible : QuadVisibility{}, viewer, cull);
        runs[cull ? "frustum_culled" : "every_leaf"] = {
            {"road_control_point", r["road_control_point"]}, {"field_border", r["field_border"]}, {"new_road", r["new_road"]}};
        if (r.contains("road_over_river")) {
            runs["road_over_river"] = r["road_over_river"];
            runs["road_over_river"]["bridges_in_scene"] = bridges;
        }
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
            {"field_node_distance_m", fieldDistance},
            {"runs", runs},
            {"peak_rss_mib", peakRssMiB()}};
}

}  // namespace lacet::bench
