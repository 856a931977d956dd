// `lacet pyramid build --shards` on the ranks of an MPI job (issue 15, app/pyramid_mpi.cpp), run
// with `mpirun -np 2` on this machine (built only with LACET_MPI): the merged pyramid equals a
// one-process build tile for tile (the three tile tables, the elevation statistics, the quad
// digests, lacet_pyramid); a rerun after a failure resumes the finished shards and gives the same
// tiles; a failing rank fails the job with its message; a pyramid of another scene is refused.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/sqlite_db.h"
#include "pyramid/pyramid_store.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

struct CliRun {
    int code = -1;
    std::string out, err;
};

std::string readFile(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

class PyramidMpi : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("lacet_pyramid_mpi_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        // Shared memory between the ranks without ptrace (CMA), which containers often forbid.
        ::setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 0);
        ASSERT_EQ(run(std::string(LACET_BINARY) + " synth --seed 7 --curves 1500 --out " + path("scene.gpkg")).code, 0);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    CliRun run(const std::string& command) const {
        const std::string out = path("stdout"), err = path("stderr");
        const int status = std::system((command + " > " + out + " 2> " + err).c_str());
        CliRun r;
        r.code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = readFile(out);
        r.err = readFile(err);
        return r;
    }

    static std::string build(const std::string& scene, const std::string& out) {
        return std::string(LACET_BINARY) + " pyramid build " + scene + " --out " + out +
               " --levels 0-3 --shard-level 1 --encoding png";
    }
    CliRun sharded(const std::string& out, const std::string& env = "", const std::string& scene = "") const {
        return run(env + " " + LACET_MPIEXEC + " --allow-run-as-root --oversubscribe -np 2 " +
                   build(scene.empty() ? path("scene.gpkg") : scene, out) + " --shards");
    }
    CliRun oneProcess(const std::string& out, const std::string& extra = "") const {
        return run(build(path("scene.gpkg"), out) + extra);
    }

    fs::path dir_;
};

using Tiles = std::vector<std::pair<PyramidKey, std::vector<std::uint8_t>>>;

// Rows of a query, one string each.
std::vector<std::string> rows(const std::string& file, const std::string& sql) {
    SqliteDb db(file, SqliteDb::Mode::ReadOnly);
    auto st = db.prepare(sql);
    std::vector<std::string> out;
    while (st.step()) out.push_back(st.text(0));
    return out;
}

void expectSamePyramid(const std::string& a, const std::string& b) {
    PyramidStore sa(a, PyramidStore::Mode::ReadOnly), sb(b, PyramidStore::Mode::ReadOnly);
    for (const char* t : {kAppearanceTable, kWaterTable, kElevationTable}) {
        const Tiles ta = sa.allTiles(t), tb = sb.allTiles(t);
        ASSERT_EQ(ta.size(), tb.size()) << t;
        EXPECT_GT(ta.size(), 0u) << t;
        std::size_t differ = 0;
        for (std::size_t i = 0; i < ta.size(); ++i) {
            ASSERT_EQ(ta[i].first, tb[i].first) << t;
            if (ta[i].second != tb[i].second) ++differ;
        }
        EXPECT_EQ(differ, 0u) << t << ": tiles that differ";
    }
    EXPECT_EQ(sa.digests(), sb.digests());
    EXPECT_EQ(sa.digests().size(), 85u);  // levels 0-3
    const auto ia = sa.info(), ib = sb.info();
    ASSERT_TRUE(ia && ib);
    EXPECT_TRUE(ia->complete);
    EXPECT_EQ(ia->inputs, ib->inputs);
    // The elevation tiles' statistics, by tile (their row ids may differ).
    const std::string stats =
        "SELECT e.zoom_level || '/' || e.tile_column || '/' || e.tile_row || ' ' || a.min || ' ' || a.max || ' ' || a.mean || ' ' || "
        "a.std_dev FROM gpkg_2d_gridded_tile_ancillary a JOIN lacet_elevation e ON a.tpudt_id = e.id ORDER BY 1";
    const auto ra = rows(a, stats), rb = rows(b, stats);
    EXPECT_EQ(ra.size(), 85u);
    EXPECT_EQ(ra, rb);
    EXPECT_EQ(rows(a, "SELECT key || '=' || value FROM lacet_pyramid ORDER BY key"),
              rows(b, "SELECT key || '=' || value FROM lacet_pyramid ORDER BY key"));
}

TEST_F(PyramidMpi, TwoRanksEqualOneProcessTileForTile) {
    const CliRun a = sharded(path("A.gpkg"));
    ASSERT_EQ(a.code, 0) << a.out << a.err;
    EXPECT_NE(a.out.find("shards: 4 at level 1 on 2 ranks (per rank: 2 run"), std::string::npos) << a.out;
    EXPECT_EQ(a.out.find("resumed"), std::string::npos) << a.out;
    EXPECT_FALSE(fs::exists(path("A.gpkg.shards")));  // removed after the merge
    const CliRun b = oneProcess(path("B.gpkg"));
    ASSERT_EQ(b.code, 0) << b.out << b.err;
    expectSamePyramid(path("A.gpkg"), path("B.gpkg"));
    // The ranks read their shards' vectors from the file by region; the whole document gives the same.
    const CliRun c = oneProcess(path("C.gpkg"), " --vectors whole");
    ASSERT_EQ(c.code, 0) << c.out << c.err;
    expectSamePyramid(path("A.gpkg"), path("C.gpkg"));
}

TEST_F(PyramidMpi, RerunAfterAFailedMergeResumesEveryShard) {
    const CliRun failed = sharded(path("A.gpkg"), "LACET_PYRAMID_FAIL_MERGE=1");
    EXPECT_NE(failed.code, 0);
    EXPECT_NE(failed.err.find("lacet: rank 0: the merge failed on purpose"), std::string::npos) << failed.err;
    EXPECT_FALSE(isPyramidFile(path("A.gpkg")));
    EXPECT_TRUE(fs::exists(path("A.gpkg.shards/shard-1-1-1.gpkg")));
    const CliRun again = sharded(path("A.gpkg"));
    ASSERT_EQ(again.code, 0) << again.out << again.err;
    EXPECT_NE(again.out.find("resumed 4 shard(s) finished by an earlier run, not remade: 1/0/0 1/1/0 1/0/1 1/1/1"),
              std::string::npos)
        << again.out;
    EXPECT_NE(again.out.find("per rank: 0 run"), std::string::npos) << again.out;
    ASSERT_EQ(oneProcess(path("B.gpkg")).code, 0);
    expectSamePyramid(path("A.gpkg"), path("B.gpkg"));
}

TEST_F(PyramidMpi, FailedRankFailsTheJobAndTheRerunRedoesTheUnfinishedShards) {
    // Shard 1 (1/1/0) is rank 1's first: rank 0's two shards may finish or be cut short by the abort.
    const CliRun failed = sharded(path("A.gpkg"), "LACET_PYRAMID_FAIL_SHARD=1");
    EXPECT_NE(failed.code, 0);
    EXPECT_NE(failed.err.find("lacet: rank 1: shard 1/1/0 failed on purpose"), std::string::npos) << failed.err;
    EXPECT_FALSE(isPyramidFile(path("A.gpkg")));
    EXPECT_FALSE(fs::exists(path("A.gpkg.shards/shard-1-1-0.gpkg")));  // never finished
    std::size_t finished = 0;  // rank 0's, if it got that far
    for (const auto& e : fs::directory_iterator(path("A.gpkg.shards")))
        if (e.path().extension() == ".gpkg") ++finished;
    const CliRun again = sharded(path("A.gpkg"));
    ASSERT_EQ(again.code, 0) << again.out << again.err;
    if (finished > 0) EXPECT_NE(again.out.find("resumed " + std::to_string(finished) + " shard(s)"), std::string::npos) << again.out;
    else EXPECT_EQ(again.out.find("resumed"), std::string::npos) << again.out;
    ASSERT_EQ(oneProcess(path("B.gpkg")).code, 0);
    expectSamePyramid(path("A.gpkg"), path("B.gpkg"));

    // An output folder that does not exist: every rank fails, naming it.
    const CliRun nowhere = sharded(path("no/such/folder/A.gpkg"));
    EXPECT_NE(nowhere.code, 0);
    EXPECT_NE(nowhere.err.find("lacet: rank "), std::string::npos) << nowhere.err;
    EXPECT_NE(nowhere.err.find("no/such/folder/A.gpkg.shards: cannot create the shard directory"), std::string::npos) << nowhere.err;
}

TEST_F(PyramidMpi, RefusesAPyramidOfAnotherScene) {
    ASSERT_EQ(run(std::string(LACET_BINARY) + " synth --seed 8 --curves 500 --out " + path("other.gpkg")).code, 0);
    ASSERT_EQ(run(build(path("other.gpkg"), path("A.gpkg"))).code, 0);
    const CliRun refused = sharded(path("A.gpkg"));
    EXPECT_NE(refused.code, 0);
    EXPECT_NE(refused.err.find("lacet: rank 0: " + path("A.gpkg") + ": the pyramid was built for another scene"), std::string::npos)
        << refused.err;
    const CliRun forced = run(std::string(LACET_MPIEXEC) + " --allow-run-as-root --oversubscribe -np 2 " +
                           build(path("scene.gpkg"), path("A.gpkg")) + " --shards --force");
    ASSERT_EQ(forced.code, 0) << forced.out << forced.err;
    ASSERT_EQ(oneProcess(path("B.gpkg")).code, 0);
    expectSamePyramid(path("A.gpkg"), path("B.gpkg"));
}

}  // namespace
}  // namespace lacet
