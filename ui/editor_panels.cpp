// The editor's ImGui panels (EditorApp::drawPanels): layers and tools, the selection's
// properties, statistics and the accuracy knobs, and the prompt before losing unsaved changes.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "ui/editor_app.h"
#include "ui/terrain_renderer.h"

namespace lacet::ui {

void EditorApp::drawPanels() {
    const Scene& scene = session_->document().scene;
    ImGui::SetNextWindowPos({10, 10}, ImGuiCond_FirstUseEver);
    ImGui::Begin("Layers", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    EditingController& ctl = *controller_;
    for (LayerId li = 0; li < scene.layers.size(); ++li) {
        ImGui::PushID(int(li));
        bool points = ctl.pointsShown(li), locked = ctl.layerLocked(li);
        if (ImGui::RadioButton("##current", ctl.currentLayer() == li)) ctl.setCurrentLayer(li);
        ImGui::SameLine();
        bool drawn = session_->layerVisible(li);
        if (ImGui::Checkbox("visible", &drawn)) session_->setLayerVisible(li, drawn);
        ImGui::SameLine();
        if (ImGui::Checkbox("points", &points)) ctl.setPointsShown(li, points);
        ImGui::SameLine();
        if (ImGui::Checkbox("locked", &locked)) ctl.setLayerLocked(li, locked);
        ImGui::SameLine();
        ImGui::Text("%s (%s)", scene.layers[li].name.c_str(), std::string(toString(scene.layers[li].kind)).c_str());
        ImGui::PopID();
    }
    ImGui::Separator();
    int tool = int(ctl.tool());
    ImGui::RadioButton("Select / drag", &tool, int(Tool::Select));
    ImGui::SameLine();
    ImGui::RadioButton("Insert point", &tool, int(Tool::Insert));
    ImGui::RadioButton("Delete point", &tool, int(Tool::DeletePoint));
    ImGui::SameLine();
    ImGui::RadioButton("Draw curve", &tool, int(Tool::Draw));
    ImGui::RadioButton("Roundabout", &tool, int(Tool::Roundabout));
    ctl.setTool(Tool(tool));
    if (ctl.tool() == Tool::Draw) {
        ImGui::TextWrapped("Click points (on a node: a junction); Enter ends, Escape cancels. %zu point(s).", ctl.drawing().size());
        ImGui::InputFloat("width (m)", &ctl.newCurve.width);
        ImGui::InputFloat("footprint (m)", &ctl.newCurve.footprint);
        ImGui::InputInt("class", &ctl.newCurve.cls);
    }
    if (ctl.tool() == Tool::Roundabout) {
        ImGui::TextWrapped("Click a junction node of the current layer: it becomes a roundabout of this radius (0 removes it).");
        ImGui::InputFloat("radius (m)", &ctl.roundaboutRadius);
    }
    ImGui::End();

    ImGui::SetNextWindowPos({10, 230}, ImGuiCond_FirstUseEver);
    ImGui::Begin("Selection", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    const Pick sel = ctl.selection();
    if (const Curve* curve = ctl.selectedCurve()) {
        ImGui::Text("Curve %u of %s: %zu vertices", sel.id, scene.layers[sel.layer].name.c_str(), curve->vertices.size());
        float w = curve->w, wf = curve->wf;
        int cls = curve->cls;
        ImGui::InputFloat("width (m)", &w);
        if (ImGui::IsItemDeactivatedAfterEdit()) ctl.setSelectedWidth(w);
        ImGui::InputFloat("footprint (m)", &wf);
        if (ImGui::IsItemDeactivatedAfterEdit()) ctl.setSelectedFootprint(wf);
        ImGui::InputInt("class", &cls);
        if (ImGui::IsItemDeactivatedAfterEdit()) ctl.setSelectedClass(cls);
        if (scene.layers[sel.layer].kind == LayerKind::Roads) {
            // The graph step's inputs (model/graph_step.h): each box is one undoable command.
            auto flag = [&](const char* label, std::uint16_t bit) {
                bool on = (curve->flags & bit) != 0;
                if (ImGui::Checkbox(label, &on)) ctl.setSelectedFlag(bit, on);
            };
            flag("bridge (the whole curve)", kBridge);
            flag("tunnel", kTunnel);
            flag("no bridge over rivers (ford)", kNoBridge);
            flag("bridge even narrow rivers", kAlwaysBridge);
            ImGui::Text("%zu bridge(s) made by the graph step", ctl.selectedBridges());
        }
        if (ImGui::Button("Delete curve")) ctl.deleteSelection();
    } else {
        ImGui::TextUnformatted("Nothing selected");
    }
    ImGui::End();

    ImGui::SetNextWindowPos({float(width_) - 10.0f, 10}, ImGuiCond_FirstUseEver, {1.0f, 0.0f});
    ImGui::Begin("Statistics", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    const TerrainStats& ts = terrain_->stats();
    ImGui::Text("Frame %zu: update %.1f ms, draw %.1f ms", frames_, lastUpdateMs_, lastRenderMs_);
    ImGui::Text("Quads: %zu in view, %zu culled, %zu drawn (%zu coarser, %zu for the cache)", lastFrame_.viewQuads, lastFrame_.culled, ts.drawn,
                ts.fallback, lastFrame_.replaced);
    ImGui::Text("Tiles: %zu made, %zu prefetched, %zu pending", lastFrame_.produced, lastFrame_.prefetched, lastFrame_.pending);
    ImGui::Text("Cache: %zu / %zu tiles, GPU %zu, %zu uploads", lastFrame_.cached, session_->params().cacheTiles, ts.gpuTiles, ts.uploads);
    const CommandReport& last = ctl.lastCommand();
    ImGui::Text("Work: %zu tiles, %zu commands", tilesProduced_, ctl.commands());
    const GraphStepCounters& gs = session_->graphStep().counters();
    ImGui::Text("Graph step: %zu bridges, %zu ring arcs; %zu crossings found, %zu segment pairs tested",
                session_->quadtree().proceduralCount(kBridge), session_->quadtree().proceduralCount(kRoundabout),
                gs.crossingsFound.load(), gs.crossingsTested.load());
    ImGui::Text("Last edit: apply %.2f ms, UPDATE %.2f ms", last.applyMs, last.updateMs);
    ImGui::Text("  %zu quads changed, %zu tiles dirty", last.changedQuads, last.dirtyTiles);
    ImGui::Text("Undo %zu, redo %zu%s", session_->undoDepth(), session_->redoDepth(), session_->modified() ? ", unsaved" : "");
    ImGui::Text("Viewer %.1f m above the ground%s", viewerHeight(), camera_.fly ? " (fly)" : "");
    ImGui::Separator();
    const PyramidUse& pu = session_->pyramidUse();
    if (const std::optional<PyramidLevels>& pyramid = pyramid_.levels())
        ImGui::Text("Pyramid: open, levels %d to %d read (L = %d, %s)", pyramid->minLevel, pyramid->vectorLevel - 1, pyramid->vectorLevel,
                    pyramid->encoding.c_str());
    else
        ImGui::TextUnformatted("Pyramid: none (every tile made live)");
    ImGui::Text("  appearance tiles: %zu read, %zu failed, %zu live (%zu touched by edits)", pu.read, pu.failed, pu.live, pu.touched);
    if (pyramid_.updating()) {
        ImGui::TextUnformatted("  updating after the last save...");
    } else if (const std::optional<PyramidUpdateResult>& u = pyramid_.last()) {
        if (!u->ok())
            ImGui::TextWrapped("  last update (edit %llu) failed: %s", static_cast<unsigned long long>(u->madeAt), u->error.c_str());
        else
            ImGui::Text("  last update (edit %llu): %zu of %zu quads changed, %zu tiles made, %zu written in %.1f s%s",
                        static_cast<unsigned long long>(u->madeAt), u->quadsChanged, u->quads, u->tilesMade, u->tilesWritten, u->seconds,
                        u->rebuilt ? " (rebuilt)" : "");
    }
    if (const DemStream* dem = session_->demStream()) {
        const DemStreamStats st = dem->stats();
        const DemLodLayout& L = dem->layout();
        ImGui::Separator();
        ImGui::Text("DEM: streamed, %d x %d samples of %.1f m, %d levels", L.width, L.height, L.cell, L.levels);
        ImGui::Text("  blocks: %zu held (%.1f of %.1f MiB), %zu pending, %llu loaded, %llu evicted", st.held, st.heldMiB,
                    dem->params().budgetMiB, st.pending, static_cast<unsigned long long>(st.loaded),
                    static_cast<unsigned long long>(st.evicted));
        ImGui::Text("  tiles from a coarser block this frame: %zu; remade finer: %zu", lastFrame_.demFallbacks, lastFrame_.demRemade);
    }
    if (const LazyForest* lazy = session_->lazyForest()) {
        const LazyStats& st = lazy->stats();
        ImGui::Separator();
        ImGui::Text("Vector data: read lazily, parts of level %d (%.0f m); edits saved in place", st.partLevel,
                    session_->document().scene.extent.size().x / double(std::int64_t(1) << st.partLevel));
        ImGui::Text("  parts: %zu held (%.1f of %.1f MiB beside the top's %.1f), %zu read, %zu evicted, %zu refused", st.partsHeld,
                    st.heldMiB, lazy->params().vectorBudgetMiB - st.topMiB, st.topMiB, st.partsRead, st.partsEvicted, st.partsRefused);
        if (!st.lastError.empty()) ImGui::TextWrapped("  last part refused: %s", st.lastError.c_str());
    }
    ImGui::Separator();
    ImGui::TextUnformatted("Accuracy");
    float K = float(adaptive_ ? adaptive_->userK() : session_->params().view.K);
    if (ImGui::SliderFloat(adaptive_ ? "K (at most)" : "K", &K, 1.0f, 8.0f)) {
        session_->setK(K);
        if (adaptive_) adaptive_->setUserK(K);
    }
    if (adaptive_)
        ImGui::Text("  adaptive: K %.2f for frames of %.0f ms (%d lowered, %d raised)", adaptive_->K(), options_.adaptiveMs,
                    adaptive_->lowered(), adaptive_->raised());
    float tol = float(session_->params().refine.toleranceTexels);
    ImGui::SliderFloat("tolerance (texels)", &tol, 0.1f, 4.0f);
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        RefineParams r = session_->params().refine;
        r.toleranceTexels = tol;
        session_->setRefineParams(r);
        terrain_->reset();
    }
    int res = session_->params().refine.resolution;
    const int choices[] = {64, 128, 256, 512};
    if (ImGui::BeginCombo("texture (texels)", std::to_string(res).c_str())) {
        for (int c : choices)
            if (ImGui::Selectable(std::to_string(c).c_str(), c == res) && c != res) {
                RefineParams r = session_->params().refine;
                r.resolution = c;
                session_->setRefineParams(r);
                terrain_->reset();
            }
        ImGui::EndCombo();
    }
    float budget = float(options_.budgetMs);
    if (ImGui::SliderFloat("budget (ms/frame)", &budget, 1.0f, 100.0f)) options_.budgetMs = budget;
    ImGui::Checkbox("wireframe", &terrain_->wireframe);
    if (!status_.empty()) {
        ImGui::Separator();
        ImGui::TextWrapped("%s", status_.c_str());
    }
    ImGui::End();

    if (confirmClose_) {
        ImGui::OpenPopup("Unsaved changes");
        confirmClose_ = false;
    }
    if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::Text("The scene has unsaved changes.");
        if (ImGui::Button("Save and quit")) {
            save({});
            closing_ = !session_->modified();
            if (closing_) glfwSetWindowShouldClose(window_, GLFW_TRUE);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Quit without saving")) {
            closing_ = true;
            glfwSetWindowShouldClose(window_, GLFW_TRUE);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

}  // namespace lacet::ui
