// `lacet edit [scene.gpkg] [--script S.json] [--pyramid FILE | --no-pyramid]`: the editor's window
// (ui/editor_app.h) on a scene file; without one, on the Andorra sample imported on the spot (its
// import report printed, as `lacet import` prints it) when its data is there, else on a synthetic
// scene. A scene file's pyramid (§7: `lacet pyramid build`, by default beside it as
// NAME.pyramid.gpkg) gives the appearance of the coarse quads and is updated after each save.
// With --vector-budget the scene file is read lazily (editor/lazy_forest.h), edited, and saved into
// itself in place (io/scene_save_edits.h), new curves drawn included.
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "app/import_summary.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "pyramid/pyramid_build.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "ui/editor_app.h"

namespace lacet::app {
namespace {

struct EditCli {
    ui::EditorOptions editor;
    std::string scene;                              // a scene file; empty: the sample
    std::string andorraDir = "../shared/data/andorra";
    std::size_t syntheticCurves = 60000;
};

// The Andorra sample's files (© OpenStreetMap contributors, ODbL; SRTM: NASA/USGS), as
// samples/andorra/import.sh reads them.
constexpr const char* kAndorraVectors = "andorra-2021-04-14.osm.pbf";
constexpr const char* kAndorraDemZip = "N42E001.hgt.zip";
constexpr const char* kAndorraDemInZip = "N42E001.hgt";

ui::EditorDocument chooseDocument(const EditCli& o) {
    ui::EditorDocument d;
    if (!o.scene.empty()) {
        d.lazy = o.editor.vectorBudgetMiB > 0.0;
        if (!d.lazy) d.document = loadScene(o.scene, d.storedChecksum);
        d.path = d.label = o.scene;
        return d;
    }
    const std::filesystem::path dir(o.andorraDir);
    const std::string pbf = (dir / kAndorraVectors).string(), zip = (dir / kAndorraDemZip).string();
    if (std::filesystem::exists(pbf) && std::filesystem::exists(zip)) {
        ImportOptions io;
        io.dem = {"/vsizip/" + zip + "/" + kAndorraDemInZip};
        io.vectors = {pbf};
        ImportReport report;
        d.document = importScene(io, report);
        for (const std::string& w : report.warnings) std::cerr << "lacet edit: warning: " << w << "\n";
        printImportSummary(std::cout, report, "the editor (not saved until Ctrl+S)");
        std::ostringstream m;
        m << "Andorra imported: " << report.featuresRead << " features read, " << report.problemCount() << " problems (the report is on the terminal)";
        d.message = m.str();
        d.label = "andorra";
        return d;
    }
    d.document.scene = makeSyntheticScene({1, o.syntheticCurves});
    d.document.dem = makeSyntheticDem(d.document.scene, {1, 5000});
    d.label = "synthetic";
    return d;
}

}  // namespace

void addEditCommand(CLI::App& app) {
    auto o = std::make_shared<EditCli>();
    auto* cmd = app.add_subcommand("edit", "Open the 3D editor (the Andorra scene when its data is there, else a synthetic one)");
    cmd->add_option("scene", o->scene, "Scene file (GeoPackage from lacet import or the editor)");
    cmd->add_option("--script", o->editor.script, "Replay a scripted session (JSON), write its screenshots and log, and exit");
    cmd->add_option("--out", o->editor.outDir, "Folder for a script's screenshots and log");
    cmd->add_option("--andorra", o->andorraDir, "Folder of the Andorra data (OSM extract and SRTM tile)");
    cmd->add_option("--curves", o->syntheticCurves, "Curves of the synthetic scene when no Andorra data is there");
    cmd->add_option("--width", o->editor.width, "Window width (pixels)");
    cmd->add_option("--height", o->editor.height, "Window height (pixels)");
    cmd->add_option("--budget", o->editor.budgetMs, "Tile production budget per frame (ms)");
    cmd->add_option("--pyramid", o->editor.pyramid,
                    "Pyramid file (lacet pyramid build) for the coarse quads' appearance; default: the scene's NAME.pyramid.gpkg when it exists");
    cmd->add_flag("--no-pyramid", o->editor.noPyramid, "Make every tile live, even when the scene has a pyramid");
    cmd->add_option("--adaptive", o->editor.adaptiveMs,
                    "Lower K while frames take longer than this, raise it back when there is room (ms; 0: K fixed; "
                    "scripted sessions keep K fixed)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--background-ms", o->editor.backgroundMs,
                    "Make quads whose tiles or subdivision would take longer than this (ms) on a background thread, so that no "
                    "frame waits for them (0: in the frames; default 1, and 0 in scripted sessions)");
    cmd->add_option("--dem-budget", o->editor.demBudgetMiB, "Memory for the blocks of a streamed DEM (MiB)")->check(CLI::PositiveNumber);
    cmd->add_option("--cache-tiles", o->editor.cacheTiles,
                    "Tile pairs the cache keeps; past it the farthest quads are shown in place of their children")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--vector-budget", o->editor.vectorBudgetMiB,
                    "Read the scene file's vector data lazily within this many MiB, as the view needs it (0: load it whole); "
                    "its edits, new curves drawn included, are saved into the file in place")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--part-level", o->editor.partLevel,
                    "With --vector-budget: the level of the quads read as one part (-1: quads at most 5 km wide)");
    cmd->callback([o] {
        if (o->editor.vectorBudgetMiB > 0.0 && o->scene.empty()) throw CLI::ValidationError("--vector-budget needs a scene file");
        if (!o->editor.script.empty()) std::filesystem::create_directories(o->editor.outDir);
        if (!o->editor.pyramid.empty() && o->editor.noPyramid) throw CLI::ValidationError("--pyramid and --no-pyramid exclude each other");
        if (!o->editor.pyramid.empty() && !std::filesystem::exists(o->editor.pyramid))
            throw CLI::ValidationError("--pyramid: " + o->editor.pyramid + " does not exist");
        if (o->editor.pyramid.empty() && !o->editor.noPyramid && !o->scene.empty()) {
            const std::string p = defaultPyramidPath(o->scene);
            if (std::filesystem::exists(p)) o->editor.pyramid = p;
        }
        if (!o->editor.pyramid.empty() && o->scene.empty())
            throw CLI::ValidationError("--pyramid needs a scene file (the pyramid is that file's)");
        ui::EditorDocument doc = chooseDocument(*o);
        const bool synthetic = doc.label == "synthetic";
        ui::EditorApp editor(o->editor, std::move(doc));
        if (synthetic) editor.log()["synthetic_curves"] = o->syntheticCurves;
        editor.run();
    });
}

}  // namespace lacet::app
