// `lacet render`: produces the tiles of a region at one level of a scene (a scene file, or a
// synthetic scene) and writes them as one mosaic image (the appearance colour, elevation as a
// hillshade, or the footprint). The mosaic's size is known from the scene's extent, the region
// and the level before anything is clipped, so a mosaic over --max-pixels is refused up front
// instead of running out of memory half-way.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "app/commands.h"
#include "app/progress_bar.h"
#include "bench/bench_util.h"
#include "io/dem_stream.h"
#include "io/image_file.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "model/graph_step.h"
#include "model/view_params.h"
#include "raster/parallel_producers.h"
#include "raster/tile_images.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

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
    std::int64_t maxPixels = std::int64_t(1) << 28;  // 16384 x 16384: 768 MiB of RGB; signed, so that -1 is refused
    double demBudgetMiB = DemStreamParams{}.budgetMiB;  // a streamed DEM's blocks held at once
    double vectorBudgetMiB = SceneRegionOptions{}.budgetMiB;  // --region: the vector data read (io/scene_region.h)
};

// Tiles go to the producers in batches of this many, so that progress moves and only one
// batch of tiles is held at a time (a whole level's would take more memory than its mosaic).
constexpr std::size_t kBatchTiles = 64;

// The cells of one axis at `level` that meet [a, b]: [lo, hi] halved `level` times at its
// midpoint exactly as Quadtree::childBounds halves a quad's bounds, cells closed as
// Box::intersects takes them. [a, b] must meet [lo, hi].
struct CellRange {
    std::uint32_t first = 0, last = 0;
    std::uint64_t count() const { return std::uint64_t(last - first) + 1; }
};
CellRange meetingCells(double lo, double hi, double a, double b, int level) {
    CellRange r;
    double firstLo = lo, firstHi = hi, lastLo = lo, lastHi = hi;
    for (int l = 0; l < level; ++l) {
        // The first cell is in the lower half when that half meets [a, b], the last in the upper.
        const double firstMid = (firstLo + firstHi) * 0.5;
        if (a <= firstMid) {
            firstHi = firstMid;
            r.first = 2 * r.first;
        } else {
            firstLo = firstMid;
            r.first = 2 * r.first + 1;
        }
        const double lastMid = (lastLo + lastHi) * 0.5;
        if (lastMid <= b) {
            lastLo = lastMid;
            r.last = 2 * r.last + 1;
        } else {
            lastHi = lastMid;
            r.last = 2 * r.last;
        }
    }
    return r;
}

// The tiles of a level meeting a region, and the mosaic they make.
struct MosaicPlan {
    CellRange columns, rows;
    int texels = 0;  // per tile side
    std::uint64_t tiles() const { return columns.count() * rows.count(); }
    std::uint64_t width() const { return columns.count() * std::uint64_t(texels); }
    std::uint64_t height() const { return rows.count() * std::uint64_t(texels); }
    double pixels() const { return double(width()) * double(height()); }  // exact below 2^53
};

MosaicPlan planMosaic(const Box& extent, const Box& region, int level, int texels) {
    return {meetingCells(extent.min.x, extent.max.x, region.min.x, region.max.x, level),
            meetingCells(extent.min.y, extent.max.y, region.min.y, region.max.y, level), texels};
}

// 268,435,456
std::string grouped(double v) {
    char digits[64];
    std::snprintf(digits, sizeof digits, "%.0f", v);
    const std::string plain = digits;
    std::string s;
    for (std::size_t i = 0; i < plain.size(); ++i) {
        if (i > 0 && (plain.size() - i) % 3 == 0) s += ',';
        s += plain[i];
    }
    return s;
}

// Throws when the mosaic of `plan` is over the limit, saying what it would be and what fits.
void checkMosaicSize(const MosaicPlan& plan, const Box& extent, const Box& region, const RenderOptions& o) {
    constexpr std::uint64_t kMaxSide = std::numeric_limits<int>::max();  // image files' limit
    const auto tooWide = [&](const MosaicPlan& p) { return p.width() > kMaxSide || p.height() > kMaxSide; };
    const auto over = [&](const MosaicPlan& p) { return p.pixels() > double(o.maxPixels) || tooWide(p); };
    if (!over(plan)) return;
    int fits = o.level;
    while (fits >= 0 && over(planMosaic(extent, region, fits, plan.texels))) --fits;
    std::ostringstream m;
    m << "render: level " << o.level << " of " << (o.region.empty() ? "the whole scene" : "--region") << " is "
      << grouped(double(plan.tiles())) << " tiles (" << grouped(double(plan.columns.count())) << " x "
      << grouped(double(plan.rows.count())) << ") of " << plan.texels << " x " << plan.texels << " texels: a "
      << grouped(double(plan.width())) << " x " << grouped(double(plan.height())) << " pixel image ("
      << grouped(plan.pixels()) << " pixels, " << grouped(plan.pixels() * 3.0) << " bytes of RGB), ";
    if (tooWide(plan)) m << "wider than an image file can be (" << grouped(double(kMaxSide)) << " pixels a side)";
    else m << "over the limit of " << grouped(double(o.maxPixels)) << " pixels (--max-pixels)";
    m << ". Choose a smaller --region or a lower --level";
    if (fits >= 0) m << " (level " << fits << " is the deepest that fits)";
    throw std::invalid_argument(m.str());
}

// Subdivides every quad meeting `region` down to `level`; collects the quads of that level.
void refineRegion(Quadtree& qt, Quad& q, const Box& region, int level, std::vector<const Quad*>& out, Progress& progress) {
    if (!q.bounds.intersects(region)) return;
    if (q.level == level) {
        out.push_back(&q);
        progress.advance();
        return;
    }
    qt.subdivide(q);
    for (auto& c : q.children) refineRegion(qt, *c, region, level, out, progress);
}

void run(const RenderOptions& o) {
    using namespace lacet::bench;
    if (!(o.vectorBudgetMiB > 0.0)) throw std::invalid_argument("--vector-budget must be > 0 MiB");
    if (std::isfinite(o.vectorBudgetMiB) && (o.region.empty() || o.scene.empty()))
        throw std::invalid_argument("--vector-budget bounds the read of --region from --scene; without both there is no such read");
    Box region;
    if (!o.region.empty()) {
        const auto& r = o.region;
        if (r.size() != 4 || !std::isfinite(r[0]) || !std::isfinite(r[1]) || !std::isfinite(r[2]) || !std::isfinite(r[3]) ||
            !(r[0] < r[2]) || !(r[1] < r[3]))
            throw std::invalid_argument("--region must be four finite numbers X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1 (metres)");
        region = {{r[0], r[1]}, {r[2], r[3]}};
    }
    const bool appearance = o.layer == "appearance";
    const RefineParams refine;
    const int n = appearance ? refine.resolution : refine.elevationResolution;
    // Refuses a region or a mosaic of a scene of this extent before any work on it.
    const auto check = [&](const Box& extent) {
        if (o.region.empty()) region = extent;
        if (!region.intersects(extent)) {
            std::ostringstream m;
            m << "--region " << region.min.x << "," << region.min.y << "," << region.max.x << "," << region.max.y
              << " does not meet the scene, whose extent is " << extent.min.x << "," << extent.min.y << ","
              << extent.max.x << "," << extent.max.y << " (metres)";
            throw std::invalid_argument(m.str());
        }
        const MosaicPlan plan = planMosaic(extent, region, o.level, n);
        checkMosaicSize(plan, extent, region, o);
        return plan;
    };

    auto t0 = Clock::now();
    SceneDocument doc;
    std::optional<SceneRegionStats> regionStats;
    if (!o.scene.empty()) {
        // A region reads only the vector data its tiles need, found through the feature tables'
        // R-trees (io/scene_region.h): the same tiles as the whole scene, in memory that follows
        // the region.
        if (o.region.empty()) {
            doc = loadScene(o.scene);
        } else {
            regionStats.emplace();
            SceneRegionOptions read;
            read.budgetMiB = o.vectorBudgetMiB;
            doc = loadSceneRegion(o.scene, region, refine, o.level, &*regionStats, read);
        }
        if (!doc.dem) throw std::invalid_argument(o.scene + ": the scene file holds no DEM");
    } else {
        const double side = syntheticExtentSide(o.curves);
        check(Box{Vec2(0.0), Vec2(side)});  // before generating: the scene's extent depends on its size only
        doc.scene = makeSyntheticScene({o.seed, o.curves});
        doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    }
    const Scene& scene = doc.scene;
    const MosaicPlan plan = check(scene.extent);
    const double prepareMs = msSince(t0);

    TerminalProgress progress;
    GraphStep graphStep(scene);  // bridges and roundabouts (§4.3)
    Quadtree qt(scene, refine, &graphStep);
    std::vector<const Quad*> quads;
    quads.reserve(std::size_t(plan.tiles()));
    t0 = Clock::now();
    progress.begin("clipping", std::size_t(plan.tiles()), "quads");
    refineRegion(qt, qt.root(), region, o.level, quads, progress);
    progress.end();
    const double clipMs = msSince(t0);
    if (quads.size() != plan.tiles())
        throw std::logic_error("render: clipping made " + std::to_string(quads.size()) + " quads of the region where " +
                               std::to_string(plan.tiles()) + " were planned");

    // A streamed DEM (the scene's LOD tree): each tile reads its window at the level its quad needs
    // and the z-profiles their fixed level, as the editor and the pyramid do; never the coarse
    // level held in memory.
    const std::unique_ptr<DemSource> demSource = batchDemSource(doc, o.demBudgetMiB);
    const HeightField& heights = demSource->heights();
    CurveDataCache data(qt, heights);
    ElevationCounters counters;
    AppearanceCounters appearanceCounters;
    const std::size_t width = std::size_t(plan.width()), height = std::size_t(plan.height());
    std::vector<std::uint8_t> mosaic(width * height * 3, 0);
    std::vector<std::uint8_t> image;
    // Copies a tile's picture into the mosaic, north up.
    const auto place = [&](const Quad& q) {
        const std::size_t ox = std::size_t(q.tx - plan.columns.first) * std::size_t(n);
        const std::size_t oy = std::size_t(plan.rows.last - q.ty) * std::size_t(n);
        for (std::size_t r = 0; r < std::size_t(n); ++r)
            std::copy_n(image.begin() + std::ptrdiff_t(r * std::size_t(n) * 3), n * 3,
                        mosaic.begin() + std::ptrdiff_t(((oy + r) * width + ox) * 3));
    };
    t0 = Clock::now();
    progress.begin("producing " + o.layer + " tiles", quads.size(), "tiles");
    for (std::size_t begin = 0; begin < quads.size(); begin += kBatchTiles) {
        const std::span<const Quad* const> batch(quads.data() + begin, std::min(kBatchTiles, quads.size() - begin));
        if (appearance) {
            const auto tiles = produceAppearanceTiles(batch, qt, data, *demSource, {}, &appearanceCounters);
            for (std::size_t k = 0; k < batch.size(); ++k) {
                appearanceImage(tiles[k], image);
                place(*batch[k]);
            }
        } else {
            const auto tiles = produceElevationTiles(batch, qt, data, *demSource, {}, &counters);
            for (std::size_t k = 0; k < batch.size(); ++k) {
                if (o.layer == "footprint") footprintImage(tiles[k], image);
                else hillshade(tiles[k], image);
                place(*batch[k]);
            }
        }
        progress.advance(batch.size());
    }
    progress.end();
    const double produceMs = msSince(t0);

    t0 = Clock::now();
    writeImage8(o.out, int(width), int(height), 3, mosaic);
    const double writeMs = msSince(t0);
    std::cout << "Wrote " << o.out << " (" << width << "x" << height << "): " << quads.size() << " tiles of level "
              << o.level << ", " << o.layer << "; scene and DEM " << prepareMs << " ms, clipping " << clipMs
              << " ms, producing " << produceMs << " ms, writing " << writeMs << " ms; elevation curves drawn " << counters.curvesDrawn << ", skipped as thin "
              << counters.curvesSkippedThin << ", lakes " << counters.lakesDrawn << ", z-profiles computed "
              << data.counters().zProfiles << "; appearance tiles " << appearanceCounters.tiles << " (uniform "
              << appearanceCounters.uniformTiles << "), curves drawn " << appearanceCounters.curvesDrawn << ", with markings "
              << appearanceCounters.curvesWithMarkings << ", markings below a texel " << appearanceCounters.markingsBelowTexel
              << ", area pieces " << appearanceCounters.areaPieces << ", triangles " << appearanceCounters.triangles
              << ", water texels " << appearanceCounters.waterTexels << ", u tables computed "
              << data.counters().arcLengthTables << "; graph step: crossings tested " << graphStep.counters().crossingsTested
              << ", found " << graphStep.counters().crossingsFound << " (imported bridges over rivers "
              << graphStep.counters().flaggedCrossings << " and over roads " << graphStep.counters().flaggedRoadCrossings
              << ", unflagged bridged " << graphStep.counters().bridgedCrossings << ", culverts " << graphStep.counters().culverts
              << "), bridges made " << graphStep.counters().bridgesMade << ", imported bridges " << graphStep.counters().importedBridges
              << " (" << graphStep.counters().importedBridgesOverRivers << " over a river), roads at roundabouts "
              << graphStep.counters().roundaboutRoads << ", curves on bridges or tunnels (no footprint) "
              << counters.curvesOnStructures << "\n";
    if (regionStats) {
        const SceneRegionStats& r = *regionStats;
        std::cout << "Vector data of the region: " << r.curves << " of " << r.sceneCurves << " curves, " << r.areas << " of "
                  << r.sceneAreas << " areas, " << r.nodes << " of " << r.sceneNodes << " nodes read, "
                  << toMiB(r.bytes) << " MiB ("
                  << r.found << " found within " << r.reach << " m of its quads through the R-trees, the rest what they depend on)"
                  << (r.wholeScene ? "; the file has no feature index (saved before it): the whole scene was read" : "")
                  << "\n";
    }
    if (const auto* streamed = dynamic_cast<const StreamedDem*>(demSource.get())) {
        const DemStreamStats d = streamed->stats();
        std::cout << "Streamed DEM: " << d.windows << " windows at the level each quad needs (" << d.fallbacks
                  << " from a coarser one), " << d.loaded << " blocks read, " << d.evicted << " dropped, " << d.failed
                  << " unreadable, " << d.loadMs << " ms reading\n";
    }
}

}  // namespace

void addRenderCommand(CLI::App& app) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand("render", "Produce the tiles of a region at one level and write them as one image");
    cmd->add_option("--scene", o->scene, "Scene file (GeoPackage from lacet import) instead of a synthetic scene");
    cmd->add_option("--seed", o->seed, "Random seed of the synthetic scene and DEM");
    cmd->add_option("--curves", o->curves, "Target number of curves of the synthetic scene");
    cmd->add_option("--region", o->region, "X0,Y0,X1,Y1 in metres (default: the whole scene)")->delimiter(',');
    cmd->add_option("--level", o->level, "Quadtree level of the tiles")->check(CLI::Range(0, ViewParams{}.maxLevel));
    cmd->add_option("--layer", o->layer, "appearance (colour), elevation (hillshade of z_m) or footprint (b)")->check(CLI::IsMember({"appearance", "elevation", "footprint"}));
    cmd->add_option("--out", o->out, "Output image (PNG, TIFF...)");
    cmd->add_option("--dem-budget", o->demBudgetMiB, "MiB of a streamed DEM's blocks held at once (a scene with a DEM LOD tree)");
    cmd->add_option("--vector-budget", o->vectorBudgetMiB,
                    "With --region: MiB of vector data the read may hold (> 0; default: no bound); past it, refused with the figure");
    cmd->add_option("--dem-resolution", o->demResolution, "Synthetic DEM samples per 100 km (the paper: 5000)");
    cmd->add_option("--max-pixels", o->maxPixels, "Refuse a mosaic of more pixels than this (default 2^28 = 16384 x 16384, 768 MiB of RGB)")
        ->check(CLI::Range(std::int64_t(1), std::numeric_limits<std::int64_t>::max()));
    cmd->callback([o] { run(*o); });
}

}  // namespace lacet::app
