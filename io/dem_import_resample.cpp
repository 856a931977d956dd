// The DEM import's resampling (io/dem_import.h): the scene grid, the source window under rows of
// it, the window read with its voids, the harmonic fill, the bilinear resampling of a row.
#include <algorithm>
#include <cmath>
#include <tuple>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "io/dem_import_internal.h"

namespace lacet {
namespace {

// Scene points to the source CRS, in place; ok[k] false where the transformation fails.
void toSource(const DemSourceInfo& src, std::vector<double>& xs, std::vector<double>& ys, std::vector<int>& ok) {
    ok.assign(xs.size(), 1);
    if (src.fromWgs84) src.fromWgs84->Transform(int(xs.size()), xs.data(), ys.data(), nullptr, ok.data());
    for (std::size_t k = 0; k < xs.size(); ++k) ok[k] = ok[k] && std::isfinite(xs[k]) && std::isfinite(ys[k]);
}

// The centres of columns [i0, i1] of grid row j in the source CRS: xs, ys (n = i1 - i0 + 1 each),
// ok[m] false where the transformation fails (toSource).
void rowToSource(const DemSourceInfo& src, const SceneFrame& frame, const dem_detail::SceneGrid& grid, int j, int i0, int i1,
                 std::vector<double>& xs, std::vector<double>& ys, std::vector<int>& ok) {
    const std::size_t n = std::size_t(i1 - i0 + 1);
    xs.resize(n), ys.resize(n);
    for (int i = i0; i <= i1; ++i) {
        const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
        xs[std::size_t(i - i0)] = ll.x, ys[std::size_t(i - i0)] = ll.y;
    }
    toSource(src, xs, ys, ok);
}

}  // namespace

namespace dem_detail {

SceneGrid makeSceneGrid(const std::string& name, const Box& extent, double cellSize, double maxSide) {
    if (!(extent.size().x > 0.0) || !(extent.size().y > 0.0))
        throw DemImportError(name + ": the scene extent must have a positive size");
    const double longSide = std::max(extent.size().x, extent.size().y), shortSide = std::min(extent.size().x, extent.size().y);
    const std::string range = "the DEM cell must be between " + number(longSide / maxSide) + " and " + number(shortSide / 1.5) +
                              " m over this " + number(extent.size().x) + " x " + number(extent.size().y) + " m extent";
    if (!std::isfinite(cellSize) || !(cellSize > 0.0)) throw DemImportError(name + ": " + range);
    const std::string aCell = name + ": a " + number(cellSize) + " m cell over this extent would make ";
    if (longSide / cellSize > maxSide)
        throw DemImportError(aCell + "more than " + number(maxSide) + " samples a side (" + range + ")");
    SceneGrid g;
    g.extent = extent;
    g.width = int(std::lround(extent.size().x / cellSize));
    g.height = int(std::lround(extent.size().y / cellSize));
    // round(side / cell) >= 2 for cell <= side / 1.5: the range's upper bound.
    if (g.width < 2 || g.height < 2) throw DemImportError(aCell + "fewer than 2 samples a side (" + range + ")");
    g.cell = extent.size() / Vec2(g.width, g.height);
    return g;
}

SourceWindow borderWindow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j0, int j1, int coveredBorder[4]) {
    const double* gt = src.geoTransform;
    std::vector<double> xs, ys;
    std::vector<int> ok, side;
    for (int i = 0; i < grid.width; ++i)
        for (int j : {j0, j1}) {
            const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
            xs.push_back(ll.x), ys.push_back(ll.y), side.push_back(j == j0 ? 0 : 1);
        }
    for (int j = j0 + 1; j < j1; ++j)
        for (int i : {0, grid.width - 1}) {
            const glm::dvec2 ll = frame.reverse(grid.centre(i, j));
            xs.push_back(ll.x), ys.push_back(ll.y), side.push_back(i == 0 ? 2 : 3);
        }
    toSource(src, xs, ys, ok);
    if (coveredBorder)
        for (int k = 0; k < 4; ++k) coveredBorder[k] = 0;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (std::size_t k = 0; k < xs.size(); ++k)
        if (ok[k]) {
            const glm::dvec2 px((xs[k] - gt[0]) / gt[1], (ys[k] - gt[3]) / gt[5]);  // pixel edges at integers
            lo = glm::min(lo, px), hi = glm::max(hi, px);
            if (coveredBorder && inFootprints(src, xs[k], ys[k])) {
                ++coveredBorder[side[k]];
                // A corner is on two sides.
                const int i = int(k / 2);
                if (side[k] < 2 && (i == 0 || i == grid.width - 1)) ++coveredBorder[i == 0 ? 2 : 3];
            }
        }
    SourceWindow w;
    if (!(lo.x <= hi.x)) return w;
    const double wx0 = std::max(0.0, std::floor(lo.x) - kWindowMargin), wy0 = std::max(0.0, std::floor(lo.y) - kWindowMargin);
    const double wx1 = std::min(src.width - 1.0, std::floor(hi.x) + kWindowMargin);
    const double wy1 = std::min(src.height - 1.0, std::floor(hi.y) + kWindowMargin);
    if (!(wx0 <= wx1 && wy0 <= wy1)) return w;
    return {int(wx0), int(wy0), int(wx1), int(wy1)};
}

Box windowBox(const DemSourceInfo& src, const SourceWindow& w) {
    const double* gt = src.geoTransform;
    const double xa = gt[0] + w.x0 * gt[1], xb = gt[0] + (w.x1 + 1) * gt[1];
    const double ya = gt[3] + w.y0 * gt[5], yb = gt[3] + (w.y1 + 1) * gt[5];
    return {{std::min(xa, xb), std::min(ya, yb)}, {std::max(xa, xb), std::max(ya, yb)}};
}

std::size_t fillFromNeighbours(std::vector<float>& v, std::vector<std::uint8_t>& state, int width, int height, std::vector<int>* layerOf) {
    const std::size_t w = std::size_t(width);
    auto forNeighbours = [&](std::size_t k, auto&& f) {
        const int i = int(k % w), j = int(k / w);
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                const int x = i + di, y = j + dj;
                if ((di != 0 || dj != 0) && x >= 0 && y >= 0 && x < width && y < height) f(std::size_t(y) * w + std::size_t(x));
            }
    };
    if (layerOf) layerOf->assign(state.size(), 0);
    std::vector<std::size_t> layer, next;
    for (std::size_t k = 0; k < state.size(); ++k) {
        if (state[k] != kOpen) continue;
        bool touches = false;
        forNeighbours(k, [&](std::size_t q) { touches = touches || state[q] == kKnown; });
        if (touches) layer.push_back(k);
    }
    for (std::size_t k : layer) state[k] = kQueued;
    std::size_t filled = 0;
    int depth = 0;
    std::vector<float> values;
    while (!layer.empty()) {
        ++depth;
        values.clear();
        for (std::size_t k : layer) {
            double sum = 0.0;
            int n = 0;
            forNeighbours(k, [&](std::size_t q) {
                if (state[q] == kKnown) sum += v[q], ++n;
            });
            values.push_back(float(sum / n));
        }
        for (std::size_t m = 0; m < layer.size(); ++m) v[layer[m]] = values[m], state[layer[m]] = kKnown;
        if (layerOf)
            for (std::size_t k : layer) (*layerOf)[k] = depth;
        filled += layer.size();
        next.clear();
        for (std::size_t k : layer)
            forNeighbours(k, [&](std::size_t q) {
                if (state[q] == kOpen) state[q] = kQueued, next.push_back(q);
            });
        layer.swap(next);
    }
    return filled;
}

WindowSamples readWindow(GDALDataset& ds, const DemSourceInfo& src, const std::string& name, const SourceWindow& w) {
    const double* gt = src.geoTransform;
    Block block = readBlock(ds, name, w.x0, w.y0, w.width(), w.height());
    WindowSamples out{w, std::move(block.values), std::vector<std::uint8_t>(block.valid.size(), kNoData)};
    const int ww = w.width(), wh = w.height();
    for (const Box& f : src.footprints) {
        // The window samples whose centres are inside f.
        const double ax = (f.min.x - gt[0]) / gt[1], bx = (f.max.x - gt[0]) / gt[1];
        const double ay = (f.min.y - gt[3]) / gt[5], by = (f.max.y - gt[3]) / gt[5];
        const int i0 = std::max(0, int(std::ceil(std::min(ax, bx) - 0.5)) - w.x0);
        const int i1 = std::min(ww - 1, int(std::floor(std::max(ax, bx) - 0.5)) - w.x0);
        const int j0 = std::max(0, int(std::ceil(std::min(ay, by) - 0.5)) - w.y0);
        const int j1 = std::min(wh - 1, int(std::floor(std::max(ay, by) - 0.5)) - w.y0);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const std::size_t k = std::size_t(j) * std::size_t(ww) + std::size_t(i);
                out.state[k] = block.valid[k] ? kKnown : kOpen;
            }
    }
    return out;
}

void resampleRow(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, const WindowSamples& window, int j, int i0,
                 int i1, float* heights, std::uint8_t* covered) {
    const double* gt = src.geoTransform;
    const int ww = window.at.width(), wh = window.at.height();
    const std::size_t n = std::size_t(i1 - i0 + 1);
    std::vector<double> xs, ys;
    std::vector<int> ok;
    rowToSource(src, frame, grid, j, i0, i1, xs, ys, ok);
    for (std::size_t m = 0; m < n; ++m) {
        covered[m] = 0;
        if (!ok[m] || !inFootprints(src, xs[m], ys[m])) continue;
        // Sample coordinates in the window (centres at integers), clamped to it: beyond the
        // outermost samples of the source the edge continues.
        const double fi = std::clamp((xs[m] - gt[0]) / gt[1] - 0.5 - window.at.x0, 0.0, ww - 1.0);
        const double fj = std::clamp((ys[m] - gt[3]) / gt[5] - 0.5 - window.at.y0, 0.0, wh - 1.0);
        const int x0 = std::min(int(fi), ww - 1), y0 = std::min(int(fj), wh - 1);
        const int x1 = std::min(x0 + 1, ww - 1), y1 = std::min(y0 + 1, wh - 1);
        const double a = fi - x0, b = fj - y0;
        // Bilinear over the samples with data: at a footprint's border inside the mosaic (a
        // missing tile) the weights of the others are renormalised, continuing the edge.
        double sum = 0.0, weight = 0.0;
        for (const auto& [x, y, wgt] : {std::tuple{x0, y0, (1 - a) * (1 - b)}, std::tuple{x1, y0, a * (1 - b)},
                                        std::tuple{x0, y1, (1 - a) * b}, std::tuple{x1, y1, a * b}}) {
            const std::size_t k = std::size_t(y) * std::size_t(ww) + std::size_t(x);
            if (window.state[k] == kKnown && wgt > 0.0) sum += wgt * window.values[k], weight += wgt;
        }
        if (!(weight > 0.0)) continue;
        heights[m] = float(sum / weight);
        covered[m] = 1;
    }
}

void coveredCells(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, int j, int i0, int i1, std::uint8_t* covered) {
    const std::size_t n = std::size_t(i1 - i0 + 1);
    std::vector<double> xs, ys;
    std::vector<int> ok;
    rowToSource(src, frame, grid, j, i0, i1, xs, ys, ok);
    for (std::size_t m = 0; m < n; ++m) covered[m] = ok[m] && inFootprints(src, xs[m], ys[m]);
}

}  // namespace dem_detail
}  // namespace lacet
