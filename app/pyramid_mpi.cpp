// `lacet pyramid build --shards` (issue 15): the pyramid's shards (the subtrees below
// PyramidParams::shardLevel, pyramid/pyramid_build.h) on the ranks of an MPI job, compiled only
// with the CMake option LACET_MPI (Open MPI from Debian); cmd_pyramid.cpp refuses --shards without it.
//
//   mpirun -np N lacet pyramid build SCENE --out OUT --shards      (or srun, samples/slurm/)
//
// Every rank makes the same PyramidJob, over the scene file (the default, --vectors region: each
// shard reads only its part of the file, so a rank's memory follows its shard, not the scene) or
// over the whole scene loaded (--vectors whole); shard k of job.shards() goes to rank
// k % N, which writes it into its own GeoPackage OUT.shards/shard-L-X-Y.gpkg (written as .part,
// renamed once committed, so a half-written shard never looks finished). After a barrier rank 0
// merges: the final pyramid at OUT gets every shard's tiles, elevation statistics and quad digests,
// then the levels above the shards (PyramidJob::runTop, mipmapped from the merged tiles), in one
// transaction; then the shard directory is removed. The result is the one-process build's, tile for
// tile.
//
// Resume: a shard file that is complete, of the same pyramid inputs (PyramidInfo::inputs) and of
// the same scene (the scene file's checksum of all its values, lacet_meta) is kept, not remade, so
// a rerun after a failure redoes only the unfinished shards. OUT.shards must be on a filesystem all
// ranks see.
//
// Errors: an exception on any rank prints "lacet: rank R: <message>" and calls MPI_Abort, so the
// job (mpirun, srun) exits non-zero. Test hooks: LACET_PYRAMID_FAIL_SHARD=k throws in shard k
// (after making its tiles, before its commit); LACET_PYRAMID_FAIL_MERGE=1 throws on rank 0 before
// the merge (every shard finished: the rerun resumes them all).
//
// Threads: TBB works on the cores the rank may use (its affinity mask: mpirun binds a rank to a core
// or a socket, srun to its --cpus-per-task); only the main thread calls MPI (MPI_THREAD_FUNNELED).
#include <mpi.h>
#include <sqlite3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/progress_bar.h"
#include "io/atomic_file.h"
#include "io/dem_lod.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_store.h"

namespace lacet::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kShardTable = "lacet_shard";  // in a shard file: key/value, what it was made of
constexpr const char* kQuadsTable = "lacet_pyramid_quads";

std::string keyName(const PyramidKey& k) {
    return std::to_string(k.level) + "/" + std::to_string(k.tx) + "/" + std::to_string(k.ty);
}

std::string shardPath(const std::string& dir, const PyramidKey& k) {
    return (fs::path(dir) / ("shard-" + std::to_string(k.level) + "-" + std::to_string(k.tx) + "-" + std::to_string(k.ty) + ".gpkg"))
        .string();
}

// The scene file's checksum of all its values (lacet_meta, io/scene_file.h): the vector data that
// PyramidInfo::inputs does not cover.
std::string sceneChecksum(const std::string& scene) {
    SqliteDb db(scene, SqliteDb::Mode::ReadOnly);
    return db.queryText("SELECT value FROM lacet_meta WHERE key = 'checksum'");
}

// Whether `path` holds the finished shard of this pyramid and scene; never throws (a file it cannot
// read is not finished).
bool shardFinished(const std::string& path, const PyramidInfo& wanted, const std::string& checksum) {
    try {
        if (!fs::is_regular_file(path)) return false;
        PyramidStore s(path, PyramidStore::Mode::ReadOnly);
        const auto info = s.info();
        if (!info || !info->complete || info->inputs != wanted.inputs) return false;
        if (!s.db().hasTable(kShardTable)) return false;
        return s.db().queryText(std::string("SELECT value FROM ") + kShardTable + " WHERE key = 'scene_checksum'") == checksum;
    } catch (const std::exception&) {
        return false;
    }
}

// Makes one shard into its own file: written as .part, renamed when committed.
void makeShard(PyramidJob& job, const PyramidKey& key, const std::string& path, const std::string& checksum, bool fail,
               Progress* progress) {
    const std::string part = path + ".part";
    for (const std::string& p : {part, part + "-journal", path}) fs::remove(p);
    {
        PyramidStore store(part, PyramidStore::Mode::ReadWrite);
        PyramidInfo info = job.info();
        store.begin();
        store.create(info);
        job.runShard(key, store, progress);
        if (fail)
            throw std::runtime_error("shard " + keyName(key) +
                                     " failed on purpose (LACET_PYRAMID_FAIL_SHARD, a test hook)");
        store.db().exec(std::string("CREATE TABLE ") + kShardTable + " (key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL)");
        auto st = store.db().prepare(std::string("INSERT INTO ") + kShardTable + " (key, value) VALUES (?, ?)");
        for (const auto& [k, v] : {std::pair<std::string, std::string>{"scene_checksum", checksum}, {"shard", keyName(key)}}) {
            st.bindText(1, k);
            st.bindText(2, v);
            st.step();
            st.reset();
        }
        info.complete = true;
        store.writeInfo(info);
        store.commit();
    }
    fs::rename(part, path);
}

// Copies a shard file's tiles, elevation statistics and quad digests into `store` (in its
// transaction). The elevation tiles get new row ids in `store`: their ancillary rows are matched
// by zoom level, column and row.
void mergeShard(PyramidStore& store, const std::string& path, const PyramidInfo& info) {
    SqliteDb src(path, SqliteDb::Mode::ReadOnly);
    SqliteDb& dst = store.db();
    std::vector<const char*> tables;
    if (info.appearance) tables.insert(tables.end(), {kAppearanceTable, kWaterTable});
    if (info.elevation) tables.push_back(kElevationTable);
    for (const char* t : tables) {
        auto in = src.prepare(std::string("SELECT zoom_level, tile_column, tile_row, tile_data FROM \"") + t + "\" ORDER BY id");
        auto out = dst.prepare(std::string("INSERT INTO \"") + t + "\" (zoom_level, tile_column, tile_row, tile_data) VALUES (?, ?, ?, ?)");
        while (in.step()) {
            for (int c = 0; c < 3; ++c) out.bind(c + 1, in.integer(c));
            out.bindBlob(4, in.blob(3));
            out.step();
            out.reset();
        }
    }
    if (info.elevation) {
        auto in = src.prepare(std::string("SELECT e.zoom_level, e.tile_column, e.tile_row, a.scale, a.offset, a.min, a.max, a.mean, "
                                          "a.std_dev FROM gpkg_2d_gridded_tile_ancillary a JOIN \"") +
                              kElevationTable + "\" e ON a.tpudt_id = e.id WHERE a.tpudt_name = '" + kElevationTable +
                              "' ORDER BY e.id");
        auto out = dst.prepare(std::string("INSERT INTO gpkg_2d_gridded_tile_ancillary (tpudt_name, tpudt_id, scale, offset, min, max, "
                                           "mean, std_dev) VALUES ('") +
                               kElevationTable + "', (SELECT id FROM \"" + kElevationTable +
                               "\" WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?), ?, ?, ?, ?, ?, ?)");
        while (in.step()) {
            for (int c = 0; c < 3; ++c) out.bind(c + 1, in.integer(c));
            for (int c = 3; c < 9; ++c) {
                if (in.type(c) == SQLITE_NULL) out.bindNull(c + 1);
                else out.bind(c + 1, in.real(c));
            }
            out.step();
            out.reset();
        }
    }
    auto in = src.prepare(std::string("SELECT level, quad_x, quad_y, digest FROM ") + kQuadsTable);
    auto out = dst.prepare(std::string("INSERT INTO ") + kQuadsTable + " (level, quad_x, quad_y, digest) VALUES (?, ?, ?, ?)");
    while (in.step()) {
        for (int c = 0; c < 4; ++c) out.bind(c + 1, in.integer(c));
        out.step();
        out.reset();
    }
}

// What each rank sends rank 0 after its shards.
struct RankFigures {
    enum : std::size_t { Quads, TilesMade, TilesWritten, Times, Run = Times + 9, Resumed, Seconds, Dem, DemLevels = Dem + 6, Count = DemLevels + kMaxDemLevels };
    std::array<double, Count> v{};
};

RankFigures figuresOf(PyramidJob& job, std::size_t run, std::size_t resumed, double seconds) {
    const PyramidStats& s = job.stats();
    RankFigures f;
    f.v[RankFigures::Quads] = double(s.quads);
    f.v[RankFigures::TilesMade] = double(s.tilesMade);
    f.v[RankFigures::TilesWritten] = double(s.tilesWritten);
    const auto& t = s.times;
    const std::array<double, 9> times{t.clip, t.digest, t.elevation, t.appearance, t.mipmap, t.encode, t.decode, t.write, t.dem};
    std::copy(times.begin(), times.end(), f.v.begin() + RankFigures::Times);
    const PyramidDemStats& d = s.dem;
    const std::array<double, 6> dem{double(d.windows),       double(d.fallbacks),    double(d.blocksRead),
                                    double(d.blocksEvicted), double(d.blocksFailed), d.readSeconds};
    std::copy(dem.begin(), dem.end(), f.v.begin() + RankFigures::Dem);
    for (std::size_t l = 0; l < d.windowsAtLevel.size() && l < kMaxDemLevels; ++l) f.v[RankFigures::DemLevels + l] = double(d.windowsAtLevel[l]);
    f.v[RankFigures::Run] = double(run);
    f.v[RankFigures::Resumed] = double(resumed);
    f.v[RankFigures::Seconds] = seconds;
    return f;
}

// Tiles of one shard's subtree (stored levels, both layers).
std::size_t shardTiles(const PyramidParams& p) {
    std::size_t quads = 0;
    for (int l = std::max(p.shardLevel, p.minLevel); l <= p.maxLevel; ++l) quads += std::size_t(1) << (2 * (l - p.shardLevel));
    return quads * (std::size_t(p.appearance) + std::size_t(p.elevation));
}

// As cmd_pyramid.cpp prints a build's figures, with the shards' figures after them.
void printStats(const PyramidStats& s, const std::string& path, bool json, const nlohmann::json& shards) {
    if (json) {
        nlohmann::json j = pyramidStatsJson(s, path);
        j["shards"] = shards;
        std::cout << j.dump(2) << "\n";
        return;
    }
    printPyramidStats(s, "built", path, false);
    std::string perRank;
    for (const auto& r : shards["ranks"]) {
        char line[160];
        std::snprintf(line, sizeof line, "%s%d run in %.2f s", perRank.empty() ? "" : ", ", r["run"].get<int>(), r["seconds"].get<double>());
        perRank += line;
    }
    std::printf("  shards: %d at level %d on %zu ranks (per rank: %s); merge and levels above %.2f s\n", shards["count"].get<int>(),
                shards["level"].get<int>(), shards["ranks"].size(), perRank.c_str(), shards["merge_s"].get<double>());
    const auto& resumed = shards["resumed"];
    if (!resumed.empty()) {
        std::string names;
        std::size_t shown = 0;
        for (const auto& n : resumed) {
            if (++shown > 16) {
                names += " ...";
                break;
            }
            names += " " + n.get<std::string>();
        }
        std::printf("  resumed %zu shard(s) finished by an earlier run, not remade:%s\n", resumed.size(), names.c_str());
    }
}

const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? v : nullptr;
}

void run(const std::string& scene, const std::string& out, const PyramidParams& params, bool force, bool json, bool region, int rank,
         int size) {
    const auto t0 = Clock::now();
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    std::unique_ptr<TerminalProgress> progress;
    if (rank == 0) progress = std::make_unique<TerminalProgress>();

    // Out of core (`region`): the job reads each shard's part of the file; else every rank holds
    // the whole scene.
    std::optional<SceneDocument> doc;
    if (!region) {
        doc = loadScene(scene);
        if (!doc->dem && rank == 0) std::cerr << "lacet pyramid: warning: " << scene << " holds no DEM: the ground is flat at 0 m\n";
    }
    const std::string checksum = sceneChecksum(scene);
    const std::unique_ptr<PyramidJob> jobOwner =
        region ? std::make_unique<PyramidJob>(scene, params) : std::make_unique<PyramidJob>(*doc, params);
    PyramidJob& job = *jobOwner;
    const PyramidInfo wanted = job.info();
    const PyramidParams& p = job.params();
    if (rank == 0 && fs::exists(out) && !force) {
        PyramidStore old(out, PyramidStore::Mode::ReadOnly);
        if (auto i = old.info()) checkPyramidMatches(*i, wanted, out);
    }
    const std::string dir = out + ".shards";
    std::error_code ec;
    fs::create_directory(dir, ec);
    if (!fs::is_directory(dir))
        throw PyramidError(dir + ": cannot create the shard directory" + (ec ? ": " + ec.message() : std::string()));

    // This rank's shards.
    const std::vector<PyramidKey> shards = job.shards();
    std::vector<std::size_t> mine, toRun;
    std::vector<std::string> resumed;
    for (std::size_t k = std::size_t(rank); k < shards.size(); k += std::size_t(size)) mine.push_back(k);
    for (std::size_t k : mine) {
        if (shardFinished(shardPath(dir, shards[k]), wanted, checksum)) resumed.push_back(keyName(shards[k]));
        else toRun.push_back(k);
    }
    long failShard = -1;
    if (const char* f = env("LACET_PYRAMID_FAIL_SHARD")) failShard = std::strtol(f, nullptr, 10);
    const auto tShards = Clock::now();
    progressBegin(progress.get(), "pyramid shards (rank 0 of " + std::to_string(size) + ")", toRun.size() * shardTiles(p), "tiles");
    for (std::size_t k : toRun)
        makeShard(job, shards[k], shardPath(dir, shards[k]), checksum, long(k) == failShard, progress.get());
    progressEnd(progress.get());
    const double shardSeconds = since(tShards);

    // Rank 0 learns every rank's figures and resumed shards (names joined by ' ').
    RankFigures mineFigures = figuresOf(job, toRun.size(), resumed.size(), shardSeconds);
    std::vector<double> all(rank == 0 ? RankFigures::Count * std::size_t(size) : 0);
    MPI_Gather(mineFigures.v.data(), int(RankFigures::Count), MPI_DOUBLE, all.data(), int(RankFigures::Count), MPI_DOUBLE, 0,
               MPI_COMM_WORLD);
    std::string names;
    for (const auto& n : resumed) names += n + " ";
    int length = int(names.size());
    std::vector<int> lengths(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string allNames;
    if (rank == 0) {
        int total = 0;
        for (int r = 0; r < size; ++r) {
            offsets[std::size_t(r)] = total;
            total += lengths[std::size_t(r)];
        }
        allNames.resize(std::size_t(total));
    }
    MPI_Gatherv(names.data(), length, MPI_CHAR, allNames.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank != 0) return;

    // Rank 0 merges.
    if (env("LACET_PYRAMID_FAIL_MERGE")) throw std::runtime_error("the merge failed on purpose (LACET_PYRAMID_FAIL_MERGE, a test hook)");
    const auto tMerge = Clock::now();
    for (const PyramidKey& k : shards)
        if (!shardFinished(shardPath(dir, k), wanted, checksum))
            throw PyramidError(shardPath(dir, k) + ": the shard is missing or unfinished after every rank's work");
    PyramidStats st;
    const auto mergeInto = [&](const std::string& path) {
        PyramidStore store(path, PyramidStore::Mode::ReadWrite);
        if (auto old = store.info(); old && !force) checkPyramidMatches(*old, wanted, path);
        try {
            store.begin();
            store.create(wanted);
            progressBegin(progress.get(), "merging shards", shards.size(), "shards");
            for (const PyramidKey& k : shards) {
                mergeShard(store, shardPath(dir, k), wanted);
                progressAdvance(progress.get());
            }
            progressEnd(progress.get());
            progressBegin(progress.get(), "pyramid tiles above the shards", job.tileTotal() - shards.size() * shardTiles(p), "tiles");
            job.runTop(store, progress.get());
            progressEnd(progress.get());
            st = job.stats();
            st.appearanceTiles = store.tileCount(kAppearanceTable);
            st.waterTiles = store.tileCount(kWaterTable);
            st.elevationTiles = store.tileCount(kElevationTable);
            st.bytes = store.tileBytes(kAppearanceTable) + store.tileBytes(kWaterTable) + store.tileBytes(kElevationTable);
            PyramidInfo done = wanted;
            done.complete = true;
            store.writeInfo(done);
            store.commit();
        } catch (...) {
            store.rollback();
            throw;
        }
    };
    // A new pyramid is merged beside `out` and renamed into place once committed: a merge that
    // fails or is killed leaves nothing at `out` (as the one-process build, pyramid/pyramid_run.cpp).
    std::error_code noFile;
    if (!fs::exists(fs::symlink_status(out, noFile))) replaceFileAtomically(out, mergeInto);
    else mergeInto(out);
    fs::remove_all(dir);
    const double mergeSeconds = since(tMerge);

    // The figures of the whole job: every rank's shards, rank 0's merge and top levels.
    std::size_t quads = 0;
    for (int l = p.minLevel; l <= p.maxLevel; ++l) quads += std::size_t(1) << (2 * l);
    st.quads = st.quadsChanged = quads;
    nlohmann::json ranks = nlohmann::json::array();
    for (int r = 0; r < size; ++r) {
        const double* f = all.data() + std::size_t(r) * RankFigures::Count;
        ranks.push_back({{"rank", r}, {"run", int(f[RankFigures::Run])}, {"resumed", int(f[RankFigures::Resumed])},
                         {"seconds", f[RankFigures::Seconds]}});
        if (r == 0) continue;
        st.tilesMade += std::size_t(f[RankFigures::TilesMade]);
        st.tilesWritten += std::size_t(f[RankFigures::TilesWritten]);
        auto& t = st.times;
        double* times[] = {&t.clip, &t.digest, &t.elevation, &t.appearance, &t.mipmap, &t.encode, &t.decode, &t.write, &t.dem};
        for (std::size_t i = 0; i < 9; ++i) *times[i] += f[RankFigures::Times + i];
        PyramidDemStats& d = st.dem;  // each rank's blocks: its shards' own
        d.windows += std::uint64_t(f[RankFigures::Dem]);
        d.fallbacks += std::uint64_t(f[RankFigures::Dem + 1]);
        d.blocksRead += std::uint64_t(f[RankFigures::Dem + 2]);
        d.blocksEvicted += std::uint64_t(f[RankFigures::Dem + 3]);
        d.blocksFailed += std::uint64_t(f[RankFigures::Dem + 4]);
        d.readSeconds += f[RankFigures::Dem + 5];
        for (std::size_t l = 0; l < kMaxDemLevels; ++l) {
            const auto n = std::uint64_t(f[RankFigures::DemLevels + l]);
            if (n == 0) continue;
            if (d.windowsAtLevel.size() <= l) d.windowsAtLevel.resize(l + 1, 0);
            d.windowsAtLevel[l] += n;
        }
    }
    // The resumed shards in the order of job.shards().
    const std::string spaced = " " + allNames;
    nlohmann::json resumedNames = nlohmann::json::array();
    for (const PyramidKey& k : shards)
        if (spaced.find(" " + keyName(k) + " ") != std::string::npos) resumedNames.push_back(keyName(k));
    st.wallSeconds = since(t0);
    const nlohmann::json shardsJson = {{"level", p.shardLevel},   {"count", int(shards.size())}, {"ranks", ranks},
                                       {"resumed", resumedNames}, {"directory", dir},            {"merge_s", mergeSeconds}};
    progress.reset();
    printStats(st, out, json, shardsJson);
    std::fflush(stdout);
}

}  // namespace

void runShardedPyramidBuild(const std::string& scene, const std::string& out, const PyramidParams& params, bool force, bool json,
                            bool region) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    int rank = 0, size = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    try {
        if (provided < MPI_THREAD_FUNNELED) throw std::runtime_error("the MPI library does not provide MPI_THREAD_FUNNELED");
        run(scene, out, params, force, json, region, rank, size);
    } catch (const std::exception& e) {
        std::cout.flush();
        std::fprintf(stderr, "lacet: rank %d: %s\n", rank, e.what());
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    } catch (...) {
        std::fprintf(stderr, "lacet: rank %d: unknown error\n", rank);
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    MPI_Finalize();
}

}  // namespace lacet::app
