#include "io/dem_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <gdal_priv.h>

#include "io/dem_import_internal.h"

// The in-memory import; its steps are in dem_import_source.cpp (the rasters and their mosaic),
// dem_import_resample.cpp (grid, windows, fill, resampling) and dem_import_seams.cpp.
namespace lacet {
namespace {

using dem_detail::number;

// The largest source window read, samples (4 GiB of heights).
constexpr double kMaxWindowSamples = double(1u << 30);

std::string describe(const Box& lonLat) {
    return "lon " + number(lonLat.min.x) + " to " + number(lonLat.max.x) + ", lat " + number(lonLat.min.y) + " to " + number(lonLat.max.y);
}

}  // namespace

namespace dem_detail {

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

DemImportError notCovered(const std::string& name, const SceneFrame& frame, const Box& extent, const DemSourceInfo& src) {
    Box lonLat{{1e300, 1e300}, {-1e300, -1e300}};
    for (const Vec2 corner : {extent.min, extent.max, Vec2(extent.min.x, extent.max.y), Vec2(extent.max.x, extent.min.y)}) {
        const glm::dvec2 ll = frame.reverse(corner);
        lonLat = {glm::min(lonLat.min, ll), glm::max(lonLat.max, ll)};
    }
    return DemImportError(name + ": the DEM does not cover the scene: no scene cell centre falls inside its rasters (the scene spans " +
                          "about " + describe(lonLat) + "; the DEM " + describe(src.lonLat) + ")");
}

void initReport(const DemSourceInfo& src, DemImportReport& report) {
    report = {};
    for (const std::string& input : src.inputs) report.path += (report.path.empty() ? "" : ", ") + input;
    report.files = src.files;
    report.sourceWidth = src.width;
    report.sourceHeight = src.height;
    report.sourceResolution = src.resolution;
}

std::size_t filesMeeting(const DemSourceInfo& src, const Box& window) {
    std::size_t n = 0;
    for (const Box& f : src.footprints) n += f.intersects(window);
    return n;
}

}  // namespace dem_detail

using namespace dem_detail;

Dem importDem(const DemSourceInfo& src, const SceneFrame& frame, const Box& extent, double cellSize, DemImportReport& report) {
    const auto t0 = std::chrono::steady_clock::now();
    initReport(src, report);
    const std::string& name = report.path;

    // The scene grid.
    const SceneGrid grid = makeSceneGrid(name, extent, cellSize, kMaxDemSide);
    const int width = grid.width, height = grid.height;
    const Vec2 cell = grid.cell;
    report.cellSize = cell.x;
    report.sceneWidth = width;
    report.sceneHeight = height;

    // The source window under the scene: its border cell centres' bounding box, in source samples.
    const SourceWindow win = borderWindow(src, frame, grid, 0, height - 1);
    if (win.empty()) throw notCovered(name, frame, extent, src);
    if (double(win.width()) * double(win.height()) > kMaxWindowSamples)
        throw DemImportError(name + ": the scene extent covers " + std::to_string(win.width()) + " x " + std::to_string(win.height()) +
                             " source samples, more than can be read at once: make a coarser copy of the DEM (gdal_translate -tr)");
    report.windowX = win.x0, report.windowY = win.y0;
    report.windowWidth = win.width(), report.windowHeight = win.height();

    // Read the window; voids are the invalid samples inside a footprint, filled.
    WindowSamples window = readWindow(*openSource(src, name), src, name, win);
    std::vector<std::uint8_t>& state = window.state;
    if (std::find(state.begin(), state.end(), std::uint8_t(kKnown)) == state.end()) {
        if (std::find(state.begin(), state.end(), std::uint8_t(kOpen)) == state.end()) throw notCovered(name, frame, extent, src);
        throw DemImportError(name + ": every sample under the scene extent is void (nodata)");
    }
    report.voids = fillFromNeighbours(window.values, state, win.width(), win.height());
    for (std::uint8_t& s : state)
        if (s == kOpen) s = kNoData;  // voids cut off from every valid sample in the window: no data
    report.filesRead = filesMeeting(src, windowBox(src, win));
    report.strips = 1;
    report.peakStripSamples = window.values.size() + std::size_t(width) * std::size_t(height);

    // Resample the scene grid; a cell is covered when its centre is inside a footprint.
    std::vector<float> heights(std::size_t(width) * std::size_t(height));
    std::vector<std::uint8_t> covered(heights.size(), 0);
    int ci0 = width, ci1 = -1, cj0 = height, cj1 = -1;
    for (int j = 0; j < height; ++j) {
        const std::size_t row = std::size_t(j) * std::size_t(width);
        resampleRow(src, frame, grid, window, j, 0, width - 1, heights.data() + row, covered.data() + row);
        for (int i = 0; i < width; ++i)
            if (covered[row + std::size_t(i)]) ci0 = std::min(ci0, i), ci1 = std::max(ci1, i), cj0 = std::min(cj0, j), cj1 = std::max(cj1, j);
    }
    if (ci1 < 0) throw notCovered(name, frame, extent, src);
    window = {};

    // The Dem: the covered cells' bounding box, the uncovered cells inside it filled.
    const int dw = ci1 - ci0 + 1, dh = cj1 - cj0 + 1;
    std::vector<float> demHeights(std::size_t(dw) * std::size_t(dh));
    std::vector<std::uint8_t> demState(demHeights.size());
    for (int j = 0; j < dh; ++j)
        for (int i = 0; i < dw; ++i) {
            const std::size_t from = std::size_t(j + cj0) * std::size_t(width) + std::size_t(i + ci0);
            const std::size_t to = std::size_t(j) * std::size_t(dw) + std::size_t(i);
            demHeights[to] = heights[from];
            demState[to] = covered[from] ? kKnown : kOpen;
        }
    heights = {};
    covered = {};
    report.uncoveredFilled = fillFromNeighbours(demHeights, demState, dw, dh);
    report.demExtent = {extent.min + Vec2(ci0, cj0) * cell,
                        {ci1 + 1 == width ? extent.max.x : extent.min.x + (ci1 + 1) * cell.x,
                         cj1 + 1 == height ? extent.max.y : extent.min.y + (cj1 + 1) * cell.y}};
    report.outsideFraction = 1.0 - double(dw) * double(dh) / (double(width) * double(height));
    report.width = dw;
    report.height = dh;
    const auto [lowest, highest] = std::minmax_element(demHeights.begin(), demHeights.end());
    report.minHeight = *lowest;
    report.maxHeight = *highest;

    if (src.files.size() > 1) checkSeams(src, windowBox(src, win), report);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return Dem(report.demExtent, dw, dh, std::move(demHeights));
}

}  // namespace lacet
