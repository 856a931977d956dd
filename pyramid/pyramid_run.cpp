// One build or update of a pyramid file (pyramid/pyramid_build.h): a PyramidJob run in one
// SQLite transaction, marked complete and committed, or rolled back when it fails (a new file is
// built under a temporary name and renamed into place once complete); the checks that the file's pyramid is this scene's.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <system_error>

#include "io/atomic_file.h"
#include "model/progress.h"
#include "pyramid/pyramid_build.h"

namespace lacet {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

void checkPyramidMatches(const PyramidInfo& stored, const PyramidInfo& wanted, const std::string& path) {
    if (stored.extent.min != wanted.extent.min || stored.extent.max != wanted.extent.max || stored.crsWkt != wanted.crsWkt) {
        const auto box = [](const Box& b) {
            char s[160];
            std::snprintf(s, sizeof s, "(%.3f, %.3f)-(%.3f, %.3f)", b.min.x, b.min.y, b.max.x, b.max.y);
            return std::string(s);
        };
        throw PyramidError(path + ": the pyramid was built for another scene (extent " + box(stored.extent) +
                           (stored.crsWkt == wanted.crsWkt ? std::string(", same CRS") : std::string(", another CRS")) +
                           "; this scene's extent is " + box(wanted.extent) + ")");
    }
}

namespace {

// Marks the pyramid complete and commits; the commit counts in the run's times (the tiles are
// stored only once committed).
void complete(PyramidStore& store, PyramidInfo info, PyramidStats& st) {
    info.complete = true;
    store.writeInfo(info);
    const auto t0 = Clock::now();
    store.commit();
    const double commit = std::chrono::duration<double>(Clock::now() - t0).count();
    st.times.write += commit;
    st.wallSeconds += commit;
}

PyramidStats run(PyramidJob& job, PyramidStore& store, Progress* progress) {
    const auto t0 = Clock::now();
    progressBegin(progress, "pyramid tiles", job.tileTotal(), "tiles");
    job.runShards(job.shards(), store, progress);
    job.runTop(store, progress);
    progressEnd(progress);
    PyramidStats& st = job.stats();
    st.appearanceTiles = store.tileCount(kAppearanceTable);
    st.waterTiles = store.tileCount(kWaterTable);
    st.elevationTiles = store.tileCount(kElevationTable);
    st.bytes = store.tileBytes(kAppearanceTable) + store.tileBytes(kWaterTable) + store.tileBytes(kElevationTable);
    st.wallSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    return st;
}

PyramidStats build(const std::function<std::unique_ptr<PyramidJob>(PyramidParams)>& makeJob, const std::string& out,
                   PyramidParams params, bool force, Progress* progress) {
    const std::unique_ptr<PyramidJob> job = makeJob(params);
    const PyramidInfo wanted = job->info();
    const auto buildInto = [&](PyramidStore& store) {
        store.begin();
        try {
            store.create(wanted);
            PyramidStats st = run(*job, store, progress);
            complete(store, wanted, st);
            return st;
        } catch (...) {
            store.rollback();
            throw;
        }
    };
    std::error_code noFile;  // not even a dangling link
    if (!std::filesystem::exists(std::filesystem::symlink_status(out, noFile))) {
        // A new file is built beside `out` and renamed into place once committed: a build that
        // fails or is killed leaves no file at `out` (the next one removes its temporary file).
        PyramidStats st;
        replaceFileAtomically(out, [&](const std::string& tmp) {
            PyramidStore store(tmp, PyramidStore::Mode::ReadWrite);
            st = buildInto(store);
        });
        return st;
    }
    PyramidStore store(out, PyramidStore::Mode::ReadWrite);
    if (auto old = store.info(); old && !force) checkPyramidMatches(*old, wanted, out);
    return buildInto(store);
}

PyramidStats update(const std::function<std::unique_ptr<PyramidJob>(PyramidParams, QuadDigestMap)>& makeJob,
                    const std::string& path, Progress* progress, double demBudgetMiB, double vectorBudgetMiB) {
    if (!std::filesystem::exists(path)) throw PyramidError(path + ": no such pyramid file (build one with lacet pyramid build)");
    PyramidStore store(path, PyramidStore::Mode::ReadWrite);
    const auto old = store.info();
    if (!old) throw PyramidError(path + ": the file holds no Lacet pyramid (lacet_pyramid table)");
    if (!old->complete) throw PyramidError(path + ": the pyramid is incomplete (an interrupted build): build it again");
    PyramidParams params = pyramidParams(*old);
    params.demBudgetMiB = demBudgetMiB;
    params.vectorBudgetMiB = vectorBudgetMiB;
    params.wholeFileCheck = false;  // a save waits for no O(file) read (PyramidParams::wholeFileCheck)
    const std::unique_ptr<PyramidJob> job = makeJob(params, store.digests());
    const PyramidInfo wanted = job->info();
    checkPyramidMatches(*old, wanted, path);
    const bool rebuild = wanted.inputs != old->inputs;
    if (rebuild) job->forgetPrevious();
    try {
        store.begin();
        if (rebuild) store.create(wanted);
        PyramidStats st = run(*job, store, progress);
        st.rebuilt = rebuild;
        complete(store, wanted, st);
        return st;
    } catch (...) {
        store.rollback();
        throw;
    }
}

}  // namespace

PyramidStats buildPyramid(const SceneDocument& doc, const std::string& out, PyramidParams params, bool force, Progress* progress) {
    return build([&](PyramidParams p) { return std::make_unique<PyramidJob>(doc, p); }, out, params, force, progress);
}

PyramidStats buildPyramid(const std::string& scenePath, const std::string& out, PyramidParams params, bool force, Progress* progress) {
    return build([&](PyramidParams p) { return std::make_unique<PyramidJob>(scenePath, p); }, out, params, force, progress);
}

PyramidStats updatePyramid(const SceneDocument& doc, const std::string& path, Progress* progress, double demBudgetMiB,
                           const std::string& sceneChecksum) {
    return update(
        [&](PyramidParams p, QuadDigestMap d) {
            p.sceneChecksum = sceneChecksum;
            return std::make_unique<PyramidJob>(doc, p, std::move(d));
        },
        path, progress,
                  demBudgetMiB, PyramidParams{}.vectorBudgetMiB);
}

PyramidStats updatePyramid(const std::string& scenePath, const std::string& path, Progress* progress, double demBudgetMiB,
                           double vectorBudgetMiB) {
    return update([&](PyramidParams p, QuadDigestMap d) { return std::make_unique<PyramidJob>(scenePath, p, std::move(d)); }, path,
                  progress, demBudgetMiB, vectorBudgetMiB);
}

}  // namespace lacet
