// A full disk and a read-only folder under every command that writes a file (issue 26): `lacet
// synth --out` and `lacet import` (a scene saved; the import first writes its DEM tree out of core)
// and `lacet pyramid build` and `lacet pyramid update`, each run by the binary in a folder of its
// own, over a file of the same kind that it must replace:
//  - a full disk: writes fail past a file size limit (prlimit --fsize, with SIGXFSZ ignored, so that
//    a write returns EFBIG where a full disk returns ENOSPC), at limits from a few KiB to most of
//    the file;
//  - a read-only folder (root runs without the capability that lets it ignore permissions).
// Each must exit non-zero (not by a signal, not by the timeout), name the file it could not write,
// leave the file it was to replace byte for byte as it was, and leave no other file behind (no
// temporary, no journal, no DEM tree). A control run without a limit succeeds, so that a command
// failing for another reason would not pass.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/app/cli_fixtures.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// A guard against a hang only: far above what any command here takes, even sanitized on a loaded machine.
constexpr int kWriterTimeoutS = 600;
using test::kWithoutRootsOverride;
using test::quoted;
using test::readFile;

struct WriterOutcome {
    int code = -1;  // the exit status; 128 + n for a signal n, 124 for the timeout
    std::string said;  // stderr, then stdout
};

// How the command is run: as it is, under a file size limit, or without root's override.
struct Limit {
    std::uint64_t fileBytes = 0;  // 0: none
    bool withoutOverride = false;
};

// Runs `lacet args` in `cwd`.
WriterOutcome run(const fs::path& cwd, const std::string& args, const Limit& limit = {}) {
    const fs::path out = cwd.parent_path() / (cwd.filename().string() + ".stdout");
    const fs::path err = cwd.parent_path() / (cwd.filename().string() + ".stderr");
    std::string cmd = "cd " + quoted(cwd.string()) + " && ";
    if (limit.fileBytes > 0) cmd += "trap '' XFSZ && ";  // inherited through exec: a write past the limit fails, no signal
    cmd += "exec timeout " + std::to_string(kWriterTimeoutS) + " ";
    if (limit.fileBytes > 0) cmd += "prlimit --fsize=" + std::to_string(limit.fileBytes) + " ";
    if (limit.withoutOverride) cmd += std::string(kWithoutRootsOverride) + " ";
    cmd += quoted(LACET_BINARY) + " " + args + " > " + quoted(out.string()) + " 2> " + quoted(err.string());
    const int status = std::system(cmd.c_str());
    WriterOutcome o;
    if (status != -1) o.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    o.said = readFile(err) + readFile(out);
    fs::remove(out);
    fs::remove(err);
    return o;
}

std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

// One writing command: the files it starts from (copied from the suite's folder), its arguments,
// and the file it writes in place of the one there.
struct Writer {
    const char* name;
    std::vector<std::pair<std::string, std::string>> inputs;  // suite file -> name in the case's folder
    std::string args;
    std::string target;        // the file written (replaced), relative to the case's folder
    std::string targetSource;  // the suite file holding what a successful run writes, for its size
};

void PrintTo(const Writer& w, std::ostream* os) { *os << w.name; }

struct WriterSuite {
    fs::path root;
    std::string error;
};
WriterSuite& writerSuite() {
    static WriterSuite s;
    return s;
}

const std::vector<Writer>& writers() {
    static const std::vector<Writer> w = {
        {"synth", {{"a.gpkg", "scene.gpkg"}}, "synth --curves 400 --seed 2 --out scene.gpkg", "scene.gpkg", "b.gpkg"},
        {"import", {{"a.gpkg", "scene.gpkg"}, {"dem.tif", "dem.tif"}, {"good.geojson", "good.geojson"}},
         "import --dem dem.tif --vectors good.geojson --dem-storage lod --out scene.gpkg", "scene.gpkg", "imported.gpkg"},
        {"pyramid_build", {{"a.gpkg", "scene.gpkg"}, {"b.pyramid.gpkg", "scene.pyramid.gpkg"}},
         "pyramid build scene.gpkg --force", "scene.pyramid.gpkg", "a.pyramid.gpkg"},
        {"pyramid_update", {{"b.gpkg", "scene.gpkg"}, {"a.pyramid.gpkg", "scene.pyramid.gpkg"}}, "pyramid update scene.gpkg",
         "scene.pyramid.gpkg", "b.pyramid.gpkg"},
    };
    return w;
}

class WriterIoErrors : public testing::TestWithParam<Writer> {
public:
    static void SetUpTestSuite() {
        WriterSuite& s = writerSuite();
        s.root = test::scratchDir("writer_io_errors");
        test::writeFixtureDem(s.root, false);  // dem.tif
        fs::copy_file(test::vectorData("good.geojson"), s.root / "good.geojson", fs::copy_options::overwrite_existing);
        // Two synthetic scenes of one extent (a and b), the pyramid of each, and an import's scene.
        for (const std::string& args :
             {std::string("synth --curves 400 --seed 1 --out a.gpkg"), std::string("synth --curves 400 --seed 2 --out b.gpkg"),
              std::string("pyramid build a.gpkg"), std::string("pyramid build b.gpkg"),
              std::string("import --dem dem.tif --vectors good.geojson --dem-storage lod --out imported.gpkg")}) {
            const WriterOutcome o = run(s.root, args);
            if (o.code != 0) {
                s.error = "lacet " + args + " failed (" + std::to_string(o.code) + "):\n" + o.said;
                return;
            }
        }
    }
    static void TearDownTestSuite() {
        std::error_code ec;
        for (const auto& e : fs::recursive_directory_iterator(writerSuite().root, ec))
            if (e.is_directory() && !e.is_symlink()) fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(writerSuite().root, ec);
    }

    // A folder of the writer's inputs.
    static fs::path prepare(const Writer& w, const std::string& caseName) {
        const fs::path dir = writerSuite().root / (std::string(w.name) + "_" + caseName);
        fs::create_directories(dir);
        for (const auto& [from, to] : w.inputs) fs::copy_file(writerSuite().root / from, dir / to, fs::copy_options::overwrite_existing);
        return dir;
    }

    // Runs the writer in a new folder under `limit`: it fails naming its target, which keeps its
    // bytes, and leaves the folder's files as they were.
    static void expectRefusedWhole(const Writer& w, const std::string& caseName, const Limit& limit, const fs::path& dir) {
        const std::string before = readFile(dir / w.target);
        const std::set<std::string> files = listing(dir);
        const WriterOutcome o = run(dir, w.args, limit);
        const std::string where = "lacet " + w.args + " (" + caseName + ") -> exit " + std::to_string(o.code) + ":\n" + o.said;
        // What the user reads: the error line.
        const std::size_t at = o.said.rfind("lacet: ");
        const std::string line = at == std::string::npos ? o.said : o.said.substr(at, o.said.find('\n', at) - at);
        std::printf("[ figures ] %s, %s: exit %d: %s\n", w.name, caseName.c_str(), o.code, line.c_str());
        EXPECT_NE(o.code, 0) << "accepted\n" << where;
        EXPECT_TRUE(o.code != 124 && o.code < 128) << "crashed or hung\n" << where;
        EXPECT_NE(o.said.find(w.target), std::string::npos) << "the message does not name " << w.target << "\n" << where;
        EXPECT_TRUE(readFile(dir / w.target) == before) << w.target << " changed\n" << where;
        // Readable again, so that the listing sees everything.
        fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add);
        EXPECT_EQ(listing(dir), files) << "files left behind or removed\n" << where;
    }
};

TEST_P(WriterIoErrors, AFullDiskLeavesTheOldFileAndNothingElse) {
    ASSERT_TRUE(writerSuite().error.empty()) << writerSuite().error;
    const Writer& w = GetParam();
    const std::uint64_t whole = fs::file_size(writerSuite().root / w.targetSource);
    // A few KiB (the first pages, a journal's header), about half of the file, and most of it.
    for (const std::uint64_t limit : {std::uint64_t(8192), whole / 2, whole * 9 / 10}) {
        const std::string caseName = "limit_" + std::to_string(limit);
        SCOPED_TRACE(std::string(w.name) + ": writes fail past " + std::to_string(limit) + " bytes of " + std::to_string(whole));
        expectRefusedWhole(w, caseName, Limit{limit, false}, prepare(w, caseName));
    }
    // The control: the same command with room succeeds and replaces the file.
    const fs::path dir = prepare(w, "room");
    const std::string before = readFile(dir / w.target);
    const WriterOutcome o = run(dir, w.args, Limit{whole * 4 + (64u << 20), false});
    EXPECT_EQ(o.code, 0) << o.said;
    EXPECT_NE(readFile(dir / w.target), before) << w.target << " was not replaced";
}

TEST_P(WriterIoErrors, AReadOnlyFolderLeavesTheOldFileAndNothingElse) {
    ASSERT_TRUE(writerSuite().error.empty()) << writerSuite().error;
    const Writer& w = GetParam();
    const fs::path dir = prepare(w, "read_only");
    fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec);
    Limit limit;
    if (::access(dir.c_str(), W_OK) == 0) {  // root: run the command without its override, if that can be done
        const std::string probe = std::string(kWithoutRootsOverride) + " sh -c 'test -w \"$0\" && exit 3 || exit 4' " +
                                  quoted(dir.string()) + " > /dev/null 2>&1";
        const int status = std::system(probe.c_str());
        if (!(WIFEXITED(status) && WEXITSTATUS(status) == 4))
            GTEST_SKIP() << "the read-only folder is writable to this user (root ignores permissions) and setpriv cannot drop that";
        limit.withoutOverride = true;
    }
    expectRefusedWhole(w, "read_only", limit, dir);
}

INSTANTIATE_TEST_SUITE_P(Commands, WriterIoErrors, testing::ValuesIn(writers()),
                         [](const testing::TestParamInfo<Writer>& w) { return std::string(w.param.name); });

}  // namespace
}  // namespace lacet
