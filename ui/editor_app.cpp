#include "ui/editor_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/geometric.hpp>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include "io/image_file.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "model/work_clock.h"
#include "ui/object_renderer.h"
#include "ui/overlay_renderer.h"
#include "ui/script_player.h"
#include "ui/terrain_renderer.h"

namespace lacet::ui {
namespace {

using Clock = std::chrono::steady_clock;

EditorApp* appOf(GLFWwindow* w) { return static_cast<EditorApp*>(glfwGetWindowUserPointer(w)); }

// Framebuffer pixels per window coordinate (cursor positions are in window coordinates).
glm::dvec2 framebufferScale(GLFWwindow* w) {
    int fw = 0, fh = 0, ww = 0, wh = 0;
    glfwGetFramebufferSize(w, &fw, &fh);
    glfwGetWindowSize(w, &ww, &wh);
    return ww > 0 && wh > 0 ? glm::dvec2(double(fw) / ww, double(fh) / wh) : glm::dvec2(1.0);
}

const glm::vec4 kOnCurve(1.0f, 0.85f, 0.1f, 1.0f), kControl(0.2f, 0.9f, 1.0f, 1.0f), kNode(1.0f, 0.25f, 0.2f, 1.0f),
    kPolygon(1.0f, 1.0f, 1.0f, 0.55f), kSelected(1.0f, 0.4f, 1.0f, 1.0f), kDrawing(0.3f, 1.0f, 0.3f, 1.0f);

}  // namespace

EditorApp::EditorApp(const EditorOptions& options, EditorDocument document) : options_(options) {
    sessionParams_.cacheTiles = options.cacheTiles;
    sessionParams_.backgroundMs = options.backgroundMs >= 0.0 ? options.backgroundMs : options.script.empty() ? kInteractiveBackgroundMs : 0.0;
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
    objects_ = std::make_unique<ObjectRenderer>();
    overlay_ = std::make_unique<OverlayRenderer>();
    scenePath_ = document.path;
    diskChecksum_ = document.storedChecksum;
    pyramid_.setFiles(options_.noPyramid ? std::string() : options_.pyramid, document.path);
    log_["scene"] = document.label;
    const Box ext = document.lazy ? loadSceneExtent(document.path) : document.document.scene.extent;
    resetSession(std::move(document.document), document.lazy ? document.path : std::string());
    camera_.target = glm::dvec3(ext.center().x, ext.center().y, 0.0);
    camera_.target.z = session_->displayedHeight(ext.center());
    camera_.distance = 0.8 * ext.size().x;
    camera_.pitch = 0.9;
    camera_.yaw = 0.0;
    if (!options_.script.empty()) script_ = std::make_unique<ScriptPlayer>(options_.script, options_.outDir);
    if (!document.message.empty()) status(document.message);
}

EditorApp::~EditorApp() {
    script_.reset();
    overlay_.reset();
    objects_.reset();
    terrain_.reset();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
}

void EditorApp::resetSession(SceneDocument doc, const std::string& lazyPath) {
    if (lazyPath.empty() && doc.scene.layers.empty()) throw std::runtime_error("lacet edit: the scene has no layer to edit");
    terrain_->reset();
    objects_->reset();
    std::optional<LayerId> current;
    Tool tool = Tool::Select;
    NewCurveStyle style;
    if (controller_) current = controller_->currentLayer(), tool = controller_->tool(), style = controller_->newCurve;
    if (session_) sessionParams_ = session_->params();  // the knobs the user set stay
    sessionParams_.appearance.hiddenLayers.clear();
    sessionParams_.elevation.hiddenLayers.clear();
    sessionParams_.objects.hiddenLayers.clear();
    controller_.reset();
    session_.reset();
    sessionParams_.demStream.budgetMiB = options_.demBudgetMiB;
    if (lazyPath.empty()) {
        session_ = std::make_unique<EditSession>(std::move(doc), sessionParams_);
    } else {
        LazyParams lazy;
        lazy.vectorBudgetMiB = options_.vectorBudgetMiB;
        lazy.partLevel = options_.partLevel;
        lazy.topElevationOnly = !pyramid_.path().empty();  // its appearance down to the part level from the pyramid
        session_ = std::make_unique<EditSession>(lazyPath, lazy, sessionParams_);
        if (session_->document().scene.layers.empty()) throw std::runtime_error("lacet edit: the scene has no layer to show");
    }
    adaptive_.reset();
    if (options_.adaptiveMs > 0.0 && options_.script.empty())
        adaptive_.emplace(sessionParams_.view.K, AdaptiveQualityParams{.targetMs = options_.adaptiveMs});
    pyramid_.sessionStarted();
    openPyramid();
    if (const LazyForest* f = session_->lazyForest()) {
        std::ostringstream m;
        m << "Read lazily within " << options_.vectorBudgetMiB << " MiB, parts of level " << f->partLevel() << " (edits saved into the file in place)";
        const auto& levels = pyramid_.levels();
        if (f->params().topElevationOnly && (!levels || levels->vectorLevel <= f->partLevel()))
            m << "; levels " << (levels ? levels->vectorLevel : 0) << " to " << f->partLevel()
              << " are drawn without their narrow curves and land areas (no pyramid gives their appearance)";
        status(m.str());
        log_["lazy"] = {{"vector_budget_mib", options_.vectorBudgetMiB}, {"part_level", f->partLevel()}, {"top_mib", f->stats().topMiB}};
    }
    controller_ = std::make_unique<EditingController>(*session_);
    controller_->onMessage = [this](const std::string& m) { status(m); };
    controller_->onCommand = [this](const CommandReport& r) {
        if (script_) log_["commands"].push_back({{"apply_ms", r.applyMs}, {"update_ms", r.updateMs},
                                                  {"changed_quads", r.changedQuads}, {"dirty_tiles", r.dirtyTiles}});
    };
    if (current && *current < session_->document().scene.layers.size()) controller_->setCurrentLayer(*current);
    controller_->setTool(tool);
    controller_->newCurve = style;
    demRange_.reset();
    // First frame: the root's tile, so that every later leaf has an ancestor to show.
    session_->frame({camera_.position().x, camera_.position().y, 1e9}, 0.0);
}

void EditorApp::status(const std::string& message) {
    status_ = message;
    if (script_) log_["messages"].push_back(message);
}

std::optional<glm::dvec2> EditorApp::project(glm::dvec3 world) const { return camera_.project(world, width_, height_, clip_); }

double EditorApp::viewerHeight() const { return session_->heightAboveGround(camera_.position()); }

PickView EditorApp::pickView() const {
    PickView v;
    v.camera = camera_;
    v.width = std::max(1, width_), v.height = std::max(1, height_);
    v.clip = clip_;
    v.ground = [this](glm::dvec2 pixel) { return terrainAt(pixel); };
    return v;
}

std::optional<glm::dvec3> EditorApp::terrainAt(glm::dvec2 pixel) const {
    const double x = pixel.x, y = pixel.y;
    const int i = int(std::floor(x)), j = height_ - 1 - int(std::floor(y));
    if (i < 0 || j < 0 || i >= width_ || j >= height_ || depth_.size() != std::size_t(width_) * std::size_t(height_)) return std::nullopt;
    const float d = depth_[std::size_t(j) * std::size_t(width_) + std::size_t(i)];
    if (d >= 1.0f) return std::nullopt;  // the sky
    return renderedCamera_.unproject(x, y, double(d), width_, height_, renderedClip_);
}

void EditorApp::handle(const InputEvent& e) {
    controller_->setView(pickView());  // the camera as the previous events left it
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
    } else if (e.button == 2 || (e.mods & GLFW_MOD_SHIFT)) {
        panning_ = true;
    } else if (!controller_->press({e.x, e.y})) {
        panning_ = true;  // a press on the ground with the select tool pans
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
    } else {
        controller_->drag(mouse_);
    }
}

void EditorApp::onMouseUp(const InputEvent& e) {
    mouse_ = {e.x, e.y};
    orbiting_ = panning_ = false;
    controller_->release();
}

void EditorApp::onKey(const InputEvent& e) {
    const bool ctrl = (e.mods & GLFW_MOD_CONTROL) != 0, shift = (e.mods & GLFW_MOD_SHIFT) != 0;
    if (ctrl && (e.key == GLFW_KEY_Y || (e.key == GLFW_KEY_Z && shift))) controller_->redo();
    else if (ctrl && e.key == GLFW_KEY_Z) controller_->undo();
    else if (ctrl && e.key == GLFW_KEY_S) save({});
    else if (e.key == GLFW_KEY_ESCAPE) controller_->cancel();
    else if (e.key == GLFW_KEY_ENTER || e.key == GLFW_KEY_KP_ENTER) controller_->finishDrawing();
    else if (e.key == GLFW_KEY_DELETE) controller_->deleteSelection();
    else if (e.key == GLFW_KEY_F && !ctrl) camera_.setFly(!camera_.fly);
}

void EditorApp::save(const std::string& path) {
    const std::string target = !path.empty() ? path : !scenePath_.empty() ? scenePath_ : options_.outDir + "/scene.gpkg";
    try {
        const auto t0 = Clock::now();
        if (session_->lazyForest()) {
            // A scene read lazily: its edits written into its own file, in place.
            std::error_code e1, e2;
            if (std::filesystem::weakly_canonical(target, e1) != std::filesystem::weakly_canonical(scenePath_, e2) || e1 || e2)
                throw std::runtime_error("a scene read lazily (a vector budget) is saved into its own file " + scenePath_ + ", not " + target);
            const SceneEditsSaved s = session_->saveEdits();
            status("Saved " + std::to_string(s.nodes + s.curves + s.areas) + " edited elements into " + target + " in " +
                   std::to_string(int(msSince(t0))) + " ms");
        } else {
            std::error_code e1, e2;
            const bool over = !diskChecksum_.empty() && std::filesystem::exists(target, e1) &&
                              std::filesystem::weakly_canonical(target, e1) == std::filesystem::weakly_canonical(scenePath_, e2) && !e1 && !e2;
            if (over) {
                diskChecksum_ = saveSceneOver(target, session_->document(), diskChecksum_);
            } else {
                saveScene(target, session_->document());
                diskChecksum_ = storedSceneChecksum(target);
            }
            session_->markSaved();
            scenePath_ = target;
            status("Saved " + target + " in " + std::to_string(int(msSince(t0))) + " ms");
        }
    } catch (const std::exception& e) {
        status(std::string("Not saved: ") + e.what());
        return;
    }
    if (const std::string m = pyramid_.afterSave(*session_, target); !m.empty()) status(m);
}

void EditorApp::setWorkClock(WorkClock clock) {
    sessionParams_.clock = clock;
    if (session_) session_->setClock(std::move(clock));
}

void EditorApp::open(const std::string& path) {
    while (pyramid_.updating()) pollPyramidUpdate(true);  // the updates of the scene being left end first
    if (options_.noPyramid) pyramid_.setFiles({}, path);
    else pyramid_.setDefaultFiles(path);
    std::string checksum;
    if (options_.vectorBudgetMiB > 0.0) resetSession({}, path);
    else resetSession(loadScene(path, checksum));
    scenePath_ = path;
    diskChecksum_ = checksum;
    status("Opened " + path);
}

void EditorApp::openPyramid() {
    const PyramidOpened o = pyramid_.open(*session_);
    if (const auto& l = o.levels) {
        log_["pyramid"] = {{"file", l->path}, {"vector_level", l->vectorLevel}, {"max_level", l->maxLevel}, {"encoding", l->encoding}};
        std::cerr << "lacet edit: pyramid " << l->path << ": the appearance of levels " << l->minLevel << " to " << l->vectorLevel - 1
                  << " is read from it\n";
    } else if (!o.error.empty()) {
        std::cerr << "lacet edit: warning: " << o.error << "; going on without the pyramid (every tile made live)\n";
        status("No pyramid: " + o.error);
        log_["pyramid_refused"] = o.error;
    }
}

void EditorApp::pollPyramidUpdate(bool wait) {
    const std::optional<PyramidUpdateResult> r = pyramid_.poll(*session_, wait);
    if (!r) return;
    nlohmann::json entry = {{"file", r->path}, {"edit_count", r->madeAt}};
    if (r->updated)
        entry.update({{"quads", r->quads}, {"quads_changed", r->quadsChanged}, {"tiles_made", r->tilesMade},
                      {"tiles_written", r->tilesWritten}, {"rebuilt", r->rebuilt}, {"seconds", r->seconds}});
    if (!r->updated) {
        entry["error"] = r->error;
        std::cerr << "lacet edit: warning: the pyramid was not updated: " << r->error << "\n";
        status("Pyramid not updated: " + r->error);
    } else if (!r->ok()) {
        entry["error"] = r->error;
        std::cerr << "lacet edit: warning: " << r->error << "; the edited quads stay live\n";
        status("Pyramid not reopened: " + r->error);
    } else {
        std::ostringstream m;
        m.precision(3);
        m << "Pyramid updated: " << r->quadsChanged << " of " << r->quads << " quads changed, " << r->tilesMade << " tiles made, "
          << r->tilesWritten << " written in " << r->seconds << " s";
        status(m.str());
    }
    log_["pyramid_updates"].push_back(entry);
}

void EditorApp::requestScreenshot(const std::string& path, bool panels, bool overlay) {
    screenshots_.push_back({path, panels, overlay});
}

void EditorApp::writeScreenshot(const Screenshot& s) {
    std::vector<std::uint8_t> rgba(std::size_t(width_) * std::size_t(height_) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    std::vector<std::uint8_t> rgb(std::size_t(width_) * std::size_t(height_) * 3);
    const std::uint8_t bg[3] = {std::uint8_t(std::lround(background_.r * 255.0f)), std::uint8_t(std::lround(background_.g * 255.0f)),
                                std::uint8_t(std::lround(background_.b * 255.0f))};
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
    controller_->setView(pickView());
    const Overlay& o = controller_->buildOverlay();
    for (const OverlayLine& l : o.lines)
        overlay_->line(l.a, l.b, l.style == OverlayLine::Style::Selected ? kSelected : l.style == OverlayLine::Style::Drawing ? kDrawing : kPolygon);
    for (const OverlayPoint& p : o.points) {
        // The current layer's points can be picked; other shown layers' are drawn smaller and dimmer.
        glm::vec4 colour = kDrawing;
        float size = 10.0f;
        switch (p.style) {
            case OverlayPoint::Style::OnCurve: colour = kOnCurve, size = p.selected ? 11.0f : 8.0f; break;
            case OverlayPoint::Style::Control: colour = kControl, size = p.selected ? 11.0f : 8.0f; break;
            case OverlayPoint::Style::Node: colour = kNode; break;
            case OverlayPoint::Style::Drawing: break;
        }
        if (p.style != OverlayPoint::Style::Drawing && !p.current) colour.a = 0.6f, size *= 0.6f;
        overlay_->point(p.world, colour, size);
    }
    const double aspect = double(width_) / double(height_);
    overlay_->draw(camera_.position(), camera_.projection(aspect, clip_) * camera_.view());
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
        pollPyramidUpdate(false);
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
        const FrameViewers viewers = lookAhead_.next(eye, h);  // §8: prefetch along the predicted path
        const double aspect = double(width_) / double(height_);
        if (!demRange_) demRange_ = frustumHeightRange(*session_->document().dem);
        const QuadVisibility visible = frustumVisibility(camera_, aspect, clip_, *demRange_);
        auto t0 = Clock::now();
        session_->setRefineBudget(lookAhead_.refineBudgetMs(options_.budgetMs));  // 0 (no budget): refine completely
        lastFrame_ = session_->frame(viewers.viewer, options_.budgetMs, visible, viewers.predicted);
        lastUpdateMs_ = msSince(t0);
        tilesProduced_ += lastFrame_.produced + lastFrame_.prefetched;

        t0 = Clock::now();
        glViewport(0, 0, width_, height_);
        glClearColor(background_.r, background_.g, background_.b, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        TerrainView tv;
        tv.camera = &camera_;
        tv.width = width_, tv.height = height_;
        tv.clip = clip_;
        tv.heightAboveGround = h;
        terrain_->draw(*session_, tv);
        // The depth buffer of what the user sees: picks of the next frame's input read it.
        depth_.resize(std::size_t(width_) * std::size_t(height_));
        glPixelStorei(GL_PACK_ALIGNMENT, 4);
        glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, depth_.data());
        renderedCamera_ = camera_;
        renderedClip_ = clip_;
        // The objects after the depth buffer was read: picks stand on the terrain, not on a tree.
        objects_->draw(*session_, camera_, aspect, clip_, terrain_->sun);
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
        if (adaptive_) {
            const double k = adaptive_->onFrame(lastUpdateMs_ + lastRenderMs_, lastFrame_.pending == 0);
            if (k != session_->params().view.K) session_->setK(k);
        }
        if (script_) {
            const TerrainStats& ts = terrain_->stats();
            log_["frames"].push_back({{"frame", frames_}, {"update_ms", lastUpdateMs_}, {"refine_ms", lastFrame_.refineMs},
                                      {"produce_ms", lastFrame_.produceMs}, {"produced", lastFrame_.produced},
                                      {"prefetched", lastFrame_.prefetched}, {"pending", lastFrame_.pending},
                                      {"view_quads", lastFrame_.viewQuads}, {"culled", lastFrame_.culled}, {"replaced", lastFrame_.replaced},
                                      {"drawn", ts.drawn}, {"fallback", ts.fallback}, {"missing", ts.missing},
                                      {"uploads", ts.uploads}, {"cached", lastFrame_.cached}, {"gpu_tiles", ts.gpuTiles},
                                      {"render_ms", lastRenderMs_}, {"viewer_height_m", h},
                                      {"from_pyramid", lastFrame_.fromPyramid}, {"pyramid_failed", lastFrame_.pyramidFailed},
                                      {"object_meshes", objects_->stats().meshes}, {"object_triangles", objects_->stats().triangles}});
        }
        glfwSwapBuffers(window_);
        ++frames_;
    }
    while (pyramid_.updating()) pollPyramidUpdate(true);  // a script's log says how the last save's update went
    if (script_) {
        const PyramidUse& p = session_->pyramidUse();
        if (pyramid_.levels())
            log_["pyramid_use"] = {{"read", p.read}, {"failed", p.failed}, {"touched", p.touched}, {"live", p.live}};
        script_->finish(*this);
    }
    return 0;
}

}  // namespace lacet::ui
