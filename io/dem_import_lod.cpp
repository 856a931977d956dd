#include "io/dem_import_lod.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "io/dem_import_internal.h"
#include "io/gpkg_dem.h"
#include "io/sqlite_db.h"

namespace lacet {

using namespace dem_detail;

namespace {

// The largest source window a strip reads, samples (as importDem's whole window).
constexpr double kMaxStripWindowSamples = double(1u << 30);

void checkParams(const DemLodImportParams& p) {
    if (p.stripRows < 1) throw std::invalid_argument("DemLodImportParams: stripRows must be >= 1");
    if (p.voidMargin < 0) throw std::invalid_argument("DemLodImportParams: voidMargin must be >= 0");
    if (p.uncoveredMargin < 0) throw std::invalid_argument("DemLodImportParams: uncoveredMargin must be >= 0");
    if (p.coarseSide < 1) throw std::invalid_argument("DemLodImportParams: coarseSide must be >= 1");
    if (p.blockSide < 4 || p.blockSide % 2 != 0) throw std::invalid_argument("DemLodImportParams: blockSide must be even and >= 4");
}

// Scene rows [jLo, jHi] (j growing with y) resampled, columns [i0, i1] of the grid.
struct Strip {
    int jLo = 0, jHi = -1;
    std::vector<float> heights;           // (jHi - jLo + 1) rows of (i1 - i0 + 1), row 0 = jLo
    std::vector<std::uint8_t> covered;
};

class StripResampler {
public:
    StripResampler(const DemSourceInfo& src, const SceneFrame& frame, const SceneGrid& grid, const SourceWindow& whole, int i0, int i1,
                   const DemLodImportParams& params, const std::string& name, DemImportReport& report)
        : src_(src), frame_(frame), grid_(grid), whole_(whole), i0_(i0), i1_(i1), params_(params), name_(name), report_(report),
          ds_(openSource(src, name)) {}

    // Rows [jLo, jHi] resampled from a window of their own; with `count`, their voids are counted in
    // the report (each source row once over the calls: the strips come in order).
    Strip resample(int jLo, int jHi, bool count) {
        Strip s{jLo, jHi, {}, {}};
        const int w = i1_ - i0_ + 1, rows = jHi - jLo + 1;
        s.heights.assign(std::size_t(w) * std::size_t(rows), 0.0f);
        s.covered.assign(s.heights.size(), 0);
        SourceWindow core = borderWindow(src_, frame_, grid_, jLo, jHi);
        core.y0 = std::max(core.y0, whole_.y0), core.y1 = std::min(core.y1, whole_.y1);
        if (core.empty()) return s;
        SourceWindow read{whole_.x0, std::max(whole_.y0, core.y0 - params_.voidMargin), whole_.x1,
                          std::min(whole_.y1, core.y1 + params_.voidMargin)};
        if (double(read.width()) * double(read.height()) > kMaxStripWindowSamples)
            throw DemImportError(name_ + ": a strip of " + std::to_string(rows) + " scene rows covers " + number(read.width()) + " x " +
                                 number(read.height()) + " source samples, more than can be read at once: lower the strip's rows");
        WindowSamples win = readWindow(*ds_, src_, name_, read);
        std::vector<int> layers;
        fillFromNeighbours(win.values, win.state, read.width(), read.height(), &layers);
        if (count) {
            // Rows not counted yet: the strips' core windows follow each other, overlapping.
            int lo = core.y0, hi = core.y1;
            if (countedHi_ >= countedLo_) {
                if (lo >= countedLo_ && lo <= countedHi_ + 1) lo = countedHi_ + 1;
                if (hi <= countedHi_ && hi >= countedLo_ - 1) hi = countedLo_ - 1;
            }
            for (int y = lo; y <= hi; ++y) {
                const int top = read.y0 > whole_.y0 ? y - read.y0 : 1 << 30;     // rows to the cut edges
                const int bottom = read.y1 < whole_.y1 ? read.y1 - y : 1 << 30;
                const int reach = std::min(top, bottom);
                const std::size_t row = std::size_t(y - read.y0) * std::size_t(read.width());
                for (int x = 0; x < read.width(); ++x) {
                    const int d = layers[row + std::size_t(x)];
                    if (d == 0) continue;
                    ++report_.voids;
                    report_.voidsBeyondMargin += 2 * d > reach;
                }
            }
            if (lo <= hi) {
                if (countedHi_ < countedLo_) countedLo_ = lo, countedHi_ = hi;
                else countedLo_ = std::min(countedLo_, lo), countedHi_ = std::max(countedHi_, hi);
            }
        }
        layers = {};
        for (std::uint8_t& st : win.state)
            if (st == kOpen) st = kNoData;  // cut off from every valid sample in the window
        for (int j = jLo; j <= jHi; ++j) {
            const std::size_t at = std::size_t(j - jLo) * std::size_t(w);
            resampleRow(src_, frame_, grid_, win, j, i0_, i1_, s.heights.data() + at, s.covered.data() + at);
        }
        report_.peakStripSamples = std::max(report_.peakStripSamples, win.values.size() + s.heights.size());
        return s;
    }

private:
    const DemSourceInfo& src_;
    const SceneFrame& frame_;
    const SceneGrid& grid_;
    SourceWindow whole_;
    int i0_, i1_;
    const DemLodImportParams& params_;
    const std::string& name_;
    DemImportReport& report_;
    Dataset ds_;
    int countedLo_ = 0, countedHi_ = -1;  // source rows whose voids are counted
};

}  // namespace

namespace {

std::string gib(double bytes) {
    char s[32];
    std::snprintf(s, sizeof s, "%.3g GiB", bytes / double(1ull << 30));
    return s;
}

// Refuses, with the figures, a grid whose tree could not be written or resampled here: one whose
// 32-bit samples, with their coarser levels, would not fit the free space beside `lodPath` even
// compressed kBestDemCompression times (the tree is then copied into the scene file: twice that),
// or whose strips would not fit half the machine's memory. Before any of the grid's rows is visited.
void checkDemLodFits(const std::string& name, const SceneGrid& grid, const std::string& lodPath, const DemLodImportParams& params) {
    constexpr double kBestDemCompression = 4.0;  // DEFLATE of float heights rarely does better than this
    const double samples = double(grid.width) * double(grid.height);
    const double treeBytes = samples * 4.0 * 4.0 / 3.0;
    const double needed = 2.0 * treeBytes / kBestDemCompression;
    const std::filesystem::path p(lodPath);
    const std::string dir = p.has_parent_path() ? p.parent_path().string() : std::string(".");
    struct statvfs fs {};
    const auto cellFor = [&](double bytes) {  // the cell at which the tree would need `bytes`
        return grid.cell.x * std::sqrt(treeBytes / std::max(bytes, 1.0));
    };
    const std::string what = name + ": the DEM at " + number(grid.cell.x) + " m cells would be " + std::to_string(grid.width) + " x " +
                             std::to_string(grid.height) + " samples (" + gib(treeBytes) +
                             " as 32-bit heights with their coarser levels)";
    if (::statvfs(dir.c_str(), &fs) == 0) {
        const double free = double(fs.f_bavail) * double(fs.f_frsize);
        if (needed > free)
            throw DemImportError(what + ": the file system of " + dir + " has " + gib(free) + " free, and the tree needs at least " +
                                 gib(needed) + " (written, then copied into the scene, compressed " + number(kBestDemCompression) +
                                 " times at best); refused: a cell of " + number(cellFor(free * kBestDemCompression / 2.0)) +
                                 " m or more would fit (--dem-cell)");
    }
    // A strip of scene rows, its source window and its void margin, a few buffers of each.
    const double stripBytes = 3.0 * 4.0 * double(grid.width) * double(params.stripRows + 2 * params.voidMargin);
    const double memory = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
    if (memory > 0.0 && stripBytes > memory / 2.0)
        throw DemImportError(what + ": its strips of " + std::to_string(params.stripRows) + " rows would hold about " + gib(stripBytes) +
                             ", more than half of this machine's " + gib(memory) + " of memory; refused: a cell of " +
                             number(grid.cell.x * stripBytes / (memory / 2.0)) + " m or more would fit (--dem-cell)");
}

// Removes the DEM trees' temporary files beside `beside` that a killed import left: named as
// uniqueDemLodPath names them, by a process that no longer runs (a live one's, or one whose id
// another process took since, are kept). Best effort: what cannot be read or removed stays.
void removeStaleImportTempFilesOf(const std::string& beside, const std::string& kind) {
    namespace fs = std::filesystem;
    const fs::path b(beside);
    const fs::path dir = b.has_parent_path() ? b.parent_path() : fs::path(".");
    const std::string prefix = b.filename().string() + "." + kind + ".";
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind(prefix, 0) != 0 || !name.ends_with(".tmp")) continue;
        long long pid = 0;
        unsigned long long r = 0;
        int used = 0;
        const std::string rest = name.substr(prefix.size());
        if (std::sscanf(rest.c_str(), "%lld.%16llx.tmp%n", &pid, &r, &used) != 2 || std::size_t(used) != rest.size() ||
            rest.size() != rest.find('.') + 1 + 16 + 4 || pid <= 0)
            continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // running, or not ours to ask
        std::error_code removed;
        fs::remove(e.path(), removed);
        fs::remove(e.path().string() + "-journal", removed);
    }
}

}  // namespace

std::string uniqueDemLodPath(const std::string& beside) { return uniqueImportTempPath(beside, "dem"); }

void removeStaleImportTempFiles(const std::string& beside) {
    for (const char* kind : {"dem", "vectors"}) removeStaleImportTempFilesOf(beside, kind);
}

std::string uniqueImportTempPath(const std::string& beside, const std::string& kind) {
    removeStaleImportTempFiles(beside);
    std::random_device random;
    for (int attempt = 0; attempt < 100; ++attempt) {
        const std::uint64_t r = std::uint64_t(random()) << 32 ^ std::uint64_t(random());
        char suffix[64];
        std::snprintf(suffix, sizeof suffix, ".%s.%lld.%016llx.tmp", kind.c_str(), static_cast<long long>(::getpid()),
                      static_cast<unsigned long long>(r));
        const std::string path = beside + suffix;
        const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd < 0) {
            if (errno == EEXIST) continue;
            throw std::runtime_error(path + ": cannot create the import's temporary file: " + std::strerror(errno));
        }
        ::close(fd);
        ::unlink(path.c_str());
        return path;
    }
    throw std::runtime_error(beside + ": no free name for the import's temporary file beside it");
}

RemoveFileOnExit::~RemoveFileOnExit() {
    std::error_code ec;
    if (!path.empty()) std::filesystem::remove(path, ec);
}

DemLodOutput writeDemLodFile(const std::string& path, const DemLodLayout& layout, const DemRowSource& rowAt, int coarseSide,
                             Progress* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    {
        std::error_code ec;
        if (std::filesystem::symlink_status(path, ec).type() != std::filesystem::file_type::not_found)
            throw std::invalid_argument("writeDemLodFile(): " + path + " exists (or cannot be checked): not replacing it");
    }
    DemLodOutput out;
    out.layout = layout;
    out.coarseLevel = levelAtMost(layout, coarseSide);
    try {
        createEmptyGpkg(path);
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        db.exec("PRAGMA synchronous = OFF");  // a file of its own, removed when the writing fails
        db.exec("BEGIN");
        DemLodWriter writer(db, layout, -1);  // undefined Cartesian: scene metres, the scene file gives its CRS
        const int step = layout.step(out.coarseLevel);
        const int cw = layout.levelWidth(out.coarseLevel), ch = layout.levelHeight(out.coarseLevel);
        std::vector<float> coarse(std::size_t(cw) * std::size_t(ch));
        std::vector<float> row(std::size_t(layout.width));
        progressBegin(progress, "writing the DEM's levels", std::size_t(layout.height), "rows");
        for (int t = 0; t < layout.height; ++t) {
            rowAt(t, row);
            writer.addRow(row);
            if (t % step == 0) {
                // Dem order: level row r is Dem row ch - 1 - r.
                float* to = coarse.data() + std::size_t(ch - 1 - t / step) * std::size_t(cw);
                for (int k = 0; k < cw; ++k) to[k] = row[std::size_t(k) * std::size_t(step)];
            }
            progressAdvance(progress);
        }
        writer.finish();
        progressEnd(progress);
        out.tiles = writer.tilesWritten();
        out.bytes = writer.bytesWritten();
        out.digest = writer.digest();
        db.exec("COMMIT");
        db.close();
        const double c = layout.levelCell(out.coarseLevel);
        const Vec2 topLeft = layout.origin + Vec2(-0.5 * c, 0.5 * c);
        out.coarse.emplace(Box{{topLeft.x, topLeft.y - ch * c}, {topLeft.x + cw * c, topLeft.y}}, cw, ch, std::move(coarse));
    } catch (const std::invalid_argument&) {  // a caller's mistake
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw;
    } catch (const DemImportError&) {  // the source's, naming it
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw;
    } catch (const std::exception& e) {
        // SQLite's and GDAL's errors give the reason only: the file is the DEM tree's.
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw DemImportError(path + ": cannot write the DEM tree: " + e.what());
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(path, ec);
        throw;
    }
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

DemLodOutput importDemLod(const DemSourceInfo& src, const SceneFrame& frame, const Box& extent, double cellSize,
                          const std::string& lodPath, DemImportReport& report, const DemLodImportParams& params, Progress* progress) {
    const auto t0 = std::chrono::steady_clock::now();
    checkParams(params);
    initReport(src, report);
    const std::string& name = report.path;
    report.storage = "lod";

    // The scene grid, square cells (see the header).
    SceneGrid grid = makeSceneGrid(name, extent, cellSize, kMaxLodDemSide);
    if (grid.cell.y != grid.cell.x) {
        grid.cell.y = grid.cell.x;
        grid.height = std::max(2, int(std::lround(extent.size().y / grid.cell.x)));
        grid.extent.max.y = extent.min.y + grid.height * grid.cell.x;
    }
    const int width = grid.width, height = grid.height;
    checkDemLodFits(name, grid, lodPath, params);
    report.cellSize = grid.cell.x;
    report.sceneWidth = width;
    report.sceneHeight = height;

    // The window under the whole scene (importDem's), and the covered cells' bounding box.
    int coveredBorder[4];
    const SourceWindow whole = borderWindow(src, frame, grid, 0, height - 1, coveredBorder);
    if (whole.empty()) throw notCovered(name, frame, extent, src);
    report.windowX = whole.x0, report.windowY = whole.y0;
    report.windowWidth = whole.width(), report.windowHeight = whole.height();
    int ci0 = 0, ci1 = width - 1, cj0 = 0, cj1 = height - 1;
    if (!(coveredBorder[0] > 0 && coveredBorder[1] > 0 && coveredBorder[2] > 0 && coveredBorder[3] > 0)) {
        ci0 = width, ci1 = -1, cj0 = height, cj1 = -1;
        std::vector<std::uint8_t> covered(static_cast<std::size_t>(width));
        for (int j = 0; j < height; ++j) {
            coveredCells(src, frame, grid, j, 0, width - 1, covered.data());
            for (int i = 0; i < width; ++i)
                if (covered[std::size_t(i)]) ci0 = std::min(ci0, i), ci1 = std::max(ci1, i), cj0 = std::min(cj0, j), cj1 = std::max(cj1, j);
        }
        if (ci1 < 0) throw notCovered(name, frame, extent, src);
    }
    const int dw = ci1 - ci0 + 1, dh = cj1 - cj0 + 1;
    const Vec2 cell = grid.cell;
    report.demExtent = {grid.extent.min + Vec2(ci0, cj0) * cell,
                        {ci1 + 1 == width ? grid.extent.max.x : grid.extent.min.x + (ci1 + 1) * cell.x,
                         cj1 + 1 == height ? grid.extent.max.y : grid.extent.min.y + (cj1 + 1) * cell.y}};
    report.outsideFraction = 1.0 - double(dw) * double(dh) / (double(width) * double(height));
    report.width = dw;
    report.height = dh;
    report.filesRead = filesMeeting(src, windowBox(src, whole));
    const DemLodLayout layout =
        DemLodLayout::make(dw, dh, cell.x, grid.centre(ci0, cj1), params.blockSide);

    // Strips from the top, each resampled when its first row is asked for.
    StripResampler resampler(src, frame, grid, whole, ci0, ci1, params, name, report);
    Strip strip;
    double lowest = 1e300, highest = -1e300;
    const std::size_t w = std::size_t(dw);
    auto nextStrip = [&](int jHi) {
        const int jLo = std::max(cj0, jHi - params.stripRows + 1);
        strip = resampler.resample(jLo, jHi, true);
        ++report.strips;
        if (std::find(strip.covered.begin(), strip.covered.end(), std::uint8_t(0)) == strip.covered.end()) return;
        // Uncovered cells: resampled again with the rows around them, filled on the scene grid.
        const int eLo = std::max(cj0, jLo - params.uncoveredMargin), eHi = std::min(cj1, jHi + params.uncoveredMargin);
        Strip e = eLo == jLo && eHi == jHi ? std::move(strip) : resampler.resample(eLo, eHi, false);
        std::vector<std::uint8_t> state(e.covered.size());
        for (std::size_t k = 0; k < state.size(); ++k) state[k] = e.covered[k] ? kKnown : kOpen;
        std::vector<int> layers;
        fillFromNeighbours(e.heights, state, dw, eHi - eLo + 1, &layers);
        report.peakStripSamples = std::max(report.peakStripSamples, e.heights.size() * 2);
        strip = Strip{jLo, jHi, std::vector<float>(e.heights.begin() + std::ptrdiff_t(std::size_t(jLo - eLo) * w),
                                                   e.heights.begin() + std::ptrdiff_t(std::size_t(jHi - eLo + 1) * w)), {}};
        for (int j = jLo; j <= jHi; ++j) {
            const int reach = std::min(eLo > cj0 ? j - eLo : 1 << 30, eHi < cj1 ? eHi - j : 1 << 30);
            for (std::size_t i = 0; i < w; ++i) {
                const std::size_t k = std::size_t(j - eLo) * w + i;
                if (state[k] != kKnown)
                    throw DemImportError(name + ": scene rows " + std::to_string(eLo) + " to " + std::to_string(eHi) +
                                         " have no DEM data under them (a hole wider than the lod import's margin of " +
                                         std::to_string(params.uncoveredMargin) + " rows)");
                if (layers[k] == 0) continue;
                ++report.uncoveredFilled;
                report.uncoveredBeyondMargin += 2 * layers[k] > reach;
            }
        }
    };
    DemLodOutput out = writeDemLodFile(
        lodPath, layout,
        [&](int t, std::span<float> row) {
            const int j = cj1 - t;
            if (j < strip.jLo || j > strip.jHi) nextStrip(j);
            const float* from = strip.heights.data() + std::size_t(j - strip.jLo) * w;
            std::copy(from, from + w, row.begin());
            for (const float h : row) lowest = std::min(lowest, double(h)), highest = std::max(highest, double(h));
        },
        params.coarseSide, progress);
    report.minHeight = lowest;
    report.maxHeight = highest;
    if (src.files.size() > 1) checkSeams(src, windowBox(src, whole), report);
    report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

}  // namespace lacet
