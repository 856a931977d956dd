#pragma once
// What a scripted session (ui/script_player.h) may do to the editor: the narrow interface the
// window implements (ui/editor_app.h), so that the player drives the editor through the same
// input queue and editing controller as a user, and knows nothing else of the window.

#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "editor/camera.h"
#include "editor/edit_session.h"
#include "editor/editing_controller.h"
#include "model/work_clock.h"
#include "ui/input_event.h"

namespace lacet::ui {

class ScriptHost {
public:
    virtual ~ScriptHost() = default;

    virtual const EditSession& session() const = 0;
    // The tools and the selection (setTool, selection()).
    virtual EditingController& controller() = 0;
    virtual Camera& camera() = 0;
    // A window pixel of a world point with the current camera; a scene point at its displayed height.
    virtual std::optional<glm::dvec2> project(glm::dvec3 world) const = 0;
    virtual glm::dvec3 groundPoint(Vec2 p) const = 0;
    // Input, handled at the next frame as the window's own.
    virtual void push(const InputEvent& e) = 0;
    // The next frame is written to `path` (with or without the panels and the overlay).
    virtual void requestScreenshot(const std::string& path, bool panels, bool overlay) = 0;
    // Saves the document (to its own file when `path` is empty); opens another in its place.
    virtual void save(const std::string& path) = 0;
    virtual void open(const std::string& path) = 0;
    virtual void setBackground(glm::vec3 rgb) = 0;
    virtual void setBudget(double ms) = 0;  // tile production per frame
    // The clock the session's budgets are read on (SessionParams::clock).
    virtual void setWorkClock(WorkClock clock) = 0;
    // The view's tiles still missing or dirty after the last frame (with a streamed DEM, and its
    // blocks still to load), and whether it left subdivisions for later.
    virtual std::size_t pendingTiles() const = 0;
    virtual bool refineDeferred() const = 0;
    virtual nlohmann::json& log() = 0;
};

}  // namespace lacet::ui
