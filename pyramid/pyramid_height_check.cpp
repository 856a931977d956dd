#include "pyramid/pyramid_height_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "io/dem_stream.h"
#include "io/scene_file.h"
#include "io/scene_region.h"
#include "io/tile_codec.h"
#include "pyramid/pyramid_store.h"

namespace lacet {

namespace {

// The cells elevationCells() stores for a quad of `bounds` whose z_m is the DEM's height: the mean
// of each cell's four corners, in the same float arithmetic, rows from the top.
std::vector<float> cellsFromDem(const Dem& dem, const Box& bounds, int n) {
    const double delta = bounds.size().x / double(n);
    const std::size_t side = std::size_t(n) + 1;
    std::vector<float> zo(side * side);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) zo[std::size_t(j) * side + std::size_t(i)] = float(dem.sample(bounds.min + Vec2(double(i), double(j)) * delta));
    const auto at = [&](int i, int j) { return zo[std::size_t(j) * side + std::size_t(i)]; };
    std::vector<float> cells(std::size_t(n) * std::size_t(n));
    for (int row = 0; row < n; ++row) {
        const int j = n - 1 - row;
        for (int i = 0; i < n; ++i)
            cells[std::size_t(row) * std::size_t(n) + std::size_t(i)] = 0.25f * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1));
    }
    return cells;
}

// The least share of a tile's cells that must agree with a level for the tile to be its (the
// footprints of roads, rivers and lakes, which agree with no level, cover the rest).
constexpr double kDecidingFraction = 0.1;

double quantile(std::vector<float>& v, double q) {
    if (v.empty()) return 0.0;
    const std::size_t k = std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5));
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
    return v[k];
}

// The quads of `level` checked: a grid of at most `tiles` spread evenly over the level.
std::vector<std::pair<std::uint32_t, std::uint32_t>> spreadQuads(int level, int tiles) {
    const std::uint64_t n = std::uint64_t(1) << level;
    const std::uint64_t g = std::min<std::uint64_t>(n, std::uint64_t(std::ceil(std::sqrt(double(tiles)))));
    std::vector<std::pair<std::uint32_t, std::uint32_t>> quads;
    for (std::uint64_t b = 0; b < g; ++b)
        for (std::uint64_t a = 0; a < g && quads.size() < std::size_t(tiles); ++a)
            quads.emplace_back(std::uint32_t((2 * a + 1) * n / (2 * g)), std::uint32_t((2 * b + 1) * n / (2 * g)));
    return quads;
}

}  // namespace

std::size_t PyramidHeightCheck::tilesElsewhere() const {
    std::size_t n = 0;
    for (const HeightLevelMatch& l : levels)
        if (l.demLevel != neededLevel) n += l.tilesBest;
    return n;
}

bool PyramidHeightCheck::passed() const { return tilesElsewhere() == 0 && tilesChecked > tilesUndecided; }

nlohmann::json PyramidHeightCheck::json() const {
    nlohmann::json ls = nlohmann::json::array();
    for (const HeightLevelMatch& l : levels)
        ls.push_back({{"dem_level", l.demLevel},
                      {"cell_m", l.cellM},
                      {"cells_within", l.cellsWithin},
                      {"fraction_within", cells ? double(l.cellsWithin) / double(cells) : 0.0},
                      {"median_m", l.medianM},
                      {"p90_m", l.p90M},
                      {"max_m", l.maxM},
                      {"tiles_best", l.tilesBest}});
    return {{"level", level},
            {"dem", {{"streamed", streamed}, {"levels", demLevels}, {"finest_level", demLevels - 1}}},
            {"needed_level", neededLevel},
            {"needed_is_finest", neededLevel == demLevels - 1},
            {"tolerance_m", toleranceM},
            {"tiles_checked", tilesChecked},
            {"tiles_missing", tilesMissing},
            {"tiles_undecided", tilesUndecided},
            {"tiles_elsewhere", tilesElsewhere()},
            {"cells", cells},
            {"dem_levels", ls},
            {"ms", ms},
            {"passed", passed()}};
}

PyramidHeightCheck checkPyramidHeights(const std::string& scenePath, const std::string& pyramidPath,
                                       const PyramidHeightCheckParams& params) {
    if (params.tiles < 1 || params.tiles > kMaxHeightCheckTiles)
        throw std::invalid_argument("the tiles checked must be 1 to " + std::to_string(kMaxHeightCheckTiles));
    if (!(params.toleranceM > 0.0) || !std::isfinite(params.toleranceM)) throw std::invalid_argument("the tolerance must be > 0 m");
    const auto t0 = std::chrono::steady_clock::now();
    PyramidStore store(pyramidPath, PyramidStore::Mode::ReadOnly);
    const auto info = store.info();
    if (!info) throw PyramidError(pyramidPath + ": the file holds no Lacet pyramid (lacet_pyramid table)");
    if (!info->elevation) throw PyramidError(pyramidPath + ": the pyramid stores no elevation tiles");
    if (!info->complete) throw PyramidError(pyramidPath + ": the pyramid is incomplete (its build did not finish)");
    const SceneOutline outline = loadSceneOutline(scenePath);
    if (!(outline.extent == info->extent))
        throw PyramidError(pyramidPath + ": the pyramid was made for another extent than the scene " + scenePath + "'s");
    if (!info->sceneChecksum.empty() && info->sceneChecksum != outline.checksum)
        throw PyramidError(pyramidPath + ": the pyramid was made from another state of " + scenePath +
                           " (edited since: run lacet pyramid update)");
    PyramidHeightCheck c;
    c.level = params.level < 0 ? info->maxLevel : params.level;
    if (c.level < info->minLevel || c.level > info->maxLevel)
        throw PyramidError(pyramidPath + ": the pyramid stores levels " + std::to_string(info->minLevel) + "-" +
                           std::to_string(info->maxLevel) + ", not " + std::to_string(c.level));
    c.toleranceM = params.toleranceM;

    // The DEM as the build read it: the tree when there is one, else the DEM in memory. Read with
    // the curves near a corner at the deepest level (a handful), never the scene's vector data.
    const Box corner{outline.extent.min, outline.extent.min + outline.extent.size() * 1e-9};
    const SceneDocument head = loadSceneRegion(scenePath, corner, RefineParams{}, 30);
    if (!head.dem && !head.demLod) throw SceneFileError(scenePath + ": the scene has no DEM: its heights are 0 m, nothing to check");
    std::unique_ptr<DemStream> stream;
    if (head.demLod) {
        stream = std::make_unique<DemStream>(head.demLod, DemStreamParams{.budgetMiB = params.demBudgetMiB, .background = false});
        c.streamed = true;
        c.demLevels = stream->layout().levels;
    }

    const int n = info->elevationSize;
    const std::uint64_t side = std::uint64_t(1) << c.level;
    const Vec2 quadSize = info->extent.size() / double(side);
    const DemNeed need0 = quadDemNeed(Box{info->extent.min, info->extent.min + quadSize});
    c.neededLevel = stream ? stream->layout().levelFor(need0.spacing) : 0;
    const int last = stream ? c.demLevels - 1 : 0;
    for (int l = 0; l <= last; ++l) c.levels.push_back({l, stream ? stream->layout().levelCell(l) : head.dem->cellSize().x});
    std::vector<std::vector<float>> diffs(c.levels.size());

    for (const auto& [tx, ty] : spreadQuads(c.level, params.tiles)) {
        const auto blob = store.tile(kElevationTable, PyramidKey{c.level, tx, ty});
        if (!blob) {
            ++c.tilesMissing;
            continue;
        }
        const DecodedFloats stored = decodeFloatTiff(*blob);
        if (stored.width != n || stored.height != n)
            throw PyramidError(pyramidPath + ": elevation tile " + std::to_string(c.level) + "/" + std::to_string(tx) + "/" +
                               std::to_string(ty) + " is not " + std::to_string(n) + "x" + std::to_string(n));
        const Vec2 min = info->extent.min + Vec2(double(tx), double(ty)) * quadSize;
        const Box bounds{min, min + quadSize};
        const DemNeed need = quadDemNeed(bounds);
        std::vector<std::size_t> within(c.levels.size(), 0);
        for (std::size_t k = 0; k < c.levels.size(); ++k) {
            std::shared_ptr<const Dem> dem;
            if (stream) {
                const DemWindow w = stream->windowNow(need.box, stream->layout().levelCell(c.levels[k].demLevel));
                if (w.level != c.levels[k].demLevel)
                    throw DemLodError(scenePath + ": the DEM tree's level " + std::to_string(c.levels[k].demLevel) +
                                      " cannot be read under elevation tile " + std::to_string(c.level) + "/" + std::to_string(tx) +
                                      "/" + std::to_string(ty) + " (a block is corrupt or missing)");
                dem = w.dem;
            } else {
                dem = std::shared_ptr<const Dem>(std::shared_ptr<const Dem>(), &*head.dem);
            }
            const std::vector<float> made = cellsFromDem(*dem, bounds, n);
            for (std::size_t i = 0; i < made.size(); ++i) {
                const double d = std::abs(double(stored.values[i]) - double(made[i]));
                diffs[k].push_back(float(d));
                within[k] += d <= params.toleranceM;
            }
            c.levels[k].cellsWithin += within[k];
        }
        ++c.tilesChecked;
        c.cells += std::size_t(n) * std::size_t(n);
        // The tile's source: the level most cells agree with, when at least kDecidingFraction of
        // them do (footprints cover the rest); a tie at the top, or too few, decides nothing.
        std::vector<std::size_t> order(c.levels.size());
        for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return within[a] > within[b]; });
        const double cellsOfTile = double(n) * double(n);
        if (double(within[order[0]]) < kDecidingFraction * cellsOfTile || (order.size() > 1 && within[order[0]] == within[order[1]]))
            ++c.tilesUndecided;
        else
            ++c.levels[order[0]].tilesBest;
    }
    for (std::size_t k = 0; k < c.levels.size(); ++k) {
        HeightLevelMatch& l = c.levels[k];
        if (diffs[k].empty()) continue;
        l.maxM = *std::max_element(diffs[k].begin(), diffs[k].end());
        l.p90M = quantile(diffs[k], 0.9);
        l.medianM = quantile(diffs[k], 0.5);
    }
    c.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return c;
}

}  // namespace lacet
