#include "editor/editing_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>
#include <variant>

#include <glm/geometric.hpp>

#include "io/scene_overlay.h"
#include "model/segment.h"

namespace lacet {
namespace {

LayerId layerOf(const Command& c) {
    return std::visit([](const auto& cmd) { return cmd.layer; }, c);
}

// Overlay points within this margin outside the viewport are still drawn (pixels).
constexpr double kOverlayMarginPixels = 20.0;
// Overlay lines and points hang this far above the displayed ground (metres), above the surface.
constexpr double kOverlayLiftMetres = 0.5;
// The overlay shows curves with a vertex within this many viewer heights plus this many metres of
// where the camera looks.
constexpr double kOverlayRadiusHeights = 4.0, kOverlayRadiusMetres = 400.0;

}  // namespace

EditingController::EditingController(EditSession& session) : session_(session) {
    const std::size_t layers = session_.document().scene.layers.size();
    if (layers == 0) throw std::invalid_argument("EditingController: the scene has no layer to edit");
    shown_.assign(layers, 0);
    locked_.assign(layers, 0);
    // The roads are what users edit most: the first roads layer is the current one, else the first.
    const auto& all = session_.document().scene.layers;
    const auto roads = std::find_if(all.begin(), all.end(), [](const Layer& l) { return l.kind == LayerKind::Roads; });
    current_ = roads == all.end() ? 0 : LayerId(roads - all.begin());
    shown_[current_] = 1;
}

void EditingController::message(const std::string& text) {
    if (onMessage) onMessage(text);
}

void EditingController::setCurrentLayer(LayerId layer) {
    if (layer >= shown_.size()) throw std::out_of_range("EditingController::setCurrentLayer(): no layer " + std::to_string(layer));
    current_ = layer;
    shown_[layer] = 1;
    selected_ = dragging_ = {};
    drawn_.clear();
    drawnNodes_.clear();
}

void EditingController::setPointsShown(LayerId layer, bool shown) {
    if (layer >= shown_.size()) throw std::out_of_range("EditingController::setPointsShown(): no layer " + std::to_string(layer));
    shown_[layer] = shown;
}

void EditingController::setLayerLocked(LayerId layer, bool locked) {
    if (layer >= locked_.size()) throw std::out_of_range("EditingController::setLayerLocked(): no layer " + std::to_string(layer));
    locked_[layer] = locked;
    if (locked && layer == current_) {
        dragging_ = {};
        drawn_.clear();
        drawnNodes_.clear();
    }
}

void EditingController::setTool(Tool tool) {
    if (tool != tool_) drawn_.clear(), drawnNodes_.clear();
    tool_ = tool;
}

bool EditingController::execute(const Command& command, bool merge) {
    if (layerLocked(layerOf(command))) {
        message("Refused: the layer is locked");
        return false;
    }
    try {
        lastCommand_ = session_.execute(command, merge);
    } catch (const std::exception& e) {
        message(std::string("Refused: ") + e.what());
        return false;
    }
    ++commands_;
    if (onCommand) onCommand(lastCommand_);
    return true;
}

bool EditingController::undo() {
    selected_ = dragging_ = {};
    if (session_.undo(&lastCommand_)) return true;
    message("Nothing to undo");
    return false;
}

bool EditingController::redo() {
    if (session_.redo(&lastCommand_)) return true;
    message("Nothing to redo");
    return false;
}

bool EditingController::deleteSelection() {
    if (selected_.kind != Pick::Kind::Curve) return false;
    const bool done = execute(DeleteCurveCmd{selected_.layer, selected_.id});
    selected_ = {};
    return done;
}

bool EditingController::setRoundabout(ElementId node, float radius) {
    return execute(SetRoundaboutCmd{current_, node, radius});
}

EditingController::Held EditingController::held(LayerId layer, ElementKind kind, ElementId file) const {
    Held out;
    session_.forEachHeldDocument([&](const SceneDocument& doc) {
        if (out.layer || layer >= doc.scene.layers.size()) return;
        const Layer& l = doc.scene.layers[layer];
        if (const ElementId id = localIdOf(l, kind, file); id != kNoElement) out = {&l, id};
    });
    return out;
}

const Curve* EditingController::selectedCurve() const {
    if (selected_.kind != Pick::Kind::Curve) return nullptr;
    const Held h = held(selected_.layer, ElementKind::Curve, selected_.id);
    return h.layer && h.layer->curves[h.id].alive ? &h.layer->curves[h.id] : nullptr;
}

bool EditingController::setSelectedWidth(float w) {
    const Curve* c = selectedCurve();
    return c && execute(SetCurveWidthCmd{selected_.layer, selected_.id, w, std::max(w, c->wf)});
}

bool EditingController::setSelectedFootprint(float wf) {
    const Curve* c = selectedCurve();
    return c && execute(SetCurveWidthCmd{selected_.layer, selected_.id, c->w, wf});
}

bool EditingController::setSelectedClass(int cls) {
    return selectedCurve() && execute(SetCurveClassCmd{selected_.layer, selected_.id, std::uint16_t(std::clamp(cls, 0, 65535))});
}

bool EditingController::setSelectedFlag(std::uint16_t bit, bool on) {
    const Curve* c = selectedCurve();
    return c && execute(SetCurveFlagsCmd{selected_.layer, selected_.id, std::uint16_t(on ? (c->flags | bit) : (c->flags & ~bit))});
}

std::size_t EditingController::selectedBridges() const {
    if (!selectedCurve()) return 0;
    // The session's tree: the document's (a lazy session's top holds the curves wide enough for it).
    const ElementId id = localIdOf(session_.document().scene.layers.at(selected_.layer), ElementKind::Curve, selected_.id);
    if (id == kNoElement) return 0;
    const Quadtree& qt = session_.quadtree();
    std::size_t bridges = 0;
    for (AncestorId a : qt.expansionOf(selected_.layer, id)) bridges += (qt.ancestorCurve(selected_.layer, a).flags & kBridge) != 0;
    return bridges;
}

void EditingController::cancel() {
    if (!drawn_.empty()) drawn_.clear(), drawnNodes_.clear();
    else selected_ = {};
}

bool EditingController::finishDrawing() {
    const std::vector<Vec2> points = std::move(drawn_);
    const std::vector<ElementId> nodes = std::move(drawnNodes_);
    drawn_.clear(), drawnNodes_.clear();
    if (points.size() < 2) return false;
    if (layerLocked(current_)) {
        message("Refused: the layer is locked");
        return false;
    }
    Curve c = curveThrough(points, newCurve);
    const std::size_t depthBefore = session_.undoDepth();
    // The ids the session gives (lazily, the file's: EditSession::nextId); kNoElement: refused.
    const auto nextId = [&](ElementKind kind) {
        try {
            return session_.nextId(current_, kind);
        } catch (const std::exception& e) {
            message(std::string("Refused: ") + e.what());
            return kNoElement;
        }
    };
    session_.beginGroup();
    auto endpoint = [&](std::size_t k) -> ElementId {
        if (nodes[k] != kNoElement) return nodes[k];  // snapped: the curve joins this node
        const ElementId id = nextId(ElementKind::Node);
        return id != kNoElement && execute(AddNodeCmd{current_, points[k]}) ? id : kNoElement;
    };
    c.start = endpoint(0);
    c.end = c.start != kNoElement ? endpoint(points.size() - 1) : kNoElement;
    const ElementId curve = c.end != kNoElement ? nextId(ElementKind::Curve) : kNoElement;
    const bool made = curve != kNoElement && execute(AddCurveCmd{current_, c});
    session_.endGroup();
    if (!made) {
        // The curve was refused (the message says why): take back the nodes made for it, for good.
        if (session_.undoDepth() > depthBefore) {
            session_.undo(&lastCommand_);
            session_.forgetRedo();
        }
        return false;
    }
    selected_ = {Pick::Kind::Curve, current_, curve, 0, 0.0};
    return true;
}

std::optional<glm::dvec2> EditingController::project(glm::dvec3 world) const {
    return view_.camera.project(world, view_.width, view_.height, view_.clip);
}

std::optional<glm::dvec3> EditingController::groundAt(glm::dvec2 pixel) const {
    return view_.ground ? view_.ground(pixel) : groundAlongRay(session_, view_, pixel);
}

double EditingController::viewerHeight() const { return session_.heightAboveGround(view_.camera.position()); }

bool EditingController::pickable(const Pick& p) const {
    if (p.layer != current_) return false;
    const Held h = held(current_, p.kind == Pick::Kind::Node ? ElementKind::Node : ElementKind::Curve, p.id);
    if (!h.layer) return false;
    if (p.kind == Pick::Kind::Node) return h.layer->nodes[h.id].alive;
    const Curve& c = h.layer->curves[h.id];
    return c.alive && (p.kind != Pick::Kind::Vertex || p.index + 1 < c.vertices.size());
}

Pick EditingController::pick(glm::dvec2 pixel, bool pointsOnly) const {
    Pick best;
    if (layerLocked(current_)) return best;
    for (const OverlayPoint& item : overlay_.points) {
        if (item.pick.kind == Pick::Kind::None) continue;
        const double d = glm::length(item.pixel - pixel);
        if (d > kPickPixels || !pickable(item.pick)) continue;
        // Nodes win over vertices at the same place (a curve's end vertex is its node).
        const double score = d - (item.pick.kind == Pick::Kind::Node ? 0.5 : 0.0);
        if (score < best.pixels) best = item.pick, best.pixels = score;
    }
    if (best.kind != Pick::Kind::None || pointsOnly) return best;
    for (const ElementId id : overlay_.curves) {
        if (!pickable({Pick::Kind::Curve, current_, id, 0, 0.0})) continue;
        const Held h = held(current_, ElementKind::Curve, id);
        std::optional<glm::dvec2> prev;
        for (const Vertex& v : h.layer->curves[h.id].vertices) {
            const auto p = project(groundPoint(v.p));
            if (p && prev) {
                const double d = distanceToSegment(pixel, *prev, *p);
                if (d < kPickPixels && d < best.pixels) best = {Pick::Kind::Curve, current_, id, 0, d};
            }
            prev = p;
        }
    }
    return best;
}

std::size_t EditingController::insertIndex(const Curve& c, glm::dvec2 pixel) const {
    // Before the vertex that ends the control polygon segment nearest on screen.
    std::size_t index = 1;
    double best = 1e30;
    for (std::size_t k = 1; k < c.vertices.size(); ++k) {
        const auto a = project(groundPoint(c.vertices[k - 1].p)), b = project(groundPoint(c.vertices[k].p));
        if (!a || !b) continue;
        const double d = distanceToSegment(pixel, *a, *b);
        if (d < best) best = d, index = k;
    }
    return index;
}

bool EditingController::press(glm::dvec2 pixel) {
    switch (tool_) {
        case Tool::Select: {
            const Pick p = pick(pixel, false);
            if (p.kind == Pick::Kind::None) {
                selected_ = {};
                return false;
            }
            if (p.kind == Pick::Kind::Vertex || p.kind == Pick::Kind::Node) {
                dragging_ = p;
                dragMoved_ = false;
            }
            selected_ = p;
            if (p.kind == Pick::Kind::Node) {
                // The selection shows a curve of the node, for the properties panel.
                const Held h = held(p.layer, ElementKind::Node, p.id);
                const Node& n = h.layer->nodes[h.id];
                if (!n.curves.empty()) selected_ = {Pick::Kind::Curve, p.layer, h.layer->sceneCurveId(n.curves.front()), 0, 0.0};
            } else if (p.kind == Pick::Kind::Vertex) {
                selected_.kind = Pick::Kind::Curve;
            }
            return true;
        }
        case Tool::Insert: {
            const Pick p = pick(pixel, false);
            const auto at = groundAt(pixel);
            if (p.kind != Pick::Kind::Curve || !at) {
                message("Insert: click on a curve of the current layer");
                return true;
            }
            const Held h = held(current_, ElementKind::Curve, p.id);
            const std::size_t index = insertIndex(h.layer->curves[h.id], pixel);
            execute(InsertVertexCmd{current_, p.id, index, Vertex{Vec2(at->x, at->y), true, false}});
            selected_ = {Pick::Kind::Curve, current_, p.id, 0, 0.0};
            return true;
        }
        case Tool::DeletePoint: {
            const Pick p = pick(pixel, true);
            if (p.kind != Pick::Kind::Vertex) {
                message("Delete point: click on a control point or an inner on-curve vertex");
                return true;
            }
            execute(DeleteVertexCmd{current_, p.id, p.index});
            return true;
        }
        case Tool::Roundabout: {
            const Pick p = pick(pixel, true);
            if (p.kind != Pick::Kind::Node) {
                message("Roundabout: click on a junction node of the current layer");
                return true;
            }
            setRoundabout(p.id, roundaboutRadius);
            return true;
        }
        case Tool::Draw: {
            if (layerLocked(current_)) {
                message("The current layer is locked");
                return true;
            }
            const Pick p = pick(pixel, true);
            if (p.kind == Pick::Kind::Node) {
                const Held h = held(current_, ElementKind::Node, p.id);
                drawn_.push_back(h.layer->nodes[h.id].p);
                drawnNodes_.push_back(p.id);
            } else if (const auto at = groundAt(pixel)) {
                drawn_.push_back(Vec2(at->x, at->y));
                drawnNodes_.push_back(kNoElement);
            }
            return true;
        }
    }
    return false;
}

void EditingController::drag(glm::dvec2 pixel) {
    if (dragging_.kind == Pick::Kind::None) return;
    const auto at = groundAt(pixel);
    if (!at) return;
    const Vec2 p(at->x, at->y);
    const bool moved = dragging_.kind == Pick::Kind::Vertex
                           ? execute(MoveVertexCmd{dragging_.layer, dragging_.id, dragging_.index, p}, dragMoved_)
                           : execute(MoveNodeCmd{dragging_.layer, dragging_.id, p}, dragMoved_);
    dragMoved_ = dragMoved_ || moved;
}

const Overlay& EditingController::buildOverlay(std::size_t pointBudget) {
    overlay_ = {};
    const Scene& scene = session_.document().scene;
    const Camera& camera = view_.camera;
    const glm::dvec3 eye = camera.position();
    const double radius = kOverlayRadiusHeights * viewerHeight() + kOverlayRadiusMetres;
    const Vec2 centre = camera.fly ? Vec2(eye.x, eye.y) : Vec2(camera.target.x, camera.target.y);
    auto near = [&](const Curve& c) {
        return std::any_of(c.vertices.begin(), c.vertices.end(), [&](const Vertex& v) { return glm::length(v.p - centre) < radius; });
    };
    const glm::dvec3 lift(0.0, 0.0, kOverlayLiftMetres);
    std::size_t points = 0;
    // Each curve once, by its id in the file, from the first document or part that holds it.
    std::vector<std::unordered_set<ElementId>> seen(scene.layers.size());
    session_.forEachHeldDocument([&](const SceneDocument& doc) {
        for (LayerId li = 0; li < scene.layers.size() && li < doc.scene.layers.size(); ++li) {
            if (!pointsShown(li)) continue;
            const bool current = li == current_;
            const Layer& layer = doc.scene.layers[li];
            for (ElementId local = 0; local < layer.curves.size() && points < pointBudget; ++local) {
                const Curve& c = layer.curves[local];
                const ElementId id = layer.sceneCurveId(local);
                const bool selected = selected_.kind == Pick::Kind::Curve && selected_.layer == li && selected_.id == id;
                if (!c.alive || (!selected && !near(c)) || !seen[li].insert(id).second) continue;
                if (current) overlay_.curves.push_back(id);
                auto add = [&](const glm::dvec3& world, const Pick& p, OverlayPoint::Style style) {
                    const auto px = project(world);
                    const double m = kOverlayMarginPixels;
                    if (!px || px->x < -m || px->y < -m || px->x > view_.width + m || px->y > view_.height + m) return;
                    overlay_.points.push_back({style, world, current ? p : Pick{}, *px, current, selected});
                    ++points;
                };
                glm::dvec3 prev{};
                for (std::size_t k = 0; k < c.vertices.size(); ++k) {
                    const glm::dvec3 w = groundPoint(c.vertices[k].p) + lift;
                    if (k > 0) overlay_.lines.push_back({selected ? OverlayLine::Style::Selected : OverlayLine::Style::Polygon, prev, w});
                    prev = w;
                    if (k == 0 || k + 1 == c.vertices.size()) continue;  // the nodes, below
                    add(w, {Pick::Kind::Vertex, li, id, k, 0.0}, c.vertices[k].onCurve ? OverlayPoint::Style::OnCurve : OverlayPoint::Style::Control);
                }
                for (const ElementId n : {c.start, c.end})
                    add(groundPoint(layer.nodes[n].p), {Pick::Kind::Node, li, layer.sceneNodeId(n), 0, 0.0}, OverlayPoint::Style::Node);
            }
        }
    });
    for (std::size_t k = 0; k < drawn_.size(); ++k) {
        const glm::dvec3 w = groundPoint(drawn_[k]) + lift;
        overlay_.points.push_back({OverlayPoint::Style::Drawing, w, Pick{}, project(w).value_or(glm::dvec2(-1e9)), true, false});
        if (k > 0) overlay_.lines.push_back({OverlayLine::Style::Drawing, groundPoint(drawn_[k - 1]) + lift, w});
    }
    return overlay_;
}

std::optional<glm::dvec3> groundAlongRay(const EditSession& session, const PickView& view, glm::dvec2 pixel,
                                         const GroundRayParams& params) {
    const Ray ray = view.camera.ray(pixel.x, pixel.y, view.width, view.height);
    auto above = [&](double t) {
        const glm::dvec3 p = ray.origin + t * ray.direction;
        return p.z - session.displayedHeight({p.x, p.y});
    };
    double t0 = view.clip.x, h0 = above(t0);
    if (!(h0 > 0.0)) return std::nullopt;  // the eye is under the surface, or the height is not a number
    while (t0 < view.clip.y) {
        const double t1 = std::min(view.clip.y, t0 + std::max(params.minStepMetres, params.stepFraction * t0));
        const double h1 = above(t1);
        if (h1 <= 0.0) {
            double lo = t0, hi = t1;  // above at lo, on or under at hi
            while (hi - lo > params.precisionMetres) {
                const double mid = 0.5 * (lo + hi);
                (above(mid) > 0.0 ? lo : hi) = mid;
            }
            return ray.origin + hi * ray.direction;
        }
        t0 = t1;
    }
    return std::nullopt;
}

}  // namespace lacet
