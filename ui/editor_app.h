#pragma once
// The editor's window (issue: the 3D editor): the terrain of an editing session drawn live while
// the user moves the camera and edits the current layer's curves (Fig. 13), with ImGui panels
// for layers, the selection's properties, statistics and the accuracy knobs (ui/editor_panels.cpp).
//
// The editing itself (tools, selection, picking, locks, the draw tool's curve) is the window-less
// editing controller's (editor/editing_controller.h); the window translates its input into the
// controller's calls and the camera's moves, draws, and shows the panels. `lacet edit`
// (app/cmd_edit.cpp) chooses and loads the document.
//
// Each frame: the queued input (window or script) is handled (camera moves; picks against the
// depth buffer of the frame the user saw; edits through the controller), then
// EditSession::frame() refines the quadtree for the camera and makes the tiles of the visible
// leaves within the per-frame budget, prefetching for the camera's predicted position, then the
// terrain, its objects (bridges, trees), the overlay and the panels are drawn.
//
// Mouse: left picks and drags control points and nodes (or, with the draw tool, adds points);
// right drag orbits, middle drag (or Shift + left on the ground) pans, the wheel zooms. Keys:
// Ctrl+Z undo, Ctrl+Y (or Ctrl+Shift+Z) redo, Ctrl+S save, Delete deletes the selected curve,
// Enter ends the road being drawn, Escape cancels it or clears the selection, F toggles fly mode
// (W A S D, Q E to move; Shift faster).
//
// The pyramid (§7): with `EditorOptions::pyramid`, the session reads the appearance of the quads
// below the pyramid's first vector level from that file, and each save to the scene's own file
// updates it in the background (editor/pyramid_link.h, which decides all of it); a pyramid that
// does not match the scene is refused with a warning on stderr, and the editor goes on without.
// The camera's predicted path and the frame's refine budget are editor/look_ahead.h's.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/adaptive_quality.h"
#include "editor/camera.h"
#include "editor/edit_session.h"
#include "editor/editing_controller.h"
#include "editor/look_ahead.h"
#include "editor/pyramid_link.h"
#include "ui/input_event.h"
#include "ui/script_host.h"

struct GLFWwindow;

namespace lacet::ui {

class TerrainRenderer;
class ObjectRenderer;
class OverlayRenderer;
class ScriptPlayer;

struct EditorOptions {
    std::string script;         // a scripted session (ui/script_player.h)
    std::string outDir = ".";   // where a script's screenshots and log go
    int width = 1280, height = 800;
    double budgetMs = 12.0;     // tile production per frame
    std::size_t cacheTiles = SessionParams{}.cacheTiles;  // tile pairs the session keeps (editor/cache_fit.h)
    bool vsync = true;
    // The pyramid file of the document (empty: none). A scene opened later (a script's open)
    // gets its default pyramid (defaultPyramidPath) when that exists, unless `noPyramid`.
    std::string pyramid;
    bool noPyramid = false;
    // Frame-rate-adaptive K (editor/adaptive_quality.h): the frame time aimed at (ms; 0: K fixed).
    // Off in scripted sessions, which must draw the same frames on every machine.
    double adaptiveMs = 1000.0 / 30.0;
    // Slow quads' tiles and subdivisions made on a background thread (SessionParams::backgroundMs;
    // 0: in the frames). < 0: kInteractiveBackgroundMs, but 0 in scripted sessions, for the same
    // reason (a script that asks for it gets it).
    double backgroundMs = -1.0;
    double demBudgetMiB = DemStreamParams{}.budgetMiB;  // a streamed DEM's blocks (io/dem_stream.h)
    // > 0: a scene file's vector data read lazily within this many MiB (editor/lazy_forest.h; its
    // parts quads of `partLevel`, -1: from LazyParams::partQuadM), edited in the file's ids and
    // saved into it in place (EditSession::saveEdits).
    double vectorBudgetMiB = 0.0;
    int partLevel = -1;
};

// The document the editor opens: the scene, the file it saves to (empty: none yet, a save goes to
// the output folder), how the log names it, and a first message for the status line.
struct EditorDocument {
    SceneDocument document;  // empty when `lazy`: `path` is read lazily (EditorOptions::vectorBudgetMiB)
    bool lazy = false;
    std::string path;
    std::string storedChecksum;  // what `path` stored when `document` was read from it (loadScene)
    std::string label;
    std::string message;
};

class EditorApp final : public ScriptHost {
public:
    EditorApp(const EditorOptions& options, EditorDocument document);
    ~EditorApp() override;
    EditorApp(const EditorApp&) = delete;
    EditorApp& operator=(const EditorApp&) = delete;

    // Runs until the window closes (or the script ends); returns the exit status.
    int run();

    // ScriptHost: what scripts may do.
    const EditSession& session() const override { return *session_; }
    EditingController& controller() override { return *controller_; }
    Camera& camera() override { return camera_; }
    std::optional<glm::dvec2> project(glm::dvec3 world) const override;
    glm::dvec3 groundPoint(Vec2 p) const override { return controller_->groundPoint(p); }
    void push(const InputEvent& e) override { events_.push_back(e); }
    void requestScreenshot(const std::string& path, bool panels, bool overlay) override;
    // Saves the document to `path` (the scene's own file when empty).
    void save(const std::string& path) override;
    // Opens a scene file in place of the current document (the camera stays).
    void open(const std::string& path) override;
    void setBackground(glm::vec3 rgb) override { background_ = rgb; }
    void setBudget(double ms) override { options_.budgetMs = ms; }
    void setWorkClock(WorkClock clock) override;
    // The view's tiles still to make, and a streamed DEM's blocks still to load (tiles made from a
    // coarser block are remade when they arrive).
    std::size_t pendingTiles() const override {
        const DemStream* dem = session_ ? session_->demStream() : nullptr;
        return lastFrame_.pending + (dem ? dem->stats().pending : 0);
    }
    bool refineDeferred() const override { return lastFrame_.refineDeferred; }
    nlohmann::json& log() override { return log_; }

private:
    struct Screenshot {
        std::string path;
        bool panels = true, overlay = true;
    };
    // A new session on `doc`, or on the scene file `lazyPath` read lazily (doc unused).
    void resetSession(SceneDocument doc, const std::string& lazyPath = {});
    PickView pickView() const;
    void handle(const InputEvent& e);
    void onMouseDown(const InputEvent& e);
    void onMouseMove(const InputEvent& e);
    void onMouseUp(const InputEvent& e);
    void onKey(const InputEvent& e);
    std::optional<glm::dvec3> terrainAt(glm::dvec2 pixel) const;  // the depth buffer the user saw
    double viewerHeight() const;  // the camera's height above the displayed ground (m, >= 1)
    void drawOverlay();
    void drawPanels();
    void writeScreenshot(const Screenshot& s);
    void status(const std::string& message);
    // The pyramid: opened for the session (a warning and none when it does not fit); an update
    // that ended (checked each frame; `wait`: until the one in flight has) logged and shown.
    void openPyramid();
    void pollPyramidUpdate(bool wait);

    EditorOptions options_;
    GLFWwindow* window_ = nullptr;
    int width_ = 0, height_ = 0;
    std::unique_ptr<EditSession> session_;
    std::unique_ptr<EditingController> controller_;
    std::string scenePath_;
    // What scenePath_ stores as read or last saved by this window (a whole document): a save over it
    // is refused when it stores something else (another editor saved it: io/scene_file.h saveSceneOver).
    std::string diskChecksum_;
    SessionParams sessionParams_;
    Camera camera_;
    std::unique_ptr<TerrainRenderer> terrain_;
    std::unique_ptr<ObjectRenderer> objects_;  // bridges and trees (§5.3), after the terrain
    std::unique_ptr<OverlayRenderer> overlay_;
    std::unique_ptr<ScriptPlayer> script_;
    std::vector<InputEvent> events_;
    std::vector<float> depth_;  // the last frame's depth buffer (rows from the bottom)
    Camera renderedCamera_;     // the camera and clip range it was drawn with
    glm::dvec2 renderedClip_{1.0, 1e5}, clip_{1.0, 1e5};
    std::optional<glm::dvec2> demRange_;
    glm::vec3 background_{0.55f, 0.70f, 0.88f};
    // Camera gestures (the controller has the editing ones).
    bool orbiting_ = false, panning_ = false;
    glm::dvec2 lastMouse_{0.0}, mouse_{0.0};
    // Figures.
    FrameReport lastFrame_;
    std::optional<AdaptiveQuality> adaptive_;  // null: K fixed
    double lastUpdateMs_ = 0.0, lastRenderMs_ = 0.0;
    std::size_t tilesProduced_ = 0, frames_ = 0;
    LookAhead lookAhead_;
    std::vector<Screenshot> screenshots_;
    nlohmann::json log_;
    std::string status_;
    bool confirmClose_ = false, closing_ = false;
    PyramidLink pyramid_;  // the pyramid and its updates after saves
};

}  // namespace lacet::ui
