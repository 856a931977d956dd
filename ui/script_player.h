#pragma once
// Scripted editor sessions (`lacet edit --script S.json`), for tests and for reproducing a bug:
// a JSON object whose "steps" run one after the other, each over one or more frames of the live
// loop, through the same input handling as the window (ui/script_host.h: what a script may do).
// When the steps are done, the log (per
// frame figures, screenshots with their count of background pixels, the steps' results) is
// written to "log" (default session-log.json) in the output folder and the editor exits.
//
// Steps ({"do": ...}):
//   camera      target [x, y] (at its ground height), "scene" (the centre), "drag_from" or
//               "drag_result" (where the last drag began and ended), "focus_node" (the focus
//               curve's start node); distance, yaw, pitch (degrees); fly (bool); in fly mode,
//               position [x, y, height above the ground] or "scene" (with height, default
//               3000 m); or save: NAME / restore: NAME, the whole camera exactly
//   focus       layer (index or name), near [x, y] (default: the scene centre), min_width (m),
//               on_curve (bool): the inner vertex (on-curve only, if asked), nearest `near`, of a
//               curve of that layer at least that wide becomes the focus; with distance/yaw/pitch, the camera looks at it
//   drag_focus  by [dx, dy] metres, steps: presses the mouse on the focus vertex, moves it to the
//               terrain `by` away in `steps` frames, releases; logs where the vertex went
//   wait_idle   max_frames: frames until no visible tile is missing or dirty
//   frames      n: frames
//   wait_ms     ms: real time (a recorded session's pauses), frames running meanwhile
//   screenshot  file (relative to the output folder), panels, overlay (bools)
//   key         name: "ctrl+z", "ctrl+y", "ctrl+s", "escape", "enter", "delete", "f"
//   mouse       action down|up|move, x, y (pixels), button (0 left, 1 right, 2 middle)
//   scroll      dy
//   click_world at [x, y], "focus" or "focus_node" (the focus curve's start node), plus offset
//               [dx, dy]: a left click where that ground point is on screen
//   inspect     logs the focus layer's counts, the selected curve and its end nodes' degrees
//   tool        name: select, insert, delete_point, draw, roundabout (radius: m, what a click on a
//               node makes)
//   save        file (default: the scene's own); open: file
//   background  rgb [r, g, b] in [0, 1]
//   budget      ms: the per-frame production budget; clock_step_ms (optional): the budget is
//               read on a stepped clock advancing that much at each reading (model/work_clock.h),
//               so that what it lets through does not depend on the machine's speed
//   probe       logs what the tiles hold where the last drag began and ended (b, z_o, z_e, z_m,
//               the appearance colour)
//   fly         to [x, y, height above the ground] or "focus" (with height), frames, pitch (degrees), screenshot_every,
//               prefix: the camera flies (fly mode) from where it is, height geometric, position
//               eased; screenshots are taken live, with whatever tiles are ready

#include <chrono>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "editor/camera.h"

namespace lacet::ui {

class ScriptHost;

class ScriptPlayer {
public:
    // Throws std::runtime_error naming the file and the reason when it cannot be read or parsed.
    ScriptPlayer(const std::string& path, const std::string& outDir);
    // Runs the current step for one frame; false when every step is done.
    bool step(ScriptHost& app);
    // Writes the log.
    void finish(ScriptHost& app);

private:
    bool begin(ScriptHost& app, const nlohmann::json& s);     // true: the step is done at once
    bool continueStep(ScriptHost& app, const nlohmann::json& s);  // true: the step is done
    // The longer steps' beginnings (same contract as begin).
    bool beginCamera(ScriptHost& app, const nlohmann::json& s);
    bool beginFocus(ScriptHost& app, const nlohmann::json& s);
    bool beginFly(ScriptHost& app, const nlohmann::json& s);
    bool probe(ScriptHost& app);
    bool inspect(ScriptHost& app);
    std::string path(const std::string& file) const;

    std::string file_, outDir_, logName_ = "session-log.json";
    nlohmann::json steps_;
    std::size_t next_ = 0;
    bool inStep_ = false;
    int frame_ = 0;  // frames spent in the current step
    // The focus vertex and the current step's state.
    bool hasFocus_ = false;
    std::uint32_t focusLayer_ = 0, focusCurve_ = 0;
    std::size_t focusIndex_ = 0;
    glm::dvec2 from_{0.0}, to_{0.0}, lastResult_{0.0};
    glm::dvec3 flyFrom_{0.0}, flyTo_{0.0};
    double flyHeightFrom_ = 0.0;
    std::map<std::string, Camera> saved_;
    std::chrono::steady_clock::time_point stepStart_;
};

}  // namespace lacet::ui
