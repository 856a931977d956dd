// `lacet pyramid build|update|info`: precomputed texture pyramids (§7) in a GeoPackage
// (pyramid/pyramid_build.h), and `--shards` for a build split over the ranks of an MPI job
// (app/pyramid_mpi.h, when built with LACET_MPI).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/progress_bar.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_check.h"

namespace lacet::app {
namespace {

struct PyramidOptions {
    std::string scene;
    std::string out;
    std::string levels;  // "A-B" or "B"
    std::string layers = "appearance,elevation";
    std::string encoding = "jpeg:90";
    double texel = 1.0;
    int vectorLevels = 1;
    int shardLevel = -1;
    int passLevels = PyramidParams{}.passLevels;
    double shardElements = PyramidParams{}.shardElements;
    double demBudgetMiB = PyramidParams{}.demBudgetMiB;
    double vectorBudgetMiB = PyramidParams{}.vectorBudgetMiB;
    bool force = false;
    bool json = false;
    bool shards = false;
    std::string vectors = "region";  // how the vector data is read: by shard from the file (region), or whole
};

// The pyramid's vector data out of core (PyramidJob over the scene file: each shard reads its
// part) or the whole document in memory; the same tiles either way.
bool readsByRegion(const PyramidOptions& o) {
    if (o.vectors != "region" && o.vectors != "whole")
        throw std::invalid_argument("--vectors: '" + o.vectors + "' is neither region nor whole");
    return o.vectors == "region";
}

PyramidParams paramsOf(const PyramidOptions& o) {
    PyramidParams p;
    if (!o.levels.empty()) {
        int a = 0, b = 0;
        char dash = 0, extra = 0;
        std::istringstream in(o.levels);
        if ((in >> a >> dash >> b) && dash == '-' && !(in >> extra)) {
            p.minLevel = a;
            p.maxLevel = b;
        } else {
            std::istringstream one(o.levels);
            if (!(one >> b) || (one >> extra)) throw std::invalid_argument("--levels must be A-B or B (levels, 0 <= A <= B <= 24)");
            p.maxLevel = b;
        }
        if (p.minLevel < 0 || p.maxLevel < p.minLevel || p.maxLevel > 24)
            throw std::invalid_argument("--levels must be A-B or B with 0 <= A <= B <= 24");
    }
    p.appearance = p.elevation = false;
    std::istringstream layers(o.layers);
    for (std::string l; std::getline(layers, l, ',');) {
        if (l == "appearance") p.appearance = true;
        else if (l == "elevation") p.elevation = true;
        else throw std::invalid_argument("--layers: unknown layer '" + l + "' (appearance, elevation)");
    }
    p.texel = o.texel;
    p.vectorLevels = o.vectorLevels;
    p.shardLevel = o.shardLevel;
    p.passLevels = o.passLevels;
    p.shardElements = o.shardElements;
    p.demBudgetMiB = o.demBudgetMiB;
    p.vectorBudgetMiB = o.vectorBudgetMiB;
    p.encoding = parseEncoding(o.encoding);
    return p;
}

SceneDocument loadForPyramid(const std::string& scene) {
    SceneDocument doc = loadScene(scene);
    if (!doc.dem) std::cerr << "lacet pyramid: warning: " << scene << " holds no DEM: the ground is flat at 0 m\n";
    return doc;
}

void checkOut(const PyramidOptions& o, const std::string& out) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(out) && fs::exists(o.scene) && fs::equivalent(out, o.scene, ec))
        throw std::invalid_argument("--out " + out + " is the scene file, which every save rewrites: the pyramid goes beside it");
}

}  // namespace

void addPyramidCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand("pyramid", "Precomputed texture pyramids (§7): build, update, info");
    cmd->require_subcommand(1);

    auto b = std::make_shared<PyramidOptions>();
    CLI::App* build = cmd->add_subcommand("build", "Build the appearance and elevation tile pyramid of a scene (GeoPackage)");
    build->add_option("scene", b->scene, "Scene file (GeoPackage from lacet import)")->required();
    build->add_option("--out", b->out, "Pyramid file (default: SCENE with .pyramid.gpkg)");
    build->add_option("--levels", b->levels, "Levels A-B (or B: 0-B); default: down to --texel metres per texel");
    build->add_option("--texel", b->texel, "Metres per texel the default deepest level reaches (> 0)");
    build->add_option("--layers", b->layers, "appearance,elevation (either or both)");
    build->add_option("--encoding", b->encoding, "Colour tiles: jpeg[:QUALITY], png[:ZLIB LEVEL] or webp[:QUALITY]");
    build->add_option("--vector-levels", b->vectorLevels, "Deepest levels made from vector data (>= 1); the rest mipmapped");
    build->add_option("--shard-level", b->shardLevel,
                      "Level of the subtrees the build goes by (default: deepest - 4, deeper where a shard would hold over "
                      "--shard-elements curves and areas)");
    build->add_option("--shard-elements", b->shardElements,
                      "Curves and areas a shard holds at most by default (> 0; a shard's part is what a build holds in memory)");
    build->add_option("--pass-levels", b->passLevels,
                      "Levels of a shard made at once (>= 1); a deeper shard goes depth first (less memory, less parallel)");
    build->add_option("--dem-budget", b->demBudgetMiB,
                      "MiB of a streamed DEM's blocks held at once (each quad reads its window at the level it needs)");
    build->add_option("--vector-budget", b->vectorBudgetMiB,
                      "MiB of vector data held at once, reading by region (> 0): a shard's part that would pass it is refused "
                      "with the figure; the next part is read ahead only when both fit");
    build->add_flag("--force", b->force, "Replace a pyramid built for another scene in --out");
    build->add_flag("--shards", b->shards, "Run the shards on the ranks of an MPI job (mpirun -np N lacet pyramid build ... --shards)");
    build->add_flag("--json", b->json, "Print the figures as JSON");
    build->add_option("--vectors", b->vectors,
                      "region (default): each shard reads only its part of the scene file (out of core); whole: the scene "
                      "read into memory once. The same tiles");
    build->callback([b] {
        const std::string out = b->out.empty() ? defaultPyramidPath(b->scene) : b->out;
        checkOut(*b, out);
        PyramidParams params = paramsOf(*b);
        const bool region = readsByRegion(*b);
        if (!region) params.sceneChecksum = loadSceneOutline(b->scene).checksum;  // the file's form of it
        if (b->shards) {
            runShardedPyramidBuild(b->scene, out, params, b->force, b->json, region);
            return;
        }
        TerminalProgress progress;
        const PyramidStats s = region ? buildPyramid(b->scene, out, params, b->force, &progress)
                                      : buildPyramid(loadForPyramid(b->scene), out, params, b->force, &progress);
        printPyramidStats(s, "built", out, b->json);
    });

    auto u = std::make_shared<PyramidOptions>();
    CLI::App* update = cmd->add_subcommand("update", "Remake the tiles of a pyramid whose inputs changed since it was built");
    update->add_option("scene", u->scene, "Scene file")->required();
    update->add_option("--pyramid", u->out, "Pyramid file (default: SCENE with .pyramid.gpkg)");
    update->add_option("--dem-budget", u->demBudgetMiB, "MiB of a streamed DEM's blocks held at once");
    update->add_option("--vector-budget", u->vectorBudgetMiB, "MiB of vector data held at once, reading by region (> 0)");
    update->add_flag("--json", u->json, "Print the figures as JSON");
    update->add_option("--vectors", u->vectors, "region (default): out of core, by shard; whole: the scene in memory. The same tiles");
    update->callback([u] {
        const std::string path = u->out.empty() ? defaultPyramidPath(u->scene) : u->out;
        TerminalProgress progress;
        if (!(u->vectorBudgetMiB > 0.0)) throw std::invalid_argument("--vector-budget must be > 0 MiB");
        const PyramidStats s = readsByRegion(*u) ? updatePyramid(u->scene, path, &progress, u->demBudgetMiB, u->vectorBudgetMiB)
                                                 : updatePyramid(loadForPyramid(u->scene), path, &progress, u->demBudgetMiB,
                                                                 loadSceneOutline(u->scene).checksum);
        printPyramidStats(s, "updated", path, u->json);
    });

    auto path = std::make_shared<std::string>();
    CLI::App* info = cmd->add_subcommand("info", "What a pyramid holds; every tile decoded (exit 2 when one is corrupt or missing)");
    info->add_option("pyramid", *path, "Pyramid file")->required();
    info->callback([path] { printPyramidInfo(*path); });
}

nlohmann::json pyramidStatsJson(const PyramidStats& s, const std::string& path) {
    const auto& t = s.times;
    const double tiles = double(s.tilesMade);
    return {{"pyramid", path},
            {"quads", s.quads},
            {"quads_changed", s.quadsChanged},
            {"peak_shard_quads", s.peakShardQuads},
            {"vector_mib", {{"peak", s.peakVectorMiB}, {"top", s.topVectorMiB}, {"largest_part", s.largestPartMiB}}},
            {"reads_not_ahead", s.readsNotAhead},
            {"whole_file_checked", s.wholeFileChecked},
            {"tiles_made", s.tilesMade},
            {"tiles_written", s.tilesWritten},
            {"rebuilt", s.rebuilt},
            {"stored", {{"appearance", s.appearanceTiles}, {"water", s.waterTiles}, {"elevation", s.elevationTiles}}},
            {"bytes", s.bytes},
            {"wall_s", s.wallSeconds},
            {"tiles_per_s", s.wallSeconds > 0 ? tiles / s.wallSeconds : 0.0},
            {"thread_seconds",
             {{"clip", t.clip}, {"digest", t.digest}, {"elevation", t.elevation}, {"appearance", t.appearance},
              {"mipmap", t.mipmap}, {"encode", t.encode}, {"decode", t.decode}, {"write", t.write}, {"dem", t.dem}}},
            {"dem", s.dem.streamed ? nlohmann::json{{"streamed", true},
                                                    {"windows", s.dem.windows},
                                                    {"fallbacks", s.dem.fallbacks},
                                                    {"windows_at_level", s.dem.windowsAtLevel},
                                                    {"blocks_read", s.dem.blocksRead},
                                                    {"blocks_evicted", s.dem.blocksEvicted},
                                                    {"blocks_failed", s.dem.blocksFailed},
                                                    {"read_s", s.dem.readSeconds}}
                                   : nlohmann::json{{"streamed", false}}}};
}

void printPyramidStats(const PyramidStats& s, const std::string& what, const std::string& path, bool json) {
    if (json) {
        std::cout << pyramidStatsJson(s, path).dump(2) << "\n";
        return;
    }
    const auto& t = s.times;
    std::printf("%s %s: %zu quads (%zu changed), %zu tiles made, %zu written; stored %zu appearance, %zu water, %zu elevation "
                "tiles, %.1f MB; %.2f s (%.0f tiles/s)\n  thread seconds: clip %.2f, digest %.2f, elevation %.2f, appearance %.2f, "
                "mipmap %.2f, encode %.2f, decode %.2f, write %.2f\n",
                what.c_str(), path.c_str(), s.quads, s.quadsChanged, s.tilesMade, s.tilesWritten, s.appearanceTiles, s.waterTiles,
                s.elevationTiles, double(s.bytes) / 1e6, s.wallSeconds, s.wallSeconds > 0 ? double(s.tilesMade) / s.wallSeconds : 0.0,
                t.clip, t.digest, t.elevation, t.appearance, t.mipmap, t.encode, t.decode, t.write);
    if (s.dem.streamed)
        std::printf("  streamed DEM: %llu windows at the level each quad needs (%llu from a coarser one), %llu blocks read, %llu "
                    "dropped, %llu unreadable, %.2f s reading\n",
                    (unsigned long long)s.dem.windows, (unsigned long long)s.dem.fallbacks, (unsigned long long)s.dem.blocksRead,
                    (unsigned long long)s.dem.blocksEvicted, (unsigned long long)s.dem.blocksFailed, s.dem.readSeconds);
    if (s.rebuilt) std::printf("  the scene's DEM, layers or a knob changed since the build: every tile was remade\n");
}

void printPyramidInfo(const std::string& path) {
    const PyramidCheck c = checkPyramid(path);
    std::cout << c.json().dump(2) << "\n";
    if (!c.problems.empty()) {
        std::cerr << "lacet: " << path << ": " << c.problems.size() << " tile(s) corrupt or missing, first: " << c.problems[0].table
                  << " level " << c.problems[0].quad.level << " column " << c.problems[0].quad.tx << ": " << c.problems[0].reason
                  << "\n";
        std::exit(2);
    }
}

#ifndef LACET_MPI
void runShardedPyramidBuild(const std::string&, const std::string&, const PyramidParams&, bool, bool, bool) {
    throw std::invalid_argument("--shards needs MPI: this lacet was built without it (cmake -DLACET_MPI=ON, Open MPI from Debian's libopenmpi-dev)");
}
#endif

}  // namespace lacet::app
