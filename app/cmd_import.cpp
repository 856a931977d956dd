// `lacet import`: a DEM and GIS vector files into one scene file (GeoPackage), with progress on
// stderr (app/progress_bar.h) and the report at the end; `lacet info`: what a scene file holds.
// The import checks every path before any work (io/import_paths.h) and fails, writing nothing,
// when an input cannot be read or nothing would be kept (io/scene_import.h).
#include <iostream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/import_summary.h"
#include "app/progress_bar.h"
#include "io/dem_import_lod.h"
#include "io/dem_lod.h"
#include "io/import_paths.h"
#include "io/scene_file.h"
#include "io/scene_import.h"

namespace lacet::app {
namespace {

struct ImportCli {
    ImportOptions options;
    std::string demStorage = "auto";
    std::string out;
    bool force = false;
    bool json = false;
};

nlohmann::json sceneInfo(const SceneDocument& doc, const std::string& path) {
    nlohmann::json layers = nlohmann::json::array();
    for (const Layer& l : doc.scene.layers) {
        std::size_t nodes = 0, curves = 0, areas = 0, vertices = 0;
        for (const Node& n : l.nodes) nodes += n.alive;
        for (const Curve& c : l.curves)
            if (c.alive) ++curves, vertices += c.vertices.size();
        for (const Area& a : l.areas) areas += a.alive;
        layers.push_back({{"name", l.name}, {"kind", std::string(toString(l.kind))}, {"nodes", nodes}, {"curves", curves},
                          {"areas", areas}, {"vertices", vertices}});
    }
    nlohmann::json j = {{"file", path},
                        {"extent_m", {doc.scene.extent.min.x, doc.scene.extent.min.y, doc.scene.extent.max.x, doc.scene.extent.max.y}},
                        {"layers", layers}};
    if (doc.georeference.valid) j["crs"] = {{"lon0", doc.georeference.lon0}, {"lat0", doc.georeference.lat0}, {"wkt", doc.georeference.crsWkt}};
    if (doc.dem) j["dem"] = {{"width", doc.dem->width()}, {"height", doc.dem->height()}, {"cell_m", doc.dem->cellSize().x}};
    if (doc.demLod) {
        const DemLodLayout& l = doc.demLod->layout();
        j["dem_lod"] = {{"width", l.width}, {"height", l.height}, {"cell_m", l.cell}, {"levels", l.levels}, {"block_side", l.blockSide}};
    }
    return j;
}

}  // namespace

void addImportCommand(CLI::App& app) {
    auto o = std::make_shared<ImportCli>();
    CLI::App* cmd = app.add_subcommand("import", "Import a DEM and GIS vector layers into a scene file");
    cmd->add_option("--dem", o->options.dem,
                    "DEM rasters (GeoTIFF, SRTM .hgt, /vsizip/...: anything GDAL reads), VRTs or directories of tiles; "
                    "several make a mosaic. None: flat ground (--flat-height)");
    cmd->add_option("--vectors", o->options.vectors, "Vector files (OSM PBF/XML, Shapefile, GeoJSON, GeoPackage). None: a DEM-only scene");
    cmd->add_option("--mapping", o->options.mapping, "Mapping file (JSON; default: OSM roads, rivers, lakes, fields, forests)");
    cmd->add_option("--tolerance", o->options.fitTolerance,
                    "Spline fitting tolerance: the Hausdorff distance between each curve and its source (m, 0 to 100)");
    cmd->add_option("--dem-cell", o->options.demCell, "Scene DEM cell (m, 0.1 to 10000; default: the source's resolution)");
    cmd->add_option("--dem-storage", o->demStorage,
                    "How the DEM is stored: grid (in memory), lod (a tree of blocks written out of core, for DEMs larger than "
                    "memory), auto (lod above " + std::to_string(kInMemoryDemSide) + " samples a side; the default)");
    cmd->add_option("--flat-height", o->options.flatHeight, "Height of the flat ground when no DEM is given (m)");
    cmd->add_option("--min-kept", o->options.minKept, "Fail unless the vectors give at least this many curves and areas (default 1)");
    cmd->add_flag("--allow-empty", o->options.allowEmpty, "Accept an import that keeps fewer than --min-kept features");
    cmd->add_option("--vector-budget", o->options.vectorBudgetMiB,
                    "Import the vectors out of core, a part's build within about this much memory (MiB; 0: in memory, the "
                    "default): features spilled to a file beside --out as they are read, the scene built and written a square "
                    "part at a time. The reader (GDAL's, a quarter of the budget on disk past it) and the libraries add a fixed "
                    "200 MiB or so, whatever the extract");
    cmd->add_option("--vector-part-level", o->options.vectorPartLevel,
                    "Out of core, with parts 2^level a side (0 to 8) instead of those --vector-budget chooses");
    cmd->add_option("--out", o->out, "Scene file to write (GeoPackage)")->required();
    cmd->add_flag("--force", o->force, "Replace --out even when it is not a Lacet scene");
    cmd->add_flag("--json", o->json, "Print the report as JSON");
    cmd->callback([o] {
        o->options.demStorage = demStorageFromString(o->demStorage);
        checkImportOptions(o->options);
        checkImportPaths({o->options.dem, o->options.vectors, o->options.mapping, o->out, o->force});
        // A lod DEM's file: a new name beside the output (the save copies the tree from there).
        if (o->options.demStorage != DemStorage::Grid && !o->options.dem.empty())
            o->options.demLodPath = uniqueDemLodPath(o->out);
        ImportReport report;
        TerminalProgress progress;
        importSceneToFile(o->options, o->out, report, &progress);
        for (const std::string& w : report.warnings) std::cerr << "lacet import: warning: " << w << "\n";
        if (o->json) std::cout << report.json().dump(2) << "\n";
        else printImportSummary(std::cout, report, o->out);
    });

    auto path = std::make_shared<std::string>();
    auto json = std::make_shared<bool>(false);
    CLI::App* info = app.add_subcommand("info", "What a scene file holds");
    info->add_option("scene", *path, "Scene file (GeoPackage)")->required();
    info->add_flag("--json", *json, "Print JSON (the only format)");
    info->callback([path, json] {
        if (isPyramidFile(*path)) printPyramidInfo(*path);  // a pyramid: every tile checked
        else std::cout << sceneInfo(loadScene(*path), *path).dump(2) << "\n";
    });
}

}  // namespace lacet::app
