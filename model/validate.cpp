#include "model/validate.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

namespace lacet {
namespace {

std::string describe(const std::vector<Problem>& problems) {
    std::ostringstream s;
    s << problems.size() << " problem(s) in scene";
    for (std::size_t i = 0; i < problems.size() && i < 10; ++i)
        s << "\n  " << problems[i].where << ": " << problems[i].reason;
    if (problems.size() > 10) s << "\n  ...";
    return s.str();
}

std::string where(const Layer& layer, const char* kind, std::size_t id) {
    return "layer '" + layer.name + "' " + kind + " " + std::to_string(id);
}

bool alive(const std::vector<Node>& v, ElementId id) { return id < v.size() && v[id].alive; }
bool alive(const std::vector<Curve>& v, ElementId id) { return id < v.size() && v[id].alive; }

void checkCurve(const Layer& layer, std::size_t id, std::vector<Problem>& out) {
    const Curve& c = layer.curves[id];
    auto report = [&](std::string reason) { out.push_back({where(layer, "curve", id), std::move(reason)}); };
    if (!std::isfinite(c.w) || !std::isfinite(c.wf) || c.w < 0.0f || c.wf < c.w)
        report("widths must be finite with 0 <= w <= wf (w=" + std::to_string(c.w) + ", wf=" + std::to_string(c.wf) + ")");
    if (auto reason = splineProblem(c.vertices); !reason.empty()) report(reason);
    if (!alive(layer.nodes, c.start) || !alive(layer.nodes, c.end)) {
        report("start or end node is missing or deleted");
        return;
    }
    if (!c.vertices.empty() &&
        (c.vertices.front().p != layer.nodes[c.start].p || c.vertices.back().p != layer.nodes[c.end].p))
        report("first/last vertex differs from its start/end node position");
}

void checkArea(const Layer& layer, std::size_t id, std::vector<Problem>& out) {
    const Area& a = layer.areas[id];
    auto report = [&](std::string reason) { out.push_back({where(layer, "area", id), std::move(reason)}); };
    if (!std::isfinite(a.wf) || a.wf < 0.0f) report("footprint width must be finite and >= 0");
    if (a.loops.empty()) report("has no outer loop");
    if (a.axial != kNoElement && !alive(layer.curves, a.axial)) report("axial curve is missing or deleted");
    for (std::size_t li = 0; li < a.loops.size(); ++li) {
        const auto& loop = a.loops[li];
        if (loop.empty()) {
            report("loop " + std::to_string(li) + " is empty");
            continue;
        }
        bool ok = true;
        for (const auto& e : loop)
            if (!alive(layer.curves, e.curve)) {
                report("loop " + std::to_string(li) + " refers to a missing curve " + std::to_string(e.curve));
                ok = false;
            }
        if (!ok) continue;
        auto from = [&](const AreaEdge& e) { const Curve& c = layer.curves[e.curve]; return e.reversed ? c.end : c.start; };
        auto to = [&](const AreaEdge& e) { const Curve& c = layer.curves[e.curve]; return e.reversed ? c.start : c.end; };
        for (std::size_t k = 0; k < loop.size(); ++k)
            if (to(loop[k]) != from(loop[(k + 1) % loop.size()])) {
                report("loop " + std::to_string(li) + " is open: curve " + std::to_string(loop[k].curve) +
                       " does not end where curve " + std::to_string(loop[(k + 1) % loop.size()].curve) + " starts");
                break;
            }
    }
}

// node.curves and curve.areas must list exactly what the curves and areas say.
void checkAdjacency(const Layer& layer, std::vector<Problem>& out) {
    std::vector<std::vector<ElementId>> curvesAt(layer.nodes.size()), areasOf(layer.curves.size());
    for (ElementId c = 0; c < layer.curves.size(); ++c) {
        const Curve& cv = layer.curves[c];
        if (!cv.alive || cv.start >= layer.nodes.size() || cv.end >= layer.nodes.size()) continue;
        curvesAt[cv.start].push_back(c);
        curvesAt[cv.end].push_back(c);
    }
    for (ElementId a = 0; a < layer.areas.size(); ++a) {
        if (!layer.areas[a].alive) continue;
        for (const auto& loop : layer.areas[a].loops)
            for (const auto& e : loop)
                if (e.curve < layer.curves.size()) areasOf[e.curve].push_back(a);
    }
    auto same = [](std::vector<ElementId> a, std::vector<ElementId> b, bool unique) {
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        if (unique) {
            a.erase(std::unique(a.begin(), a.end()), a.end());
            b.erase(std::unique(b.begin(), b.end()), b.end());
        }
        return a == b;
    };
    for (std::size_t n = 0; n < layer.nodes.size(); ++n)
        if (layer.nodes[n].alive && !same(layer.nodes[n].curves, curvesAt[n], false))
            out.push_back({where(layer, "node", n), "its list of curves differs from the curves that end there"});
    for (std::size_t c = 0; c < layer.curves.size(); ++c)
        if (layer.curves[c].alive && !same(layer.curves[c].areas, areasOf[c], true))
            out.push_back({where(layer, "curve", c), "its list of areas differs from the areas whose loops use it"});
}

}  // namespace

ValidationError::ValidationError(std::vector<Problem> problems)
    : std::runtime_error(describe(problems)), problems_(std::move(problems)) {}

bool isFinite(Vec2 p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate;
}

std::string splineProblem(const std::vector<Vertex>& v) {
    if (v.size() < 2) return "has fewer than 2 vertices";
    if (!v.front().onCurve || !v.back().onCurve) return "first and last vertices must be on-curve";
    int controls = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!isFinite(v[i].p)) return "vertex " + std::to_string(i) + " has a non-finite or out-of-range coordinate";
        controls = v[i].onCurve ? 0 : controls + 1;
        if (controls > 2) return "more than 2 control points in a row at vertex " + std::to_string(i);
    }
    return {};
}

// A part of a file's layer: one file id per element of each kind, ascending.
static void checkSceneIds(const Layer& layer, std::vector<Problem>& out) {
    const auto check = [&](const std::vector<ElementId>& ids, std::size_t count, const char* kind) {
        if (ids.size() != count)
            out.push_back({"layer '" + layer.name + "'", std::string("has ") + std::to_string(ids.size()) + " file ids for its " +
                                                             std::to_string(count) + " " + kind});
        else if (std::adjacent_find(ids.begin(), ids.end(), std::greater_equal<ElementId>()) != ids.end())
            out.push_back({"layer '" + layer.name + "'", std::string("the file ids of its ") + kind + " do not ascend"});
    };
    check(layer.sceneIds.nodes, layer.nodes.size(), "nodes");
    check(layer.sceneIds.curves, layer.curves.size(), "curves");
    check(layer.sceneIds.areas, layer.areas.size(), "areas");
}

std::vector<Problem> validate(const Scene& scene) {
    std::vector<Problem> out;
    if (!isFinite(scene.extent.min) || !isFinite(scene.extent.max) || !(scene.extent.min.x < scene.extent.max.x) ||
        !(scene.extent.min.y < scene.extent.max.y))
        out.push_back({"scene", "extent must be finite and non-empty"});
    else if (scene.extent.size().x != scene.extent.size().y)
        out.push_back({"scene", "extent must be square (it is the root quad)"});
    for (const Layer& layer : scene.layers) {
        for (std::size_t id = 0; id < layer.nodes.size(); ++id) {
            const Node& n = layer.nodes[id];
            if (!n.alive) continue;
            if (!isFinite(n.p)) out.push_back({where(layer, "node", id), "position is not finite or out of range"});
            if (!(n.roundabout >= 0.0f) || !std::isfinite(n.roundabout))
                out.push_back({where(layer, "node", id), "roundabout radius is not a finite number of metres >= 0"});
        }
        for (std::size_t id = 0; id < layer.curves.size(); ++id)
            if (layer.curves[id].alive) checkCurve(layer, id, out);
        for (std::size_t id = 0; id < layer.areas.size(); ++id)
            if (layer.areas[id].alive) checkArea(layer, id, out);
        checkAdjacency(layer, out);
        if (layer.isPart()) checkSceneIds(layer, out);
    }
    return out;
}

void validateOrThrow(const Scene& scene) {
    auto problems = validate(scene);
    if (!problems.empty()) throw ValidationError(std::move(problems));
}

}  // namespace lacet
