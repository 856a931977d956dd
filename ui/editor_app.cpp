#include "ui/editor_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/geometric.hpp>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "io/image_file.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "ui/overlay_renderer.h"
#include "ui/script_player.h"
#include "ui/terrain_renderer.h"

namespace lacet::ui {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

EditorApp* appOf(GLFWwindow* w) { return static_cast<EditorApp*>(glfwGetWindowUserPointer(w)); }

// Framebuffer pixels per window coordinate (cursor positions are in window coordinates).
glm::dvec2 framebufferScale(GLFWwindow* w) {
    int fw = 0, fh = 0, ww = 0, wh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    glfwGetWindowSize(w, &ww, &wh);
    return ww > 0 && wh > 0 ? glm::dvec2(double(fw) / ww, double(fh) / wh) : glm::dvec2(1.0);
}

double segmentDistance(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(p - (a + t * ab));
}

// Picked by the overlay within this many pixels.
constexpr double kPickPixels = 10.0;

const glm::vec4 kOnCurve(1.0f, 0.85f, 0.1f, 1.0f), kControl(0.2f, 0.9f, 1.0f, 1.0f), kNode(1.0f, 0.25f, 0.2f, 1.0f),
    kPolygon(1.0f, 1.0f, 1.0f, 0.55f), kSelected(1.0f, 0.4f, 1.0f, 1.0f), kDrawing(0.3f, 1.0f, 0.3f, 1.0f);

}  // namespace

EditorApp::EditorApp(const EditorOptions& options) : options_(options) {
    sessionParams_.cacheTiles = options.cacheTiles;
    if (!glfwInit()) throw std::runtime_error("lacet edit: cannot initialise GLFW (no display?)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_DEPTH_BITS, 24);
    window_ = glfwCreateWindow(options.width, options.height, "Lacet", nullptr, nullptr);
    if (!window_) {
        glfwTerminate();
        throw std::runtime_error("lacet edit: cannot open an OpenGL 4.1 core window");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(options.vsync && options.script.empty() ? 1 : 0);
    glfwSetWindowUserPointer(window_, this);
    // Our callbacks first: ImGui's backend chains to them.
    glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
        if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
        double x = 0.0, y = 0.0;
        glfwGetCursorPos(w, &x, &y);
        const glm::dvec2 scale = framebufferScale(w);
        InputEvent e;
        e.type = action == GLFW_PRESS ? InputEvent::Type::MouseDown : InputEvent::Type::MouseUp;
        e.x = x * scale.x, e.y = y * scale.y;
        e.button = button == GLFW_MOUSE_BUTTON_LEFT ? 0 : button == GLFW_MOUSE_BUTTON_RIGHT ? 1 : 2;
        e.mods = mods;
        appOf(w)->push(e);
    });
    glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
        const glm::dvec2 scale = framebufferScale(w);
        InputEvent e;
        e.type = InputEvent::Type::MouseMove;
        e.x = x * scale.x, e.y = y * scale.y;
        appOf(w)->push(e);
    });
    glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
        if (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse) return;
        InputEvent e;
        e.type = InputEvent::Type::Scroll;
        e.y = dy;
        appOf(w)->push(e);
    });
    glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
        if (action == GLFW_RELEASE || (ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureKeyboard)) return;
        if (action == GLFW_REPEAT && key != GLFW_KEY_Z && key != GLFW_KEY_Y) return;  // held keys repeat undo/redo only
        InputEvent e;
        e.type = InputEvent::Type::Key;
        e.key = key;
        e.mods = mods;
        appOf(w)->push(e);
    });
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 410 core");
    terrain_ = std::make_unique<TerrainRenderer>();
    overlay_ = std::make_unique<OverlayRenderer>();
    loadInitialDocument();
    if (!options_.script.empty()) script_ = std::make_unique<ScriptPlayer>(options_.script, options_.outDir);
}

EditorApp::~EditorApp() {
    script_.reset();
    overlay_.reset();
    terrain_.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
}

void EditorApp::loadInitialDocument() {
    SceneDocument doc;
    const std::string pbf = options_.andorraDir + "/andorra-2021-04-14.osm.pbf";
    const std::string dem = options_.andorraDir + "/N42E001.hgt.zip";
    if (!options_.scene.empty()) {
        doc = loadScene(options_.scene);
        scenePath_ = options_.scene;
        log_["scene"] = options_.scene;
    } else if (std::filesystem::exists(pbf) && std::filesystem::exists(dem)) {
        // Andorra (© OpenStreetMap contributors, ODbL; SRTM).
        ImportOptions io;
        io.dem = {"/vsizip/" + dem + "/N42E001.hgt"};
        io.vectors = {pbf};
        ImportReport report;
        doc = importScene(io, report);
        log_["scene"] = "andorra";
    } else {
        doc.scene = makeSyntheticScene({1, options_.syntheticCurves});
        doc.dem = makeSyntheticDem(doc.scene, {1, 5000});
        log_["scene"] = "synthetic";
        log_["synthetic_curves"] = options_.syntheticCurves;
    }
    const Box ext = doc.scene.extent;
    resetSession(std::move(doc));
    camera_.target = glm::dvec3(ext.center().x, ext.center().y, 0.0);
    camera_.target.z = session_->displayedHeight(ext.center());
    camera_.distance = 0.8 * ext.size().x;
    camera_.pitch = 0.9;
    camera_.yaw = 0.0;
    for (const Layer& l : session_->document().scene.layers)
        if (l.kind == LayerKind::Roads) {
            currentLayer_ = LayerId(&l - session_->document().scene.layers.data());
            layerVisible_.assign(layerVisible_.size(), 0);
            layerVisible_[currentLayer_] = 1;
            break;
        }
}

void EditorApp::resetSession(SceneDocument doc) {
    if (doc.scene.layers.empty()) throw std::runtime_error("lacet edit: the scene has no layer to edit");
    terrain_->reset();
    if (session_) sessionParams_ = session_->params();  // the knobs the user set stay
    sessionParams_.appearance.hiddenLayers.clear();
    sessionParams_.elevation.hiddenLayers.clear();
    session_.reset();
    session_ = std::make_unique<EditSession>(std::move(doc), sessionParams_);
    demRange_.reset();
    const std::size_t layers = session_->document().scene.layers.size();
    layerVisible_.assign(layers, 0);
    layerLocked_.assign(layers, 0);
    if (currentLayer_ >= layers) currentLayer_ = 0;
    layerVisible_[currentLayer_] = 1;
    selected_ = dragging_ = {};
    drawing_.clear();
    // First frame: the root's tile, so that every later leaf has an ancestor to show.
    session_->frame({camera_.position().x, camera_.position().y, 1e9}, 0.0);
}

void EditorApp::status(const std::string& message) {
    status_ = message;
    if (script_) log_["messages"].push_back(message);
}

glm::dvec3 EditorApp::groundPoint(Vec2 p) const { return {p.x, p.y, session_->displayedHeight(p)}; }

std::optional<glm::dvec2> EditorApp::project(glm::dvec3 world) const { return camera_.project(world, width_, height_, clip_); }

double EditorApp::viewerHeight() const {
    const glm::dvec3 eye = camera_.position();
    return std::max(1.0, eye.z - session_->displayedHeight({eye.x, eye.y}));
}

std::optional<glm::dvec3> EditorApp::terrainAt(double x, double y) const {
    const int i = int(std::floor(x)), j = height_ - 1 - int(std::floor(y));
    if (i < 0 || j < 0 || i >= width_ || j >= height_ || depth_.size() != std::size_t(width_) * std::size_t(height_)) return std::nullopt;
    const float d = depth_[std::size_t(j) * std::size_t(width_) + std::size_t(i)];
    if (d >= 1.0f) return std::nullopt;  // the sky
    return renderedCamera_.unproject(x, y, double(d), width_, height_, renderedClip_);
}

Pick EditorApp::pick(double x, double y, bool verticesOnly) const {
    Pick best;
    if (layerLocked_[currentLayer_]) return best;
    const Layer& layer = session_->document().scene.layers[currentLayer_];
    const glm::dvec2 m(x, y);
    // The overlay is the last frame's: skip what an edit since (an undo, a deletion) took away.
    auto alive = [&](const Pick& p) {
        if (p.layer != currentLayer_) return false;
        if (p.kind == Pick::Kind::Node) return p.id < layer.nodes.size() && layer.nodes[p.id].alive;
        return p.id < layer.curves.size() && layer.curves[p.id].alive &&
               (p.kind != Pick::Kind::Vertex || p.index + 1 < layer.curves[p.id].vertices.size());
    };
    for (const OverlayItem& item : overlayItems_) {
        const double d = glm::length(item.pixel - m);
        if (d > kPickPixels || !alive(item.pick)) continue;
        // Nodes win over vertices at the same place (a curve's end vertex is its node).
        const double score = d - (item.pick.kind == Pick::Kind::Node ? 0.5 : 0.0);
        if (score < best.pixels) best = item.pick, best.pixels = score;
    }
    if (best.kind != Pick::Kind::None || verticesOnly) return best;
    // A curve: the nearest control polygon segment on screen.
    for (const ElementId id : overlayCurves_) {
        if (!alive({Pick::Kind::Curve, currentLayer_, id, 0, 0.0})) continue;
        const Curve& c = layer.curves[id];
        std::optional<glm::dvec2> prev;
        for (const Vertex& v : c.vertices) {
            const auto p = project(groundPoint(v.p));
            if (p && prev) {
                const double d = segmentDistance(m, *prev, *p);
                if (d < kPickPixels && d < best.pixels) best = {Pick::Kind::Curve, currentLayer_, id, 0, d};
            }
            prev = p;
        }
    }
    return best;
}

void EditorApp::execute(const Command& c, bool merge) {
    const LayerId layer = std::visit([](const auto& cmd) { return cmd.layer; }, c);
    if (layer < layerLocked_.size() && layerLocked_[layer]) {
        status("Refused: the layer is locked");
        return;
    }
    try {
        lastCommand_ = session_->execute(c, merge);
        ++commands_;
        if (script_) log_["commands"].push_back({{"apply_ms", lastCommand_.applyMs}, {"update_ms", lastCommand_.updateMs},
                                                  {"changed_quads", lastCommand_.changedQuads}, {"dirty_tiles", lastCommand_.dirtyTiles}});
    } catch (const std::exception& e) {
        status(std::string("Refused: ") + e.what());
    }
}

void EditorApp::handle(const InputEvent& e) {
    switch (e.type) {
        case InputEvent::Type::MouseDown: onMouseDown(e); break;
        case InputEvent::Type::MouseMove: onMouseMove(e); break;
        case InputEvent::Type::MouseUp: onMouseUp(e); break;
        case InputEvent::Type::Scroll:
            // Orbit: scale the distance; fly: move along the view by a share of the height.
            if (camera_.fly) camera_.move(0.2 * e.y * std::max(2.0, viewerHeight()), 0.0, 0.0);
            else camera_.zoom(std::pow(0.85, e.y), 2.0);
            break;
        case InputEvent::Type::Key: onKey(e); break;
    }
}

void EditorApp::onMouseDown(const InputEvent& e) {
    mouse_ = lastMouse_ = {e.x, e.y};
    if (e.button == 1) {
        orbiting_ = true;
        return;
    }
    if (e.button == 2 || (e.mods & GLFW_MOD_SHIFT)) {
        panning_ = true;
        return;
    }
    const Layer& layer = session_->document().scene.layers[currentLayer_];
    switch (tool_) {
        case Tool::Select: {
            const Pick p = pick(e.x, e.y, false);
            if (p.kind == Pick::Kind::None) {
                selected_ = {};
                panning_ = true;  // a drag on the ground pans
                return;
            }
            if (p.kind == Pick::Kind::Vertex || p.kind == Pick::Kind::Node) {
                dragging_ = p;
                dragMoved_ = false;
            }
            selected_ = p;
            if (p.kind == Pick::Kind::Node) {
                // The selection shows a curve of the node, for the properties panel.
                const Node& n = layer.nodes[p.id];
                if (!n.curves.empty()) selected_ = {Pick::Kind::Curve, p.layer, n.curves.front(), 0, 0.0};
            } else if (p.kind == Pick::Kind::Vertex) {
                selected_.kind = Pick::Kind::Curve;
            }
            break;
        }
        case Tool::Insert: {
            const Pick p = pick(e.x, e.y, false);
            const auto at = terrainAt(e.x, e.y);
            if (p.kind != Pick::Kind::Curve || !at) {
                status("Insert: click on a curve of the current layer");
                return;
            }
            // Before the vertex that ends the nearest control polygon segment.
            const Curve& c = layer.curves[p.id];
            std::size_t index = 1;
            double best = 1e30;
            for (std::size_t k = 1; k < c.vertices.size(); ++k) {
                const auto a = project(groundPoint(c.vertices[k - 1].p)), b = project(groundPoint(c.vertices[k].p));
                if (!a || !b) continue;
                const double d = segmentDistance({e.x, e.y}, *a, *b);
                if (d < best) best = d, index = k;
            }
            execute(InsertVertexCmd{currentLayer_, p.id, index, Vertex{Vec2(at->x, at->y), true, false}});
            selected_ = {Pick::Kind::Curve, currentLayer_, p.id, 0, 0.0};
            break;
        }
        case Tool::DeletePoint: {
            const Pick p = pick(e.x, e.y, true);
            if (p.kind != Pick::Kind::Vertex) {
                status("Delete point: click on a control point or an inner on-curve vertex");
                return;
            }
            execute(DeleteVertexCmd{currentLayer_, p.id, p.index});
            break;
        }
        case Tool::Draw: {
            if (layerLocked_[currentLayer_]) {
                status("The current layer is locked");
                return;
            }
            const Pick p = pick(e.x, e.y, true);
            if (p.kind == Pick::Kind::Node) {
                drawing_.push_back({layer.nodes[p.id].p, p.id});  // snapped: the road joins this node
            } else if (const auto at = terrainAt(e.x, e.y)) {
                drawing_.push_back({Vec2(at->x, at->y), kNoElement});
            }
            break;
        }
    }
}

void EditorApp::onMouseMove(const InputEvent& e) {
    mouse_ = {e.x, e.y};
    const glm::dvec2 d = mouse_ - lastMouse_;
    lastMouse_ = mouse_;
    if (orbiting_) {
        camera_.orbit(d.x * 0.005, d.y * 0.005);
    } else if (panning_) {
        if (camera_.fly) {  // over the ground, at a speed that follows the height
            const double k = 2.0 * std::max(2.0, viewerHeight()) / double(height_);
            const glm::dvec3 ahead(std::sin(camera_.yaw), std::cos(camera_.yaw), 0.0);
            camera_.flyPosition += (camera_.right() * -d.x + ahead * d.y) * k;
        } else {
            camera_.pan(-d.x / double(height_), d.y / double(height_));
        }
    } else if (dragging_.kind != Pick::Kind::None) {
        const auto at = terrainAt(e.x, e.y);
        if (!at) return;
        const Vec2 p(at->x, at->y);
        // The first move of a drag starts a new undo step; the next ones merge into it.
        if (dragging_.kind == Pick::Kind::Vertex) execute(MoveVertexCmd{dragging_.layer, dragging_.id, dragging_.index, p}, dragMoved_);
        else execute(MoveNodeCmd{dragging_.layer, dragging_.id, p}, dragMoved_);
        dragMoved_ = true;
    }
}

void EditorApp::onMouseUp(const InputEvent& e) {
    mouse_ = {e.x, e.y};
    orbiting_ = panning_ = false;
    dragging_ = {};
}

void EditorApp::onKey(const InputEvent& e) {
    const bool ctrl = (e.mods & GLFW_MOD_CONTROL) != 0, shift = (e.mods & GLFW_MOD_SHIFT) != 0;
    if (ctrl && (e.key == GLFW_KEY_Y || (e.key == GLFW_KEY_Z && shift))) {
        if (!session_->redo(&lastCommand_)) status("Nothing to redo");
    } else if (ctrl && e.key == GLFW_KEY_Z) {
        if (!session_->undo(&lastCommand_)) status("Nothing to undo");
        selected_ = dragging_ = {};
    } else if (ctrl && e.key == GLFW_KEY_S) {
        save();
    } else if (e.key == GLFW_KEY_ESCAPE) {
        if (!drawing_.empty()) drawing_.clear();
        else selected_ = {};
    } else if (e.key == GLFW_KEY_ENTER || e.key == GLFW_KEY_KP_ENTER) {
        finishDrawing();
    } else if (e.key == GLFW_KEY_DELETE && selected_.kind == Pick::Kind::Curve) {
        execute(DeleteCurveCmd{selected_.layer, selected_.id});
        selected_ = {};
    } else if (e.key == GLFW_KEY_F && !ctrl) {
        camera_.setFly(!camera_.fly);
    }
}

void EditorApp::finishDrawing() {
    if (drawing_.size() < 2) {
        drawing_.clear();
        return;
    }
    // A smooth curve through the clicked points: Catmull-Rom segments as cubic Bezier pieces.
    std::vector<Vec2> p;
    for (const DrawPoint& d : drawing_) p.push_back(d.p);
    Curve c;
    for (std::size_t k = 0; k + 1 < p.size(); ++k) {
        const Vec2 a = p[k], b = p[k + 1];
        const Vec2 before = k > 0 ? p[k - 1] : a, after = k + 2 < p.size() ? p[k + 2] : b;
        if (k == 0) c.vertices.push_back({a, true, false});
        c.vertices.push_back({a + (b - before) / 6.0, false, false});
        c.vertices.push_back({b - (after - a) / 6.0, false, false});
        c.vertices.push_back({b, true, false});
    }
    c.w = newWidth_;
    c.wf = std::max(newFootprint_, newWidth_);
    c.cls = std::uint16_t(std::clamp(newClass_, 0, 65535));
    const std::size_t curvesBefore = session_->document().scene.layers[currentLayer_].curves.size();
    const std::size_t depthBefore = session_->undoDepth();
    session_->beginGroup();
    auto endpoint = [&](const DrawPoint& d) -> ElementId {
        if (d.node != kNoElement) return d.node;
        execute(AddNodeCmd{currentLayer_, d.p});
        return ElementId(session_->document().scene.layers[currentLayer_].nodes.size() - 1);
    };
    c.start = endpoint(drawing_.front());
    c.end = endpoint(drawing_.back());
    execute(AddCurveCmd{currentLayer_, c});
    session_->endGroup();
    drawing_.clear();
    if (session_->document().scene.layers[currentLayer_].curves.size() == curvesBefore) {
        // The curve was refused (the status says why): take back the nodes made for it.
        if (session_->undoDepth() > depthBefore) session_->undo(&lastCommand_);
        return;
    }
    selected_ = {Pick::Kind::Curve, currentLayer_, ElementId(curvesBefore), 0, 0.0};
}

void EditorApp::save(const std::string& path) {
    const std::string target = !path.empty() ? path : !scenePath_.empty() ? scenePath_ : options_.outDir + "/scene.gpkg";
    try {
        const auto t0 = Clock::now();
        session_->save(target);
        scenePath_ = target;
        status("Saved " + target + " in " + std::to_string(int(msSince(t0))) + " ms");
    } catch (const std::exception& e) {
        status(std::string("Not saved: ") + e.what());
    }
}

void EditorApp::open(const std::string& path) {
    resetSession(loadScene(path));
    scenePath_ = path;
    status("Opened " + path);
}

void EditorApp::requestScreenshot(const std::string& path, bool panels, bool overlay) {
    screenshots_.push_back({path, panels, overlay});
}

void EditorApp::writeScreenshot(const Screenshot& s) {
    std::vector<std::uint8_t> rgba(std::size_t(width_) * std::size_t(height_) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    std::vector<std::uint8_t> rgb(std::size_t(width_) * std::size_t(height_) * 3);
    const std::uint8_t bg[3] = {std::uint8_t(std::lround(background.r * 255.0f)), std::uint8_t(std::lround(background.g * 255.0f)),
                                std::uint8_t(std::lround(background.b * 255.0f))};
    std::size_t backgroundPixels = 0;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const std::uint8_t* src = &rgba[(std::size_t(height_ - 1 - y) * std::size_t(width_) + std::size_t(x)) * 4];
            std::uint8_t* dst = &rgb[(std::size_t(y) * std::size_t(width_) + std::size_t(x)) * 3];
            std::copy(src, src + 3, dst);
            backgroundPixels += src[0] == bg[0] && src[1] == bg[1] && src[2] == bg[2];
        }
    writeImage8(s.path, width_, height_, 3, rgb);
    log_["screenshots"].push_back({{"file", s.path}, {"frame", frames_}, {"width", width_}, {"height", height_},
                                   {"background_pixels", backgroundPixels}, {"drawn_quads", terrain_->stats().drawn},
                                   {"fallback_quads", terrain_->stats().fallback}, {"pending_tiles", lastFrame_.pending}});
}

void EditorApp::drawOverlay() {
    overlay_->clear();
    overlayItems_.clear();
    overlayCurves_.clear();
    const Scene& scene = session_->document().scene;
    const glm::dvec3 eye = camera_.position();
    // The shown layers' curves near the view (and the selection), within a point budget.
    const double radius = 4.0 * viewerHeight() + 400.0;
    const Vec2 centre = camera_.fly ? Vec2(eye.x, eye.y) : Vec2(camera_.target.x, camera_.target.y);
    auto near = [&](const Curve& c) {
        for (const Vertex& v : c.vertices)
            if (glm::length(v.p - centre) < radius) return true;
        return false;
    };
    std::size_t points = 0;
    for (LayerId li = 0; li < scene.layers.size(); ++li) {
        if (!layerVisible_[li]) continue;
        // The current layer's points can be picked; other shown layers' are drawn smaller and dimmer.
        const bool current = li == currentLayer_;
        const float scale = current ? 1.0f : 0.6f;
        const Layer& layer = scene.layers[li];
        for (ElementId id = 0; id < layer.curves.size() && points < 20000; ++id) {
            const Curve& c = layer.curves[id];
            const bool selected = selected_.kind == Pick::Kind::Curve && selected_.layer == li && selected_.id == id;
            if (!c.alive || (!selected && !near(c))) continue;
            if (current) overlayCurves_.push_back(id);
            auto add = [&](const glm::dvec3& world, const Pick& p, glm::vec4 colour, float size) {
                const auto px = project(world);
                if (!px || px->x < -20 || px->y < -20 || px->x > width_ + 20 || px->y > height_ + 20) return;
                if (!current) colour.a = 0.6f;
                overlay_->point(world, colour, size * scale);
                ++points;
                if (current) overlayItems_.push_back({p, *px});
            };
            glm::dvec3 prev{};
            for (std::size_t k = 0; k < c.vertices.size(); ++k) {
                const glm::dvec3 w = groundPoint(c.vertices[k].p) + glm::dvec3(0.0, 0.0, 0.5);
                if (k > 0) overlay_->line(prev, w, selected ? kSelected : kPolygon);
                prev = w;
                if (k == 0 || k + 1 == c.vertices.size()) continue;  // the nodes, below
                add(w, {Pick::Kind::Vertex, li, id, k, 0.0}, c.vertices[k].onCurve ? kOnCurve : kControl, selected ? 11.0f : 8.0f);
            }
            for (const ElementId n : {c.start, c.end}) add(groundPoint(layer.nodes[n].p), {Pick::Kind::Node, li, n, 0, 0.0}, kNode, 10.0f);
        }
    }
    for (std::size_t k = 0; k < drawing_.size(); ++k) {
        const glm::dvec3 w = groundPoint(drawing_[k].p) + glm::dvec3(0.0, 0.0, 0.5);
        overlay_->point(w, kDrawing, 10.0f);
        if (k > 0) overlay_->line(groundPoint(drawing_[k - 1].p) + glm::dvec3(0.0, 0.0, 0.5), w, kDrawing);
    }
    const double aspect = double(width_) / double(height_);
    overlay_->draw(eye, camera_.projection(aspect, clip_) * camera_.view());
}

int EditorApp::run() {
    while (true) {
        glfwPollEvents();
        if (glfwWindowShouldClose(window_)) {
            if (script_ || !session_->modified() || closing_) break;
            confirmClose_ = true;  // the prompt below decides
            glfwSetWindowShouldClose(window_, GLFW_FALSE);
        }
        glfwGetFramebufferSize(window_, &width_, &height_);
        if (width_ <= 0 || height_ <= 0) {  // minimised
            glfwWaitEvents();
            continue;
        }
        if (script_ && !script_->step(*this)) break;
        std::vector<InputEvent> events;
        events.swap(events_);
        for (const InputEvent& e : events) handle(e);
        if (camera_.fly && !script_ && !ImGui::GetIO().WantCaptureKeyboard) {
            const double speed = std::max(2.0, viewerHeight()) * (glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) ? 0.08 : 0.02);
            auto held = [&](int k) { return glfwGetKey(window_, k) == GLFW_PRESS ? 1.0 : 0.0; };
            camera_.move(speed * (held(GLFW_KEY_W) - held(GLFW_KEY_S)), speed * (held(GLFW_KEY_D) - held(GLFW_KEY_A)),
                         speed * (held(GLFW_KEY_E) - held(GLFW_KEY_Q)));
        }

        // The live loop: refine for the camera, make the visible tiles within the budget.
        const glm::dvec3 eye = camera_.position();
        const double h = viewerHeight();
        clip_ = Camera::clipRange(h);
        const glm::dvec3 viewer(eye.x, eye.y, h);
        velocity_ = frames_ > 0 ? eye - lastEye_ : glm::dvec3(0.0);
        lastEye_ = eye;
        std::optional<glm::dvec3> predicted;
        if (glm::length(velocity_) > 1e-3 * h) {
            // Half a second ahead at 60 frames per second (§8: prefetch along the predicted path).
            const glm::dvec3 ahead = eye + velocity_ * 30.0;
            predicted = glm::dvec3(ahead.x, ahead.y, std::max(1.0, h + (ahead.z - eye.z)));
        }
        const double aspect = double(width_) / double(height_);
        if (!demRange_) demRange_ = frustumHeightRange(*session_->document().dem);
        const QuadVisibility visible = frustumVisibility(camera_, aspect, clip_, *demRange_);
        auto t0 = Clock::now();
        session_->setRefineBudget(0.5 * options_.budgetMs);  // 0 (no budget): refine completely
        lastFrame_ = session_->frame(viewer, options_.budgetMs, visible, predicted);
        lastUpdateMs_ = msSince(t0);
        tilesProduced_ += lastFrame_.produced + lastFrame_.prefetched;

        t0 = Clock::now();
        glViewport(0, 0, width_, height_);
        glClearColor(background.r, background.g, background.b, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        TerrainView tv;
        tv.camera = &camera_;
        tv.width = width_, tv.height = height_;
        tv.clip = clip_;
        tv.heightAboveGround = h;
        tv.viewParams = session_->params().view;
        tv.visible = &visible;
        terrain_->draw(*session_, tv);
        // The depth buffer of what the user sees: picks of the next frame's input read it.
        depth_.resize(std::size_t(width_) * std::size_t(height_));
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, depth_.data());
        renderedCamera_ = camera_;
        renderedClip_ = clip_;
        std::vector<Screenshot> shots;
        shots.swap(screenshots_);
        for (const Screenshot& s : shots)
            if (!s.overlay && !s.panels) writeScreenshot(s);
        drawOverlay();
        for (const Screenshot& s : shots)
            if (s.overlay && !s.panels) writeScreenshot(s);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        drawPanels();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        for (const Screenshot& s : shots)
            if (s.panels) writeScreenshot(s);
        lastRenderMs_ = msSince(t0);
        if (script_) {
            const TerrainStats& ts = terrain_->stats();
            log_["frames"].push_back({{"frame", frames_}, {"update_ms", lastUpdateMs_}, {"refine_ms", lastFrame_.refineMs},
                                      {"produce_ms", lastFrame_.produceMs}, {"produced", lastFrame_.produced},
                                      {"prefetched", lastFrame_.prefetched}, {"pending", lastFrame_.pending},
                                      {"view_quads", lastFrame_.viewQuads}, {"culled", lastFrame_.culled}, {"replaced", lastFrame_.replaced},
                                      {"drawn", ts.drawn}, {"fallback", ts.fallback}, {"missing", ts.missing},
                                      {"uploads", ts.uploads}, {"cached", lastFrame_.cached}, {"gpu_tiles", ts.gpuTiles},
                                      {"render_ms", lastRenderMs_}, {"viewer_height_m", h}});
        }
        glfwSwapBuffers(window_);
        ++frames_;
    }
    if (script_) script_->finish(*this);
    return 0;
}

}  // namespace lacet::ui
