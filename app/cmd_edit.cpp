// `lacet edit [scene.gpkg] [--script S.json]`: the editor's window (ui/editor_app.h).
#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "ui/editor_app.h"

namespace lacet::app {

void addEditCommand(CLI::App& app) {
    auto o = std::make_shared<ui::EditorOptions>();
    auto* cmd = app.add_subcommand("edit", "Open the 3D editor (the Andorra scene when its data is there, else a synthetic one)");
    cmd->add_option("scene", o->scene, "Scene file (GeoPackage from lacet import or the editor)");
    cmd->add_option("--script", o->script, "Replay a scripted session (JSON), write its screenshots and log, and exit");
    cmd->add_option("--out", o->outDir, "Folder for a script's screenshots and log");
    cmd->add_option("--andorra", o->andorraDir, "Folder of the Andorra data (OSM extract and SRTM tile)");
    cmd->add_option("--curves", o->syntheticCurves, "Curves of the synthetic scene when no Andorra data is there");
    cmd->add_option("--width", o->width, "Window width (pixels)");
    cmd->add_option("--height", o->height, "Window height (pixels)");
    cmd->add_option("--budget", o->budgetMs, "Tile production budget per frame (ms)");
    cmd->add_option("--cache-tiles", o->cacheTiles, "Tile pairs the cache keeps; past it the farthest quads are shown in place of their children")
        ->check(CLI::PositiveNumber);
    cmd->callback([o] {
        if (!o->script.empty()) std::filesystem::create_directories(o->outDir);
        ui::EditorApp editor(*o);
        editor.run();
    });
}

}  // namespace lacet::app
