// `lacet render`: produces the tiles of a region at one level of a scene (a scene file, or a
// synthetic scene) and writes them as one mosaic image (the appearance colour, elevation as a
// hillshade, or the footprint).
#include <iostream>
#include <sstream>

#include "app/commands.h"
#include "bench/bench_util.h"
#include "io/image_file.h"
#include "io/scene_file.h"
#include "model/synthetic_scene.h"
#include "raster/dem_height_field.h"
#include "raster/parallel_producers.h"
#include "raster/synthetic_dem.h"
#include "raster/tile_images.h"

namespace lacet::app {
namespace {

struct RenderOptions {
    std::uint64_t seed = 1;
    std::size_t curves = 10000;
    std::vector<double> region;  // x0, y0, x1, y1 (m); empty: the whole scene
    int level = 5;
    std::string layer = "elevation";
    std::string out = "render.png";
    int demResolution = 5000;
    std::string scene;  // a scene file instead of the synthetic scene
};

// Subdivides every quad meeting `region` down to `level`; collects the quads of that level.
void refineRegion(Quadtree& qt, Quad& q, const Box& region, int level, std::vector<const Quad*>& out) {
    if (!q.bounds.intersects(region)) return;
    if (q.level == level) {
        out.push_back(&q);
        return;
    }
    qt.subdivide(q);
    for (auto& c : q.children) refineRegion(qt, *c, region, level, out);
}

void run(const RenderOptions& o) {
    using namespace lacet::bench;
    auto t0 = Clock::now();
    SceneDocument doc;
    if (!o.scene.empty()) {
        doc = loadScene(o.scene);
        if (!doc.dem) throw std::invalid_argument(o.scene + ": the scene file holds no DEM");
    } else {
        doc.scene = makeSyntheticScene({o.seed, o.curves});
        doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    }
    const Scene& scene = doc.scene;
    const Dem& dem = *doc.dem;
    const double prepareMs = msSince(t0);
    Box region = scene.extent;
    if (!o.region.empty()) {
        if (o.region.size() != 4 || !(o.region[0] < o.region[2]) || !(o.region[1] < o.region[3]))
            throw std::invalid_argument("--region must be X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1 (metres)");
        region = {{o.region[0], o.region[1]}, {o.region[2], o.region[3]}};
    }
    Quadtree qt(scene);
    std::vector<const Quad*> quads;
    t0 = Clock::now();
    refineRegion(qt, qt.root(), region, o.level, quads);
    const double clipMs = msSince(t0);
    if (quads.empty()) throw std::invalid_argument("--region does not meet the scene extent");
    DemHeightField heights(dem);
    CurveDataCache data(qt, heights);
    ElevationCounters counters;
    AppearanceCounters appearanceCounters;
    const bool appearance = o.layer == "appearance";
    const int n = appearance ? qt.params().resolution : qt.params().elevationResolution;
    std::vector<std::vector<std::uint8_t>> images(quads.size());
    t0 = Clock::now();
    if (appearance) {
        const auto tiles = produceAppearanceTiles(quads, qt, data, dem, {}, &appearanceCounters);
        for (std::size_t k = 0; k < quads.size(); ++k) appearanceImage(tiles[k], images[k]);
    } else {
        const auto tiles = produceElevationTiles(quads, qt, data, dem, {}, &counters);
        for (std::size_t k = 0; k < quads.size(); ++k) {
            if (o.layer == "footprint") footprintImage(tiles[k], images[k]);
            else hillshade(tiles[k], images[k]);
        }
    }
    const double produceMs = msSince(t0);

    std::uint32_t x0 = UINT32_MAX, y0 = UINT32_MAX, x1 = 0, y1 = 0;
    for (const Quad* q : quads) {
        x0 = std::min(x0, q->tx), y0 = std::min(y0, q->ty);
        x1 = std::max(x1, q->tx), y1 = std::max(y1, q->ty);
    }
    const int width = int(x1 - x0 + 1) * n, height = int(y1 - y0 + 1) * n;
    std::vector<std::uint8_t> mosaic(std::size_t(width) * std::size_t(height) * 3, 0);
    for (std::size_t k = 0; k < quads.size(); ++k) {
        const int ox = int(quads[k]->tx - x0) * n, oy = int(y1 - quads[k]->ty) * n;  // north up
        for (int r = 0; r < n; ++r)
            std::copy_n(images[k].begin() + std::ptrdiff_t(r) * n * 3, n * 3,
                        mosaic.begin() + (std::ptrdiff_t(oy + r) * width + ox) * 3);
    }
    writeImage8(o.out, width, height, 3, mosaic);
    std::cout << "Wrote " << o.out << " (" << width << "x" << height << "): " << quads.size() << " tiles of level "
              << o.level << ", " << o.layer << "; scene and DEM " << prepareMs << " ms, clipping " << clipMs
              << " ms, producing " << produceMs << " ms; elevation curves drawn " << counters.curvesDrawn << ", skipped as thin "
              << counters.curvesSkippedThin << ", lakes " << counters.lakesDrawn << ", z-profiles computed "
              << data.counters().zProfiles << "; appearance tiles " << appearanceCounters.tiles << " (uniform "
              << appearanceCounters.uniformTiles << "), curves drawn " << appearanceCounters.curvesDrawn << ", with markings "
              << appearanceCounters.curvesWithMarkings << ", markings below a texel " << appearanceCounters.markingsBelowTexel
              << ", area pieces " << appearanceCounters.areaPieces << ", triangles " << appearanceCounters.triangles
              << ", water texels " << appearanceCounters.waterTexels << ", u tables computed "
              << data.counters().arcLengthTables << "\n";
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Produce the tiles of a region at one level and write them as one image");
    cmd->add_option("--scene", o->scene, "Scene file (GeoPackage from lacet import) instead of a synthetic scene");
    cmd->add_option("--seed", o->seed, "Random seed of the synthetic scene and DEM");
    cmd->add_option("--curves", o->curves, "Target number of curves of the synthetic scene");
    cmd->add_option("--region", o->region, "X0,Y0,X1,Y1 in metres (default: the whole scene)")->delimiter(',');
    cmd->add_option("--level", o->level, "Quadtree level of the tiles")->check(CLI::Range(0, 24));
    cmd->add_option("--layer", o->layer, "appearance (colour), elevation (hillshade of z_m) or footprint (b)")->check(CLI::IsMember({"appearance", "elevation", "footprint"}));
    cmd->add_option("--out", o->out, "Output image (PNG, TIFF...)");
    cmd->add_option("--dem-resolution", o->demResolution, "Synthetic DEM samples per 100 km (the paper: 5000)");
    cmd->callback([o] { run(*o); });
}

}  // namespace lacet::app
