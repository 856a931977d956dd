#pragma once
// The editor's window (issue: the 3D editor): the terrain of an editing session drawn live while
// the user moves the camera and edits the current layer's curves (Fig. 13), with ImGui panels
// for layers, the selection's properties, statistics and the accuracy knobs (ui/editor_panels.cpp).
//
// Each frame: the queued input (window or script) is handled (camera moves; picks against the
// depth buffer of the frame the user saw; edits as commands of the session), then
// EditSession::frame() refines the quadtree for the camera and makes the tiles of the visible
// leaves within the per-frame budget, prefetching for the camera's predicted position, then the
// terrain, the overlay and the panels are drawn.
//
// Mouse: left picks and drags control points and nodes (or, with the draw tool, adds points);
// right drag orbits, middle drag (or Shift + left on the ground) pans, the wheel zooms. Keys:
// Ctrl+Z undo, Ctrl+Y (or Ctrl+Shift+Z) redo, Ctrl+S save, Delete deletes the selected curve,
// Enter ends the road being drawn, Escape cancels it or clears the selection, F toggles fly mode
// (W A S D, Q E to move; Shift faster).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "editor/edit_session.h"
#include "editor/camera.h"
#include "ui/input_event.h"

struct GLFWwindow;

namespace lacet::ui {

class TerrainRenderer;
class OverlayRenderer;
class ScriptPlayer;

struct EditorOptions {
    std::string scene;          // a scene file; empty: Andorra when its data is there, else synthetic
    std::string andorraDir = "../shared/data/andorra";
    std::size_t syntheticCurves = 60000;
    std::string script;         // a scripted session (ui/script_player.h)
    std::string outDir = ".";   // where a script's screenshots and log go
    int width = 1280, height = 800;
    double budgetMs = 12.0;     // tile production per frame
    std::size_t cacheTiles = SessionParams{}.cacheTiles;  // tile pairs the session keeps (editor/cache_fit.h)
    bool vsync = true;
};

enum class Tool { Select, Insert, DeletePoint, Draw };

// What the pointer is on: a vertex of a curve, a node, or a curve.
struct Pick {
    enum class Kind { None, Vertex, Node, Curve } kind = Kind::None;
    LayerId layer = 0;
    ElementId id = kNoElement;  // curve or node
    std::size_t index = 0;      // vertex index
    double pixels = 1e30;       // distance on screen
};

class EditorApp {
public:
    explicit EditorApp(const EditorOptions& options);
    ~EditorApp();
    EditorApp(const EditorApp&) = delete;
    EditorApp& operator=(const EditorApp&) = delete;

    // Runs until the window closes (or the script ends); returns the exit status.
    int run();

    // For scripts and tests.
    EditSession& session() { return *session_; }
    Camera& camera() { return camera_; }
    int width() const { return width_; }
    int height() const { return height_; }
    void push(const InputEvent& e) { events_.push_back(e); }
    std::optional<glm::dvec2> project(glm::dvec3 world) const;
    glm::dvec3 groundPoint(Vec2 p) const;  // p at its displayed height
    // Saves the document to `path` (the scene's own file when empty).
    void save(const std::string& path = {});
    // Opens a scene file in place of the current document (the camera stays).
    void open(const std::string& path);
    // The next frame is written to `path` (with or without the panels and the overlay), and
    // the log records it.
    void requestScreenshot(const std::string& path, bool panels, bool overlay);
    std::size_t pendingTiles() const { return lastFrame_.pending; }
    bool refineDeferred() const { return lastFrame_.refineDeferred; }
    glm::vec3 background{0.55f, 0.70f, 0.88f};
    nlohmann::json& log() { return log_; }
    const Pick& selection() const { return selected_; }
    void setBudget(double ms) { options_.budgetMs = ms; }
    void setTool(Tool t) { tool_ = t; }

private:
    struct Screenshot {
        std::string path;
        bool panels = true, overlay = true;
    };
    void loadInitialDocument();
    void resetSession(SceneDocument doc);
    void handle(const InputEvent& e);
    void onMouseDown(const InputEvent& e);
    void onMouseMove(const InputEvent& e);
    void onMouseUp(const InputEvent& e);
    void onKey(const InputEvent& e);
    void execute(const Command& c, bool merge = false);
    void finishDrawing();
    Pick pick(double x, double y, bool verticesOnly) const;
    std::optional<glm::dvec3> terrainAt(double x, double y) const;  // ray against the displayed terrain
    double viewerHeight() const;
    void drawOverlay();
    void drawPanels();
    void writeScreenshot(const Screenshot& s);
    void status(const std::string& message);

    EditorOptions options_;
    GLFWwindow* window_ = nullptr;
    int width_ = 0, height_ = 0;
    std::unique_ptr<EditSession> session_;
    std::string scenePath_;
    SessionParams sessionParams_;
    Camera camera_;
    std::unique_ptr<TerrainRenderer> terrain_;
    std::unique_ptr<OverlayRenderer> overlay_;
    std::unique_ptr<ScriptPlayer> script_;
    std::vector<InputEvent> events_;
    std::vector<float> depth_;  // the last frame's depth buffer (rows from the bottom)
    Camera renderedCamera_;     // the camera and clip range it was drawn with
    glm::dvec2 renderedClip_{1.0, 1e5}, clip_{1.0, 1e5};
    std::optional<glm::dvec2> demRange_;
    // What the overlay drew this frame: the points that can be picked, and the curves.
    struct OverlayItem {
        Pick pick;
        glm::dvec2 pixel;
    };
    std::vector<OverlayItem> overlayItems_;
    std::vector<ElementId> overlayCurves_;
    // Interaction.
    Tool tool_ = Tool::Select;
    LayerId currentLayer_ = 0;
    std::vector<char> layerVisible_, layerLocked_;
    Pick selected_, dragging_;
    bool dragMoved_ = false;  // the current drag has made its first move (later ones merge)
    bool orbiting_ = false, panning_ = false;
    glm::dvec2 lastMouse_{0.0}, mouse_{0.0};
    struct DrawPoint {
        Vec2 p;
        ElementId node = kNoElement;  // snapped to an existing node
    };
    std::vector<DrawPoint> drawing_;
    float newWidth_ = 7.0f, newFootprint_ = 16.0f;
    int newClass_ = 1;
    // Figures.
    FrameReport lastFrame_;
    CommandReport lastCommand_;
    double lastUpdateMs_ = 0.0, lastRenderMs_ = 0.0;
    std::size_t tilesProduced_ = 0, commands_ = 0, frames_ = 0;
    glm::dvec3 lastEye_{0.0}, velocity_{0.0};
    std::vector<Screenshot> screenshots_;
    nlohmann::json log_;
    std::string status_;
    bool confirmClose_ = false, closing_ = false;
};

}  // namespace lacet::ui
