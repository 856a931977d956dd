#pragma once
// The editing controller (§6 of the paper: the user edits the vector data, the terrain follows):
// the rules of editing without a window, over an EditSession. It holds the tools, the current
// layer, the selection, the curve being drawn and the layer locks; it picks against a Camera and
// turns the user's gestures into commands of the session. The window (ui/editor_app.h) only
// translates its input into the calls below and draws what overlay() lists; scripts and tests
// drive the same calls in process, without a display.
//
// Order of calls, each frame: setView() with the camera and viewport the user sees; the input
// (press / drag / release in pixels, and the actions of keys: undo, redo, cancel, finishDrawing,
// deleteSelection); then buildOverlay() for what to draw. Picks are made against the overlay
// last built: the points the user saw when clicking.
//
// Ids: picks, the selection and commands name elements by their ids in the scene file, which are
// the document's own for a session holding a whole document. A session reading a scene file
// lazily (editor/lazy_forest.h) shows the elements of its top document and of the parts it holds
// (EditSession::forEachHeldDocument), each once; its commands take the file's ids
// (editor/lazy_edits.h), its edits are saved into the file in place (EditSession::saveEdits).
// The draw tool's new nodes and curve get the ids the session gives (EditSession::nextId).
//
// Lock policy: every command of the controller checks the lock of its layer and is refused on a
// locked layer (the message says so), whether it comes from a tool, a key, a panel or a script.
// Undo and redo walk the history and are not refused: they restore states the user made. The
// session itself (editor/edit_session.h) knows no locks: it is the programming interface, for
// tools such as benchmarks that edit without a user.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "editor/camera.h"
#include "editor/draw_curve.h"
#include "editor/edit_session.h"

namespace lacet {

// Roundabout: a click on a node of the current layer sets its roundabout radius to
// EditingController::roundaboutRadius (0 removes it; model/roundabouts.h says which radii fit).
enum class Tool { Select, Insert, DeletePoint, Draw, Roundabout };

// What the pointer is on: an inner vertex of a curve, a node, or a curve.
struct Pick {
    enum class Kind { None, Vertex, Node, Curve } kind = Kind::None;
    LayerId layer = 0;
    ElementId id = kNoElement;  // curve or node
    std::size_t index = 0;      // vertex index (Kind::Vertex)
    double pixels = 1e30;       // distance on screen (pixels)
};

// The view the user sees and picks in: the camera, the viewport (pixels, y down), the clip range
// (metres), and the ground under a pixel. The window reads it from the depth buffer of the frame
// the user saw; left empty, the controller casts the pixel's ray against the session's displayed
// heights (groundAlongRay).
struct PickView {
    Camera camera;
    int width = 1, height = 1;
    glm::dvec2 clip{1.0, 1e5};
    std::function<std::optional<glm::dvec3>(glm::dvec2 pixel)> ground;
};

// What the overlay shows, in world coordinates: the control polygons of the shown layers' curves
// near the view, their points (those of the current layer can be picked) and the curve being drawn.
struct OverlayPoint {
    enum class Style { OnCurve, Control, Node, Drawing } style = Style::OnCurve;
    glm::dvec3 world{0.0};
    Pick pick;               // what picking it gives (Kind::None: not pickable)
    glm::dvec2 pixel{0.0};   // where it was on screen
    bool current = false;    // of the current layer
    bool selected = false;   // of the selected curve
};
struct OverlayLine {
    enum class Style { Polygon, Selected, Drawing } style = Style::Polygon;
    glm::dvec3 a{0.0}, b{0.0};
};
struct Overlay {
    std::vector<OverlayPoint> points;
    std::vector<OverlayLine> lines;
    std::vector<ElementId> curves;  // the current layer's curves shown (picked by their polygon)
};

// Picks within this distance of a point or a control polygon on screen (pixels).
constexpr double kPickPixels = 10.0;

class EditingController {
public:
    explicit EditingController(EditSession& session);

    // Each message for the user (a refusal and its reason, "Nothing to undo") and each command's
    // report, as they happen.
    std::function<void(const std::string&)> onMessage;
    std::function<void(const CommandReport&)> onCommand;

    // Layers: the current one (the one edited: at first the first roads layer, else the first;
    // setting it shows its points and clears the selection and the curve being drawn), whose
    // points the overlay shows (at first the current one's), which are locked (none at first).
    LayerId currentLayer() const { return current_; }
    void setCurrentLayer(LayerId layer);
    bool pointsShown(LayerId layer) const { return layer < shown_.size() && shown_[layer]; }
    void setPointsShown(LayerId layer, bool shown);
    bool layerLocked(LayerId layer) const { return layer < locked_.size() && locked_[layer]; }
    void setLayerLocked(LayerId layer, bool locked);

    // Tools. Changing the tool drops the curve being drawn.
    Tool tool() const { return tool_; }
    void setTool(Tool tool);
    NewCurveStyle newCurve;  // what the draw tool's curves get
    float roundaboutRadius = 15.0f;  // m, what the roundabout tool sets (0 removes), 0..500
    const std::vector<Vec2>& drawing() const { return drawn_; }
    const Pick& selection() const { return selected_; }

    // A command through the lock policy; false when refused (the message says why).
    bool execute(const Command& command, bool merge = false);
    // The history (not subject to locks). Undo clears the selection.
    bool undo();
    bool redo();
    const CommandReport& lastCommand() const { return lastCommand_; }
    std::size_t commands() const { return commands_; }
    // Keys: Delete deletes the selected curve (the selection is cleared either way); Escape drops the curve being drawn, else the
    // selection; Enter ends the curve being drawn (a curve of its points, joining the nodes it
    // was snapped to, made as one undo step; false when none was made).
    bool deleteSelection();
    // Sets the roundabout radius (m, 0 removes it) of a node of the current layer, as the
    // roundabout tool does: through the lock policy; a radius that does not fit is refused with
    // the reason (false).
    bool setRoundabout(ElementId node, float radius);
    // The selected curve's properties, each one undoable command through the lock policy (false:
    // nothing selected, or refused). The width w (m) raises the footprint wf to it when wf would
    // be narrower; the footprint is set as given (the command refuses wf < w); the class is
    // clamped to 0..65535; a flag bit (model/graph.h: kBridge, kTunnel, kNoBridge, kAlwaysBridge:
    // the graph step's inputs) is set or cleared alone.
    bool setSelectedWidth(float w);
    bool setSelectedFootprint(float wf);
    bool setSelectedClass(int cls);
    bool setSelectedFlag(std::uint16_t bit, bool on);
    // The selected curve, alive (nullptr: none).
    const Curve* selectedCurve() const;
    // Bridges the graph step made from the selected curve (0 when none is selected).
    std::size_t selectedBridges() const;
    void cancel();
    bool finishDrawing();

    // The view of the next input and overlay.
    void setView(const PickView& view) { view_ = view; }
    const PickView& view() const { return view_; }
    // A left press at `pixel`: the tool's action. False when it falls on nothing the tool uses
    // (the select tool on the ground), which the window turns into a pan.
    bool press(glm::dvec2 pixel);
    // The pointer moved with the button down: a point being dragged follows it onto the ground
    // (the first move of a drag begins an undo step, the next ones merge into it).
    void drag(glm::dvec2 pixel);
    void release() { dragging_ = {}; }
    bool dragging() const { return dragging_.kind != Pick::Kind::None; }
    // What is at `pixel` on the current layer (nothing on a locked layer): the nearest point of
    // the last overlay within kPickPixels (a node before a vertex at the same place), else
    // (unless `pointsOnly`) the curve whose control polygon passes nearest.
    Pick pick(glm::dvec2 pixel, bool pointsOnly) const;

    // The overlay of the view: the curves of the layers whose points are shown that have a
    // vertex within 4 viewer heights plus 400 m of where the camera looks (and the selected
    // curve), up to `pointBudget` points, then the curve being drawn.
    const Overlay& buildOverlay(std::size_t pointBudget = 20000);
    const Overlay& overlay() const { return overlay_; }

    // A scene point at its displayed height (EditSession::displayedHeight), its pixel, the ground
    // under a pixel, and the viewer's height above the displayed ground (at least 1 m).
    glm::dvec3 groundPoint(Vec2 p) const { return {p.x, p.y, session_.displayedHeight(p)}; }
    std::optional<glm::dvec2> project(glm::dvec3 world) const;
    std::optional<glm::dvec3> groundAt(glm::dvec2 pixel) const;
    double viewerHeight() const;

private:
    void message(const std::string& text);
    bool pickable(const Pick& p) const;  // still there (the overlay is the last frame's)
    // An element the window sees, by its id in the file: the layer of the document or part that
    // holds it and its id there (layer nullptr: nothing held has it).
    struct Held {
        const Layer* layer = nullptr;
        ElementId id = kNoElement;
    };
    Held held(LayerId layer, ElementKind kind, ElementId file) const;
    std::size_t insertIndex(const Curve& c, glm::dvec2 pixel) const;

    EditSession& session_;
    PickView view_;
    Overlay overlay_;
    Tool tool_ = Tool::Select;
    LayerId current_ = 0;
    std::vector<char> shown_, locked_;
    Pick selected_, dragging_;
    bool dragMoved_ = false;  // the current drag has made its first move
    std::vector<Vec2> drawn_;
    std::vector<ElementId> drawnNodes_;  // per drawn point: the node it was snapped to, or kNoElement
    CommandReport lastCommand_;
    std::size_t commands_ = 0;
};

// How the ray through a pixel is marched to the displayed surface.
struct GroundRayParams {
    double minStepMetres = 1.0;     // the shortest step (m, > 0)
    double stepFraction = 0.01;     // a step's length as a share of the distance along the ray (> 0)
    double precisionMetres = 1e-3;  // where the crossing is bisected to (m, > 0)
};

// Where the ray through `pixel` first meets the session's displayed surface (nullopt: the sky, or
// beyond the far plane): marched in steps, then bisected. A ridge thinner than a step may be
// crossed unseen.
std::optional<glm::dvec3> groundAlongRay(const EditSession& session, const PickView& view, glm::dvec2 pixel,
                                         const GroundRayParams& params = {});

}  // namespace lacet
