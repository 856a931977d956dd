// `lacet render`: produces the tiles of a region at one level of a scene (a scene file, or a
// synthetic scene) and writes them as one mosaic image (the appearance colour, elevation as a
// hillshade, or the footprint). The mosaic's size is known from the scene's extent, the region
// and the level before anything is clipped, so a mosaic over --max-pixels is refused up front
// instead of running out of memory half-way. A scene file is read by parts (--vectors region, issue
// 23): each block of at most --part-tiles tiles a side reads from the file only what its tiles need
// (io/scene_region.h), within --vector-budget MiB, so memory follows the block and the mosaic, not
// the scene; the image is the one the scene read whole gives (--vectors whole).
#include <bit>
#include <cmath>
#include <functional>
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
    // --scene: "region", each block of at most partTiles tiles a side read from the file alone
    // (io/scene_region.h) within vectorBudgetMiB; "whole", the scene read into memory once.
    std::string vectors = "region";
    int partTiles = 16;
    double vectorBudgetMiB = 2048.0;  // MiB of one part's vector data (io/scene_region.h)
    bool partsOptionsGiven = false;   // --vector-budget or --part-tiles on the command line
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

// Subdivides the quads holding tiles of `level` in columns `cols` and rows `rows` down to that
// level; collects those tiles' quads.
void refineTiles(Quadtree& qt, Quad& q, int level, const CellRange& cols, const CellRange& rows, std::vector<const Quad*>& out) {
    const int below = level - q.level;
    const auto overlaps = [&](std::uint32_t t, const CellRange& r) {
        const std::uint64_t first = std::uint64_t(t) << below, last = ((std::uint64_t(t) + 1) << below) - 1;
        return first <= r.last && r.first <= last;
    };
    if (!overlaps(std::uint32_t(q.tx), cols) || !overlaps(std::uint32_t(q.ty), rows)) return;
    if (below == 0) {
        out.push_back(&q);
        return;
    }
    qt.subdivide(q);
    for (auto& c : q.children) refineTiles(qt, *c, level, cols, rows, out);
}

// What the graph steps and curve data of the quadtrees made (one, or one per part) counted.
struct RenderSums {
    std::size_t zProfiles = 0, arcLengthTables = 0;
    std::size_t crossingsTested = 0, crossingsFound = 0, flaggedCrossings = 0, flaggedRoadCrossings = 0, bridgedCrossings = 0,
                culverts = 0, bridgesMade = 0, importedBridges = 0, importedBridgesOverRivers = 0, roundaboutRoads = 0;
    void add(const GraphStepCounters& g, const CurveDataCounters& d) {
        zProfiles += d.zProfiles;
        arcLengthTables += d.arcLengthTables;
        crossingsTested += g.crossingsTested;
        crossingsFound += g.crossingsFound;
        flaggedCrossings += g.flaggedCrossings;
        flaggedRoadCrossings += g.flaggedRoadCrossings;
        bridgedCrossings += g.bridgedCrossings;
        culverts += g.culverts;
        bridgesMade += g.bridgesMade;
        importedBridges += g.importedBridges;
        importedBridgesOverRivers += g.importedBridgesOverRivers;
        roundaboutRoads += g.roundaboutRoads;
    }
};

// The reads of the parts of a render by parts (--vectors region).
struct PartReads {
    std::size_t reads = 0, nodes = 0, curves = 0, areas = 0, largestBytes = 0;
    std::size_t sceneNodes = 0, sceneCurves = 0, sceneAreas = 0;
    bool wholeScene = false;
    double readMs = 0.0;
    void add(const SceneRegionStats& st, double ms) {
        ++reads;
        nodes += st.nodes;
        curves += st.curves;
        areas += st.areas;
        largestBytes = std::max(largestBytes, st.bytes);
        sceneNodes = st.sceneNodes;
        sceneCurves = st.sceneCurves;
        sceneAreas = st.sceneAreas;
        wholeScene = wholeScene || st.wholeScene;
        readMs += ms;
    }
};

void run(const RenderOptions& o) {
    using namespace lacet::bench;
    if (!(o.vectorBudgetMiB > 0.0)) throw std::invalid_argument("--vector-budget must be > 0 MiB");
    if (std::popcount(unsigned(o.partTiles)) != 1) throw std::invalid_argument("--part-tiles must be a power of two");
    if (o.partsOptionsGiven && (o.scene.empty() || o.vectors == "whole"))
        throw std::invalid_argument("--vector-budget and --part-tiles bound the reads of --scene by parts (--vectors region); there is none here");
    Box region;
    if (!o.region.empty()) {
        const auto& r = o.region;
        if (r.size() != 4 || !std::isfinite(r[0]) || !std::isfinite(r[1]) || !std::isfinite(r[2]) || !std::isfinite(r[3]) ||
            !(r[0] < r[2]) || !(r[1] < r[3]))
            throw std::invalid_argument("--region must be four finite numbers X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1 (metres)");
        region = {{r[0], r[1]}, {r[2], r[3]}};
    }
    const bool appearance = o.layer == "appearance";
    const RefineParams refineParams;
    const int n = appearance ? refineParams.resolution : refineParams.elevationResolution;
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
    // The document: the whole scene (a synthetic one, or --vectors whole), or, read by parts, the
    // DEM and georeference alone (each part's vector data is read for its tiles, below).
    SceneDocument doc;
    const bool byParts = !o.scene.empty() && o.vectors == "region";
    if (byParts) {
        doc.scene.extent = loadSceneExtent(o.scene);
    } else if (!o.scene.empty()) {
        doc = loadScene(o.scene);
        if (!doc.dem) throw std::invalid_argument(o.scene + ": the scene file holds no DEM");
    } else {
        const double side = syntheticExtentSide(o.curves);
        check(Box{Vec2(0.0), Vec2(side)});  // before generating: the scene's extent depends on its size only
        doc.scene = makeSyntheticScene({o.seed, o.curves});
        doc.dem = makeSyntheticDem(doc.scene, {o.seed, o.demResolution});
    }
    const Box extent = doc.scene.extent;
    const MosaicPlan plan = check(extent);
    double prepareMs = msSince(t0);

    TerminalProgress progress;
    std::unique_ptr<DemSource> demSource;
    ElevationCounters counters;
    AppearanceCounters appearanceCounters;
    RenderSums sums;
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
    // The tiles of `quads` (of `qt`'s scene) into the mosaic, a batch at a time.
    double clipMs = 0.0, produceMs = 0.0;
    std::size_t made = 0;
    const auto produce = [&](const Scene& scene, const std::function<void(Quadtree&, std::vector<const Quad*>&)>& refine) {
        auto t1 = Clock::now();
        GraphStep graphStep(scene);  // bridges and roundabouts (§4.3)
        Quadtree qt(scene, refineParams, &graphStep);
        std::vector<const Quad*> quads;
        refine(qt, quads);
        clipMs += msSince(t1);
        t1 = Clock::now();
        // A streamed DEM (the scene's LOD tree): each tile reads its window at the level its quad
        // needs and the z-profiles their fixed level, as the editor and the pyramid do; never the
        // coarse level held in memory.
        CurveDataCache data(qt, demSource->heights());
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
        made += quads.size();
        sums.add(graphStep.counters(), data.counters());
        produceMs += msSince(t1);
    };

    std::optional<PartReads> parts;
    progress.begin("producing " + o.layer + " tiles", std::size_t(plan.tiles()), "tiles");
    if (!byParts) {
        demSource = batchDemSource(doc, o.demBudgetMiB);
        produce(doc.scene, [&](Quadtree& qt, std::vector<const Quad*>& quads) {
            quads.reserve(std::size_t(plan.tiles()));
            refineTiles(qt, qt.root(), o.level, plan.columns, plan.rows, quads);
        });
    } else {
        // Blocks of at most --part-tiles tiles a side, each read from the file alone (the curves
        // and areas its tiles need, io/scene_region.h: the same tiles as the whole scene).
        parts.emplace();
        const int shift = std::min(o.level, int(std::bit_width(unsigned(o.partTiles))) - 1);
        const Vec2 tileSide = extent.size() / double(std::uint64_t(1) << o.level);
        bool readWhole = false;  // a file without the feature index: its first read was the whole scene
        for (std::uint32_t by = plan.rows.first >> shift; by <= plan.rows.last >> shift && !readWhole; ++by)
            for (std::uint32_t bx = plan.columns.first >> shift; bx <= plan.columns.last >> shift && !readWhole; ++bx) {
                const CellRange cols{std::max(plan.columns.first, bx << shift), std::min(plan.columns.last, ((bx + 1) << shift) - 1)};
                const CellRange rows{std::max(plan.rows.first, by << shift), std::min(plan.rows.last, ((by + 1) << shift) - 1)};
                // The block's tiles inward by a hair: the quads of the level that meet it are its
                // own alone (io/scene_region.h takes closed boxes), read with the reach around them.
                const Box box{extent.min + (Vec2(double(cols.first), double(rows.first)) + 1e-6) * tileSide,
                              extent.min + (Vec2(double(cols.last + 1), double(rows.last + 1)) - 1e-6) * tileSide};
                auto t1 = Clock::now();
                SceneRegionStats st;
                SceneRegionOptions read;
                read.budgetMiB = o.vectorBudgetMiB;
                read.dem = !demSource;  // the DEM opened with the first part, kept for the others
                SceneDocument part = loadSceneRegion(o.scene, box, refineParams, o.level, &st, read);
                if (!demSource) {
                    if (!part.dem) throw std::invalid_argument(o.scene + ": the scene file holds no DEM");
                    doc.dem = std::move(part.dem);
                    doc.demLod = std::move(part.demLod);
                    doc.georeference = part.georeference;
                    demSource = batchDemSource(doc, o.demBudgetMiB);
                }
                parts->add(st, msSince(t1));
                readWhole = st.wholeScene;
                produce(part.scene, [&](Quadtree& qt, std::vector<const Quad*>& quads) {
                    if (readWhole) refineTiles(qt, qt.root(), o.level, plan.columns, plan.rows, quads);  // every tile from it
                    else refineTiles(qt, qt.root(), o.level, cols, rows, quads);
                });
            }
        prepareMs += parts->readMs;
    }
    progress.end();
    if (made != plan.tiles())
        throw std::logic_error("render: clipping made " + std::to_string(made) + " quads of the region where " +
                               std::to_string(plan.tiles()) + " were planned");

    t0 = Clock::now();
    writeImage8(o.out, int(width), int(height), 3, mosaic);
    const double writeMs = msSince(t0);
    std::cout << "Wrote " << o.out << " (" << width << "x" << height << "): " << made << " tiles of level "
              << o.level << ", " << o.layer << "; scene and DEM " << prepareMs << " ms, clipping " << clipMs
              << " ms, producing " << produceMs << " ms, writing " << writeMs << " ms; elevation curves drawn " << counters.curvesDrawn << ", skipped as thin "
              << counters.curvesSkippedThin << ", lakes " << counters.lakesDrawn << ", z-profiles computed "
              << sums.zProfiles << "; appearance tiles " << appearanceCounters.tiles << " (uniform "
              << appearanceCounters.uniformTiles << "), curves drawn " << appearanceCounters.curvesDrawn << ", with markings "
              << appearanceCounters.curvesWithMarkings << ", markings below a texel " << appearanceCounters.markingsBelowTexel
              << ", area pieces " << appearanceCounters.areaPieces << ", triangles " << appearanceCounters.triangles
              << ", water texels " << appearanceCounters.waterTexels << ", u tables computed "
              << sums.arcLengthTables << "; graph step: crossings tested " << sums.crossingsTested
              << ", found " << sums.crossingsFound << " (imported bridges over rivers "
              << sums.flaggedCrossings << " and over roads " << sums.flaggedRoadCrossings
              << ", unflagged bridged " << sums.bridgedCrossings << ", culverts " << sums.culverts
              << "), bridges made " << sums.bridgesMade << ", imported bridges " << sums.importedBridges
              << " (" << sums.importedBridgesOverRivers << " over a river), roads at roundabouts "
              << sums.roundaboutRoads << ", curves on bridges or tunnels (no footprint) "
              << counters.curvesOnStructures << (parts && parts->reads > 1 ? " (summed over the parts: what several read counts in each)" : "")
              << "\n";
    if (parts) {
        const PartReads& r = *parts;
        std::cout << "Vector data read by parts (--vectors region) of at most " << o.partTiles << " tiles a side: " << r.reads
                  << " reads, " << r.readMs << " ms; " << r.curves << " curves, " << r.areas << " areas, " << r.nodes
                  << " nodes read in all, of the file's " << r.sceneCurves << " curves, " << r.sceneAreas << " areas, "
                  << r.sceneNodes << " nodes; the largest part " << toMiB(r.largestBytes) << " MiB (budget "
                  << o.vectorBudgetMiB << " MiB)" << (r.wholeScene ? "; the file has no feature index (saved before it): it was read whole, once" : "")
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
    cmd->add_option("--vectors", o->vectors,
                    "With --scene: region (default), each block of --part-tiles tiles read from the file alone (memory follows the "
                    "block); whole, the scene read into memory once. The same image")
        ->check(CLI::IsMember({"region", "whole"}));
    CLI::Option* partTiles = cmd->add_option("--part-tiles", o->partTiles, "With --vectors region: tiles a side of each block read (a power of two; 16)")
                                 ->check(CLI::Range(1, 1 << 20));
    CLI::Option* vectorBudget =
        cmd->add_option("--vector-budget", o->vectorBudgetMiB,
                        "With --vectors region: MiB of vector data one block's read may hold (> 0; 2048); past it, refused with the figure");
    cmd->add_option("--dem-resolution", o->demResolution, "Synthetic DEM samples per 100 km (the paper: 5000)");
    cmd->add_option("--max-pixels", o->maxPixels, "Refuse a mosaic of more pixels than this (default 2^28 = 16384 x 16384, 768 MiB of RGB)")
        ->check(CLI::Range(std::int64_t(1), std::numeric_limits<std::int64_t>::max()));
    cmd->callback([o, partTiles, vectorBudget] {
        o->partsOptionsGiven = partTiles->count() > 0 || vectorBudget->count() > 0;
        run(*o);
    });
}

}  // namespace lacet::app
