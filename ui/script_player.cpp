#include "ui/script_player.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <stdexcept>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "model/work_clock.h"
#include "ui/script_host.h"

namespace lacet::ui {
namespace {

double radians(double degrees) { return degrees * M_PI / 180.0; }

InputEvent keyEvent(const std::string& name) {
    InputEvent e;
    e.type = InputEvent::Type::Key;
    std::string k = name;
    if (k.rfind("ctrl+", 0) == 0) {
        e.mods |= GLFW_MOD_CONTROL;
        k = k.substr(5);
    }
    if (k.rfind("shift+", 0) == 0) {
        e.mods |= GLFW_MOD_SHIFT;
        k = k.substr(6);
    }
    if (k.size() == 1 && k[0] >= 'a' && k[0] <= 'z') e.key = GLFW_KEY_A + (k[0] - 'a');
    else if (k == "escape") e.key = GLFW_KEY_ESCAPE;
    else if (k == "enter") e.key = GLFW_KEY_ENTER;
    else if (k == "delete") e.key = GLFW_KEY_DELETE;
    else throw std::runtime_error("script: unknown key '" + name + "'");
    return e;
}

InputEvent mouseEvent(InputEvent::Type type, glm::dvec2 p, int button = 0) {
    InputEvent e;
    e.type = type;
    e.x = p.x, e.y = p.y;
    e.button = button;
    return e;
}

LayerId layerOf(const Scene& scene, const nlohmann::json& v) {
    if (v.is_number_integer()) return v.get<LayerId>();
    const std::string name = v.get<std::string>();
    for (LayerId i = 0; i < scene.layers.size(); ++i)
        if (scene.layers[i].name == name || toString(scene.layers[i].kind) == name) return i;
    throw std::runtime_error("script: no layer '" + name + "'");
}

// Where a script puts the camera's target or position: on the DEM, the ground the view converges
// to. The displayed height is not used: before the view is refined there it comes from a coarse
// tile, which in mountains lies tens of metres off, and a close camera would end up under the
// refined terrain.
glm::dvec3 ground(ScriptHost& app, Vec2 p) { return {p.x, p.y, app.session().document().dem->sample(p)}; }

void placeCamera(Camera& cam, const nlohmann::json& s) {
    if (s.contains("distance")) cam.distance = s["distance"].get<double>();
    if (s.contains("yaw")) cam.yaw = radians(s["yaw"].get<double>());
    if (s.contains("pitch")) cam.pitch = radians(s["pitch"].get<double>());
}

}  // namespace

ScriptPlayer::ScriptPlayer(const std::string& path, const std::string& outDir) : file_(path), outDir_(outDir) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot read the script");
    nlohmann::json j;
    try {
        in >> j;
    } catch (const std::exception& e) {
        throw std::runtime_error(path + ": not JSON: " + e.what());
    }
    if (!j.is_object() || !j.contains("steps") || !j["steps"].is_array()) throw std::runtime_error(path + ": expected {\"steps\": [...]}");
    steps_ = j["steps"];
    if (j.contains("log")) logName_ = j["log"].get<std::string>();
    for (std::size_t i = 0; i < steps_.size(); ++i)
        if (!steps_[i].is_object() || !steps_[i].contains("do"))
            throw std::runtime_error(path + ": step " + std::to_string(i) + " has no \"do\"");
}

std::string ScriptPlayer::path(const std::string& file) const {
    return !file.empty() && file[0] == '/' ? file : outDir_ + "/" + file;
}

bool ScriptPlayer::step(ScriptHost& app) {
    while (next_ < steps_.size()) {
        const nlohmann::json& s = steps_[next_];
        try {
            const bool done = inStep_ ? continueStep(app, s) : begin(app, s);
            if (!done) {
                inStep_ = true;
                ++frame_;
                return true;
            }
        } catch (const std::exception& e) {
            throw std::runtime_error(file_ + ": step " + std::to_string(next_) + " (" + s["do"].get<std::string>() + "): " + e.what());
        }
        inStep_ = false;
        frame_ = 0;
        ++next_;
        // A step that asked for a screenshot or an input needs the next frame to happen.
        const std::string kind = s["do"].get<std::string>();
        if (kind == "screenshot" || kind == "key" || kind == "mouse" || kind == "scroll" || kind == "click_world") return true;
    }
    return false;
}

bool ScriptPlayer::begin(ScriptHost& app, const nlohmann::json& s) {
    const std::string kind = s["do"].get<std::string>();
    const Scene& scene = app.session().document().scene;
    frame_ = 0;
    if (kind == "camera") return beginCamera(app, s);
    if (kind == "focus") return beginFocus(app, s);
    if (kind == "drag_focus") {
        if (!hasFocus_) throw std::runtime_error("no focus vertex (use a focus step first)");
        from_ = scene.layers[focusLayer_].curves[focusCurve_].vertices[focusIndex_].p;
        to_ = from_ + glm::dvec2(s["by"][0].get<double>(), s["by"][1].get<double>());
        const auto px = app.project(app.groundPoint(from_));
        if (!px) throw std::runtime_error("the focus vertex is behind the camera");
        app.push(mouseEvent(InputEvent::Type::MouseDown, *px));
        return false;
    }
    if (kind == "wait_idle" || kind == "frames") return continueStep(app, s);
    if (kind == "wait_ms") {
        stepStart_ = std::chrono::steady_clock::now();
        return continueStep(app, s);
    }
    if (kind == "screenshot") {
        app.requestScreenshot(path(s["file"].get<std::string>()), s.value("panels", false), s.value("overlay", true));
        return true;
    }
    if (kind == "key") {
        app.push(keyEvent(s["name"].get<std::string>()));
        return true;
    }
    if (kind == "mouse") {
        const std::string a = s["action"].get<std::string>();
        const auto type = a == "down" ? InputEvent::Type::MouseDown : a == "up" ? InputEvent::Type::MouseUp : InputEvent::Type::MouseMove;
        app.push(mouseEvent(type, {s["x"].get<double>(), s["y"].get<double>()}, s.value("button", 0)));
        return true;
    }
    if (kind == "scroll") {
        InputEvent e;
        e.type = InputEvent::Type::Scroll;
        e.y = s["dy"].get<double>();
        app.push(e);
        return true;
    }
    if (kind == "click_world") {
        Vec2 at;
        if (s["at"].is_array()) {
            at = Vec2(s["at"][0].get<double>(), s["at"][1].get<double>());
        } else {
            // Relative to the focus: "focus_node" (its curve's start node) or "focus" plus `offset`.
            if (!hasFocus_) throw std::runtime_error("no focus vertex (use a focus step first)");
            const Layer& l = scene.layers[focusLayer_];
            const Curve& c = l.curves[focusCurve_];
            at = s["at"] == "focus_node" ? l.nodes[c.start].p : c.vertices[focusIndex_].p;
            if (s.contains("offset")) at += Vec2(s["offset"][0].get<double>(), s["offset"][1].get<double>());
        }
        const auto px = app.project(app.groundPoint(at));
        if (!px) throw std::runtime_error("the point is behind the camera");
        app.push(mouseEvent(InputEvent::Type::MouseDown, *px));
        app.push(mouseEvent(InputEvent::Type::MouseUp, *px));
        return true;
    }
    if (kind == "tool") {
        const std::string n = s["name"].get<std::string>();
        app.controller().setTool(n == "insert"         ? Tool::Insert
                                 : n == "delete_point" ? Tool::DeletePoint
                                 : n == "draw"         ? Tool::Draw
                                 : n == "roundabout"   ? Tool::Roundabout
                                                       : Tool::Select);
        if (s.contains("radius")) app.controller().roundaboutRadius = s["radius"].get<float>();
        return true;
    }
    if (kind == "save") {
        app.save(s.contains("file") ? path(s["file"].get<std::string>()) : std::string());
        return true;
    }
    if (kind == "open") {
        app.open(path(s["file"].get<std::string>()));
        return true;
    }
    if (kind == "background") {
        app.setBackground(glm::vec3(s["rgb"][0].get<float>(), s["rgb"][1].get<float>(), s["rgb"][2].get<float>()));
        return true;
    }
    if (kind == "probe") return probe(app);
    if (kind == "inspect") return inspect(app);
    if (kind == "budget") {
        app.setBudget(s["ms"].get<double>());
        if (s.contains("clock_step_ms")) app.setWorkClock(steppedClockMs(s["clock_step_ms"].get<double>()));
        return true;
    }
    if (kind == "fly") return beginFly(app, s);
    throw std::runtime_error("unknown step");
}

bool ScriptPlayer::beginCamera(ScriptHost& app, const nlohmann::json& s) {
    const Scene& scene = app.session().document().scene;
    Camera& cam = app.camera();
    if (s.contains("save")) {
        saved_[s["save"].get<std::string>()] = cam;
        return true;
    }
    if (s.contains("restore")) {
        const auto it = saved_.find(s["restore"].get<std::string>());
        if (it == saved_.end()) throw std::runtime_error("no camera saved as '" + s["restore"].get<std::string>() + "'");
        cam = it->second;
        return true;
    }
    placeCamera(cam, s);
    if (s.contains("fly")) cam.setFly(s["fly"].get<bool>());
    if (s.contains("target")) {
        Vec2 t = scene.extent.center();
        if (s["target"].is_array()) t = Vec2(s["target"][0].get<double>(), s["target"][1].get<double>());
        else if (s["target"] == "drag_from") t = from_;
        else if (s["target"] == "drag_result") t = lastResult_;
        else if (s["target"] == "focus_node" && hasFocus_) t = scene.layers[focusLayer_].nodes[scene.layers[focusLayer_].curves[focusCurve_].start].p;
        cam.target = ground(app, t);
    }
    if (s.contains("position")) {
        if (s["position"].is_string()) {  // "scene": above its centre, `height` metres up
            cam.flyPosition = ground(app, scene.extent.center()) + glm::dvec3(0.0, 0.0, s.value("height", 3000.0));
        } else {
            const Vec2 p(s["position"][0].get<double>(), s["position"][1].get<double>());
            cam.flyPosition = ground(app, p) + glm::dvec3(0.0, 0.0, s["position"][2].get<double>());
        }
    }
    return true;
}

bool ScriptPlayer::beginFocus(ScriptHost& app, const nlohmann::json& s) {
    const Scene& scene = app.session().document().scene;
    const LayerId layer = layerOf(scene, s.value("layer", nlohmann::json(0)));
    const Vec2 near = s.contains("near") ? Vec2(s["near"][0].get<double>(), s["near"][1].get<double>()) : scene.extent.center();
    const double minWidth = s.value("min_width", 0.0);
    const bool onCurve = s.value("on_curve", false);
    double best = 1e300;
    hasFocus_ = false;
    const Layer& l = scene.layers[layer];
    for (ElementId id = 0; id < l.curves.size(); ++id) {
        const Curve& c = l.curves[id];
        if (!c.alive || c.vertices.size() < 3 || c.w < minWidth) continue;
        for (std::size_t k = 1; k + 1 < c.vertices.size(); ++k) {
            if (onCurve && !c.vertices[k].onCurve) continue;
            const double d = glm::length(c.vertices[k].p - near);
            if (d < best) best = d, hasFocus_ = true, focusLayer_ = layer, focusCurve_ = id, focusIndex_ = k;
        }
    }
    if (!hasFocus_) throw std::runtime_error("no curve to focus on");
    const Vec2 p = l.curves[focusCurve_].vertices[focusIndex_].p;
    app.camera().setFly(false);
    app.camera().target = ground(app, p);
    placeCamera(app.camera(), s);
    app.log()["focus"] = {{"layer", focusLayer_}, {"curve", focusCurve_}, {"index", focusIndex_}, {"x", p.x}, {"y", p.y}};
    return true;
}

bool ScriptPlayer::probe(ScriptHost& app) {
    // What the session's tiles hold at the last drag's start and end: the footprint's
    // blending b and enforced height z_e against the DEM's z_o, and the appearance colour.
    nlohmann::json out;
    for (const auto& [name, p] : {std::pair<const char*, glm::dvec2>{"from", from_}, {"result", lastResult_}}) {
        const DrawItem* shown = app.session().plan().itemAt(p);
        if (!shown || !shown->tile) continue;
        const CachedTile* t = shown->tile;
        const ElevationTile& e = t->elevation;
        const glm::ivec2 ij = glm::ivec2(glm::round((p - e.bounds.min) / e.delta));
        const std::size_t k = e.index(ij.x, ij.y);
        const AppearanceTile& a = t->appearance;
        const glm::ivec2 ai = glm::ivec2(glm::floor((p - a.bounds.min) / a.delta));
        const std::vector<std::uint8_t> texels = t->texels();
        const std::size_t ak = a.index(ai.x, ai.y);
        out[name] = {{"level", std::get<0>(shown->tileKey)}, {"b", e.b[k]}, {"zo", e.zo[k]}, {"ze", e.ze[k]}, {"zm", e.zm[k]},
                     {"rgb", {texels[ak], texels[ak + 1], texels[ak + 2]}}};
    }
    app.log()["probes"].push_back(out);
    return true;
}

bool ScriptPlayer::inspect(ScriptHost& app) {
    const Scene& scene = app.session().document().scene;
    // The current layer's counts and the selected curve with its end nodes' degrees.
    const Pick& sel = app.controller().selection();
    nlohmann::json out;
    const Layer& l = scene.layers[hasFocus_ ? focusLayer_ : 0];
    out["nodes"] = l.nodes.size(), out["curves"] = l.curves.size();
    std::size_t alive = 0;
    for (const Curve& c : l.curves) alive += c.alive;
    out["alive_curves"] = alive;
    if (sel.kind == Pick::Kind::Curve) {
        const Curve& c = scene.layers[sel.layer].curves[sel.id];
        const Layer& sl = scene.layers[sel.layer];
        out["selected"] = {{"curve", sel.id}, {"start", c.start}, {"end", c.end}, {"vertices", c.vertices.size()},
                           {"start_degree", sl.nodes[c.start].curves.size()}, {"end_degree", sl.nodes[c.end].curves.size()}};
    }
    if (hasFocus_) {
        const Curve& f = l.curves[focusCurve_];
        out["focus_curve"] = {{"curve", focusCurve_}, {"start", f.start}, {"start_degree", l.nodes[f.start].curves.size()}};
    }
    app.log()["inspections"].push_back(out);
    return true;
}

bool ScriptPlayer::beginFly(ScriptHost& app, const nlohmann::json& s) {
    const Scene& scene = app.session().document().scene;
    Camera& cam = app.camera();
    cam.setFly(true);
    if (s.contains("pitch")) cam.pitch = radians(s["pitch"].get<double>());
    if (s.contains("yaw")) cam.yaw = radians(s["yaw"].get<double>());
    flyFrom_ = cam.flyPosition;
    flyHeightFrom_ = std::max(1.0, flyFrom_.z - ground(app, {flyFrom_.x, flyFrom_.y}).z);
    if (s["to"] == "focus") {
        if (!hasFocus_) throw std::runtime_error("no focus vertex (use a focus step first)");
        const Vec2 p = scene.layers[focusLayer_].curves[focusCurve_].vertices[focusIndex_].p;
        flyTo_ = glm::dvec3(p.x, p.y, s.value("height", 5.0));
    } else {
        flyTo_ = glm::dvec3(s["to"][0].get<double>(), s["to"][1].get<double>(), s["to"][2].get<double>());
    }
    return continueStep(app, s);
}

bool ScriptPlayer::continueStep(ScriptHost& app, const nlohmann::json& s) {
    const std::string kind = s["do"].get<std::string>();
    if (kind == "frames") return frame_ >= s.value("n", 1);
    if (kind == "wait_ms")  // real time, the live loop running meanwhile (a recorded session's pauses)
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - stepStart_).count() >= s.value("ms", 0.0);
    if (kind == "wait_idle") {
        if (frame_ > 0 && app.pendingTiles() == 0 && !app.refineDeferred()) return true;
        if (frame_ >= s.value("max_frames", 2000)) throw std::runtime_error("tiles still pending");
        return false;
    }
    if (kind == "drag_focus") {
        const int steps = s.value("steps", 20);
        if (frame_ <= steps) {
            const double t = double(frame_) / double(steps);
            const auto px = app.project(app.groundPoint(from_ + (to_ - from_) * t));
            if (!px) throw std::runtime_error("the drag left the view");
            app.push(mouseEvent(InputEvent::Type::MouseMove, *px));
            return false;
        }
        const auto px = app.project(app.groundPoint(to_));
        app.push(mouseEvent(InputEvent::Type::MouseUp, px.value_or(glm::dvec2(0.0))));
        const Vec2 now = app.session().document().scene.layers[focusLayer_].curves[focusCurve_].vertices[focusIndex_].p;
        lastResult_ = now;
        app.log()["drags"].push_back({{"from", {from_.x, from_.y}}, {"target", {to_.x, to_.y}}, {"result", {now.x, now.y}},
                                      {"moved_m", glm::length(now - from_)}, {"error_m", glm::length(now - to_)},
                                      {"target_pixel", {px.value_or(glm::dvec2(0.0)).x, px.value_or(glm::dvec2(0.0)).y}}});
        return true;
    }
    if (kind == "fly") {
        const int frames = s.value("frames", 300);
        const double t = double(frame_ + 1) / double(frames);
        Camera& cam = app.camera();
        const double height = flyHeightFrom_ * std::pow(std::max(1.0, flyTo_.z) / flyHeightFrom_, t);
        const double e = 1.0 - (1.0 - t) * (1.0 - t);  // fast first, slow near the ground
        const glm::dvec2 xy = glm::dvec2(flyFrom_) + (glm::dvec2(flyTo_) - glm::dvec2(flyFrom_)) * e;
        cam.flyPosition = ground(app, {xy.x, xy.y}) + glm::dvec3(0.0, 0.0, height);
        const int every = s.value("screenshot_every", 0);
        if (every > 0 && (frame_ + 1) % every == 0)
            app.requestScreenshot(path(s.value("prefix", std::string("fly")) + "_" + std::to_string(frame_ + 1) + ".png"), false, false);
        return frame_ + 1 >= frames;
    }
    return true;
}

void ScriptPlayer::finish(ScriptHost& app) {
    std::ofstream out(path(logName_));
    out << app.log().dump(1) << "\n";
    if (!out) throw std::runtime_error(path(logName_) + ": cannot write the log");
    // A summary on stdout: the screenshots and the last frame's figures.
    const nlohmann::json& log = app.log();
    nlohmann::json summary = {{"log", path(logName_)}, {"scene", log.value("scene", nlohmann::json())}};
    if (log.contains("frames") && !log["frames"].empty()) {
        summary["frames"] = log["frames"].size();
        summary["last_frame"] = log["frames"].back();
    }
    if (log.contains("screenshots"))
        for (const auto& s : log["screenshots"]) summary["screenshots"].push_back(s["file"]);
    std::cout << summary.dump(1) << "\n";
}

}  // namespace lacet::ui
