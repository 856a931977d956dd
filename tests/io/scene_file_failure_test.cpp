// A scene file's failures (io/scene_file.h, io/atomic_file.h): a write that cannot finish leaves
// the previous file and no temporary; missing, empty, foreign, truncated, damaged and overwritten
// files are refused by name, never a crash; a save killed at any moment leaves a whole scene.
#include "io/sqlite_db.h"
#include "tests/io/scene_file_fixture.h"

namespace lacet {
namespace {

class SceneFileFailure : public SceneFile {};

TEST_F(SceneFileFailure, ATemporaryPathThatCannotBeWrittenLeavesThePreviousFile) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true));
    const std::string before = readBytes(path);
    fs::create_directories(path + ".tmp/occupied");  // the temporary file cannot be removed nor created
    expectSceneFileError([&] { saveScene(path, syntheticDocument()); }, path, "cannot remove the stale temporary file");
    EXPECT_EQ(readBytes(path), before);
    EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    EXPECT_TRUE(fs::is_directory(path + ".tmp/occupied"));  // not ours: left alone
}

// Writes fail past `limit` bytes per file while alive (RLIMIT_FSIZE, SIGXFSZ ignored), as on a full disk.
class FileSizeLimit {
public:
    explicit FileSizeLimit(rlim_t limit) {
        previousHandler_ = std::signal(SIGXFSZ, SIG_IGN);
        ::getrlimit(RLIMIT_FSIZE, &previous_);
        rlimit r = previous_;
        r.rlim_cur = limit;
        ok_ = ::setrlimit(RLIMIT_FSIZE, &r) == 0;
    }
    ~FileSizeLimit() {
        ::setrlimit(RLIMIT_FSIZE, &previous_);
        std::signal(SIGXFSZ, previousHandler_);
    }
    bool ok() const { return ok_; }

private:
    rlimit previous_{};
    void (*previousHandler_)(int) = nullptr;
    bool ok_ = false;
};

TEST_F(SceneFileFailure, AWriteFailingMidwayLeavesThePreviousFile) {
    const std::string path = file("scene.gpkg");
    const SceneDocument& big = syntheticDocument();
    saveScene(path, handDocument(true));
    const std::string before = readBytes(path);
    // Size of the file once GDAL has written the DEM, before the SQLite part: a limit a little
    // above it fails inside the SQLite transaction, one below it inside GDAL.
    const std::string probe = file("probe.gpkg");
    createGpkgWithDem(probe, *big.dem, "");
    const auto rasterOnly = fs::file_size(probe);
    for (const rlim_t limit : {rlim_t(rasterOnly / 2), rlim_t(rasterOnly + 64 * 1024)}) {
        SCOPED_TRACE("file size limit " + std::to_string(limit) + " bytes (DEM-only file " + std::to_string(rasterOnly) +
                     ")");
        {
            FileSizeLimit fsl(limit);
            ASSERT_TRUE(fsl.ok());
            expectSceneFileError([&] { saveScene(path, big); }, path, "cannot save");
        }
        EXPECT_EQ(readBytes(path), before);
        EXPECT_FALSE(fs::exists(path + ".tmp"));
        EXPECT_FALSE(fs::exists(path + ".tmp-journal"));
        EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    }
    saveScene(path, big);  // and a save with room to write succeeds
    EXPECT_TRUE(identical(loadScene(path), big));
}

TEST_F(SceneFileFailure, AFailedRenameRemovesTheTemporaryFile) {
    const std::string path = file("scene.gpkg");
    fs::create_directories(path + "/occupied");  // the final rename cannot replace a directory
    expectSceneFileError([&] { saveScene(path, handDocument(true)); }, path, "cannot rename");
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_TRUE(fs::is_directory(path + "/occupied"));
}

// What a save killed before its rename leaves at <path>.tmp is recognized as such (the import
// removes it, and refuses to remove anything else): empty, the DEM part alone (its SQLite part
// rolled back), or a whole scene; a user's text file or GeoPackage is not.
TEST_F(SceneFileFailure, AKilledSavesTemporaryFileIsToldFromAUsersFile) {
    const std::string empty = file("empty.gpkg.tmp");
    { std::ofstream(empty).flush(); }
    EXPECT_TRUE(isStaleSaveTemporary(empty));
    const std::string whole = file("whole.gpkg.tmp");
    saveScene(whole, handDocument(true));
    EXPECT_TRUE(isStaleSaveTemporary(whole));
    // The DEM part: the whole scene less what its SQLite transaction writes.
    const std::string demOnly = file("dem_only.gpkg.tmp");
    saveScene(demOnly, handDocument(true));
    {
        SqliteDb db(demOnly, SqliteDb::Mode::ReadWrite);
        std::vector<std::string> drop;
        auto tables = db.prepare("SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'gpkg%' AND name NOT LIKE "
                                 "'rtree%' AND name NOT LIKE 'sqlite%' AND name <> 'dem'");
        while (tables.step()) drop.push_back(tables.text(0));
        tables.reset();
        ASSERT_FALSE(drop.empty());
        for (const std::string& t : drop) db.exec("DROP TABLE \"" + t + "\"");
    }
    EXPECT_FALSE(isLacetScene(demOnly));
    EXPECT_TRUE(isStaleSaveTemporary(demOnly));
    // A user's files.
    const std::string text = file("notes.gpkg.tmp");
    { std::ofstream(text) << "my notes\n"; }
    EXPECT_FALSE(isStaleSaveTemporary(text));
    const std::string theirs = file("theirs.gpkg.tmp");
    saveScene(theirs, handDocument(true));
    {
        SqliteDb db(theirs, SqliteDb::Mode::ReadWrite);
        db.exec("DROP TABLE lacet_meta");
        db.exec("CREATE TABLE parcels (id INTEGER PRIMARY KEY, owner TEXT)");
    }
    EXPECT_FALSE(isStaleSaveTemporary(theirs));
    EXPECT_FALSE(isStaleSaveTemporary(file("missing.gpkg.tmp")));
}

TEST_F(SceneFileFailure, AnInvalidSceneIsNotSaved) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(false));
    const std::string before = readBytes(path);
    SceneDocument bad = handDocument(false);
    bad.scene.layers[0].curves[0].vertices[0].p.x = 5.0;  // no longer at its start node
    expectSceneFileError([&] { saveScene(path, bad); }, path, "invalid scene");
    EXPECT_EQ(readBytes(path), before);
}

TEST_F(SceneFileFailure, AStaleTemporaryFileAndJournalAreReplaced) {
    const std::string path = file("scene.gpkg");
    writeBytes(path + ".tmp", "half a scene");
    writeBytes(path + ".tmp-journal", std::string(4096, '\x5a'));
    saveScene(path, handDocument(true));
    EXPECT_TRUE(identical(loadScene(path), handDocument(true)));
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_FALSE(fs::exists(path + ".tmp-journal"));
}

TEST_F(SceneFileFailure, MissingEmptyAndForeignFilesAreRefused) {
    const std::string missing = file("missing.gpkg");
    expectSceneFileError([&] { loadScene(missing); }, missing, "No such file");
    const std::string empty = file("empty.gpkg");
    writeBytes(empty, "");
    expectSceneFileError([&] { loadScene(empty); }, empty, "empty file");
    const std::string text = file("text.gpkg");
    writeBytes(text, std::string(10000, 'x'));
    expectSceneFileError([&] { loadScene(text); }, text, "not a GeoPackage");
    expectSceneFileError([&] { loadScene(dir_.string()); }, dir_.string(), "is a directory");
    const std::string sqlite = file("plain.sqlite");
    execSql(sqlite, "CREATE TABLE t (a); INSERT INTO t VALUES (1)");
    expectSceneFileError([&] { loadScene(sqlite); }, sqlite, "not a GeoPackage");
    const std::string gpkg = file("other.gpkg");
    createEmptyGpkg(gpkg);
    expectSceneFileError([&] { loadScene(gpkg); }, gpkg, "not a Lacet scene");
}

TEST_F(SceneFileFailure, TruncatedFilesAreRefused) {
    const std::string path = file("scene.gpkg");
    saveScene(path, syntheticDocument());
    const std::string bytes = readBytes(path);
    ASSERT_GT(bytes.size(), 65536u);
    for (const std::size_t size : {std::size_t(1), std::size_t(50), std::size_t(100), std::size_t(1024),
                                   std::size_t(4096), std::size_t(4097), bytes.size() / 3, bytes.size() / 2,
                                   bytes.size() - 4096, bytes.size() - 1}) {
        const std::string cut = file("cut_" + std::to_string(size) + ".gpkg");
        writeBytes(cut, bytes.substr(0, size));
        try {
            loadScene(cut);
            ADD_FAILURE() << "a copy truncated to " << size << " bytes of " << bytes.size() << " loaded";
        } catch (const SceneFileError& e) {
            EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
        }
    }
}

TEST_F(SceneFileFailure, DamagedContentsAreRefused) {
    const std::string good = file("good.gpkg");
    saveScene(good, handDocument(true));
    auto damaged = [&](const std::string& name, const std::string& sql, const std::string& reason) {
        SCOPED_TRACE(name);
        const std::string path = file(name + ".gpkg");
        fs::copy_file(good, path);
        execSql(path, sql);
        expectSceneFileError([&] { loadScene(path); }, path, reason);
    };
    damaged("vertices_length", "UPDATE lacet_curves SET vertices = zeroblob(33) WHERE layer = 0 AND id = 1",
            "lacet_curves row (layer 0, id 1): vertices blob of 33 bytes, not a multiple of 17");
    damaged("vertices_odd_length",
            "UPDATE lacet_curves SET vertices = CAST(zeroblob(34) || x'07' AS BLOB) WHERE layer = 0 AND id = 1",
            "not a multiple of 17");
    damaged("vertex_flag_bits",
            "UPDATE lacet_curves SET vertices = CAST(substr(vertices, 1, length(vertices) - 1) || x'09' AS BLOB) "
            "WHERE layer = 0 AND id = 1",
            "unknown flag bits");
    damaged("areas_blob", "UPDATE lacet_curves SET areas = x'010203' WHERE layer = 1 AND id = 0", "not a multiple of 4");
    damaged("loops_blob", "UPDATE lacet_areas SET loops = x'05000000' WHERE layer = 1 AND id = 0", "loops blob is truncated");
    damaged("loops_count", "UPDATE lacet_areas SET loops = x'ffffffff01000000' WHERE layer = 1 AND id = 0",
            "loops blob is truncated");
    damaged("node_text", "UPDATE lacet_nodes SET x = 'east' WHERE layer = 1 AND id = 1", "x is not a number");
    damaged("missing_id", "DELETE FROM lacet_curves WHERE layer = 0 AND id = 2", "ids are not 0, 1, 2");
    damaged("unknown_layer", "UPDATE lacet_nodes SET layer = 7 WHERE layer = 1 AND id = 4", "layer = 7 is out of range");
    damaged("roundabout_negative", "UPDATE lacet_nodes SET roundabout = -2 WHERE layer = 0 AND id = 1",
            "roundabout is not a finite radius >= 0");
    damaged("roundabout_text", "UPDATE lacet_nodes SET roundabout = 'big' WHERE layer = 0 AND id = 1",
            "roundabout is not a number");
    damaged("width_not_float", "UPDATE lacet_curves SET w = 0.1 WHERE layer = 0 AND id = 1", "w is not a 32-bit float");
    damaged("kind", "UPDATE lacet_layers SET kind = 'glaciers' WHERE id = 1", "unknown layer kind 'glaciers'");
    damaged("no_meta", "DROP TABLE lacet_meta", "not a Lacet scene");
    damaged("no_curves", "DROP TABLE lacet_curves", "no lacet_curves table");
    damaged("version", "UPDATE lacet_meta SET value = '3' WHERE key = 'format_version'", "format version 3");
    damaged("extent", "UPDATE lacet_meta SET value = '12.5' WHERE key = 'extent_max_x'", "is not a hex float");
    damaged("dem_size", "UPDATE lacet_meta SET value = '8' WHERE key = 'dem_width'", "the DEM raster is 7 x 5");
    damaged("dem_tiles", "DELETE FROM dem", "corrupt DEM: raster table 'dem' holds 0 of its 1 tiles");
    damaged("dem_tile_data", "UPDATE dem SET tile_data = zeroblob(100)", "cannot read the DEM raster");
    damaged("model", "UPDATE lacet_nodes SET x = x + 1 WHERE layer = 1 AND id = 0", "invalid scene");
    damaged("application_id", "PRAGMA application_id = 0", "not a GeoPackage");
    // Changes that leave a valid scene: only the checksum tells.
    damaged("class", "UPDATE lacet_curves SET cls = 3 WHERE layer = 0 AND id = 0", "do not match their checksum");
    damaged("dead_slot", "UPDATE lacet_curves SET cls = 1 WHERE layer = 0 AND id = 3", "do not match their checksum");
    damaged("first_vertex",
            "UPDATE lacet_curves SET vertices = CAST(x'0000000000c08240' || substr(vertices, 9) AS BLOB) "
            "WHERE layer = 1 AND id = 0",
            "invalid scene");
    damaged("control_point",
            "UPDATE lacet_curves SET vertices = "
            "CAST(substr(vertices, 1, 16) || x'0000000000c08240' || substr(vertices, 25) AS BLOB) "
            "WHERE layer = 1 AND id = 0",
            "do not match their checksum");
    damaged("georeference", "UPDATE lacet_meta SET value = '0x1p+0' WHERE key = 'georeference_lon0'",
            "do not match their checksum");
    damaged("no_checksum", "DELETE FROM lacet_meta WHERE key = 'checksum'", "lacet_meta has no 'checksum'");
}

TEST_F(SceneFileFailure, OverwrittenBytesAreRefusedWithoutACrash) {
    // 512 bytes of garbage at 23 places: refused (by SQLite's quick_check, the checks of every value or
    // the checksum), or, where it fell on unused space, the scene saved.
    const std::string good = file("good.gpkg");
    saveScene(good, syntheticDocument());
    const std::string bytes = readBytes(good);
    int refused = 0, loaded = 0;
    for (std::size_t at = 4096; at + 4096 <= bytes.size(); at += bytes.size() / 23) {
        std::string copy = bytes;
        for (std::size_t k = 0; k < 512; ++k) copy[at + k] = char((k * 131 + at) & 0xff);
        const std::string path = file("garbage.gpkg");
        writeBytes(path, copy);
        try {
            // Garbage over unused space: what loads is then the scene saved, bit for bit (the checksum).
            EXPECT_TRUE(identical(loadScene(path), syntheticDocument())) << "garbage at byte " << at;
            ++loaded;
        } catch (const SceneFileError& e) {
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
            ++refused;
        }
    }
    std::printf("[ figures ] overwritten pages: %d refused, %d loaded\n", refused, loaded);
    EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// A child process saves over the file in a loop and is killed (SIGKILL) at varying moments: the
// file at the path always opens and holds one of the two scenes, whole.
TEST_F(SceneFileFailure, KillingTheProcessDuringASaveLeavesAWholeScene) {
    const SceneDocument& big = syntheticDocument();
    const SceneDocument small = handDocument(true);
    const std::string path = file("killed.gpkg");
    saveScene(path, small);
    int sawOld = 0, sawNew = 0;
    for (int delayMs : {1, 5, 12, 25, 50, 100, 200}) {
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            for (;;) saveScene(path, big);  // killed from outside
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
        ::kill(child, SIGKILL);
        int status = 0;
        ::waitpid(child, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status));
        const SceneDocument loaded = loadScene(path);
        const bool isOld = identical(loaded, small), isNew = identical(loaded, big);
        EXPECT_TRUE(isOld || isNew) << "after a kill at " << delayMs << " ms";
        sawOld += isOld;
        sawNew += isNew;
    }
    std::printf("[ figures ] killed saves: %d left the old scene, %d the new one, 0 a broken file\n", sawOld, sawNew);
}

}  // namespace
}  // namespace lacet

namespace lacet {
namespace {

// Two editors of one file (issue 26's concurrent writers): the second save over it, made from what
// it read before the first's, is refused by name and loses neither; saved again from the file's new
// checksum, it goes through.
TEST_F(SceneFileFailure, ASaveOverAFileChangedSinceItWasReadIsRefused) {
    const std::string path = file("shared.gpkg");
    saveScene(path, handDocument(true));
    std::string readByA, readByB;
    SceneDocument a = loadScene(path, readByA), b = loadScene(path, readByB);
    ASSERT_EQ(readByA, readByB);
    EXPECT_EQ(readByA, storedSceneChecksum(path));
    b.scene.layers[0].curves[0].wf += 1.0f;
    const std::string afterB = saveSceneOver(path, b, readByB);
    EXPECT_EQ(afterB, storedSceneChecksum(path));
    EXPECT_NE(afterB, readByA);
    a.scene.layers[0].curves[0].wf += 2.0f;
    try {
        saveSceneOver(path, a, readByA);
        ADD_FAILURE() << "A saved over B's edits";
    } catch (const SceneFileChangedError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("changed since it was read"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(identical(loadScene(path), b));
    const std::string afterA = saveSceneOver(path, a, afterB);  // A read B's save (its checksum) and saves again
    EXPECT_TRUE(identical(loadScene(path), a));
    EXPECT_EQ(afterA, storedSceneChecksum(path));
    EXPECT_THROW(saveSceneOver(file("nowhere.gpkg"), a, afterA), SceneFileError);
}

// Two processes save over the file at the same moment from the same checksum: they take turns
// under the file's lock, one succeeds and the other is refused, and the file holds the first's.
TEST_F(SceneFileFailure, TwoSavesOverOneFileAtOnceTakeTurns) {
    const std::string path = file("raced.gpkg");
    saveScene(path, handDocument(true));
    const std::string base = storedSceneChecksum(path);
    SceneDocument docs[2] = {syntheticDocument(), syntheticDocument()};
    docs[1].scene.layers[0].curves[0].w += 1.0f;
    for (int round = 0; round < 3; ++round) {
        SCOPED_TRACE("round " + std::to_string(round));
        saveScene(path, handDocument(true));
        int go[2];
        ASSERT_EQ(::pipe(go), 0);
        pid_t children[2];
        for (int k = 0; k < 2; ++k) {
            children[k] = ::fork();
            ASSERT_GE(children[k], 0);
            if (children[k] == 0) {
                char c;
                ::close(go[1]);
                if (::read(go[0], &c, 1) != 0) ::_exit(9);  // both start when the parent closes the pipe
                try {
                    saveSceneOver(path, docs[k], base);
                    ::_exit(0);
                } catch (const SceneFileChangedError&) {
                    ::_exit(3);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "save %d: %s\n", k, e.what());
                    ::_exit(4);
                }
            }
        }
        ::close(go[0]);
        ::close(go[1]);
        int codes[2];
        for (int k = 0; k < 2; ++k) {
            int status = 0;
            ::waitpid(children[k], &status, 0);
            codes[k] = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
        ASSERT_TRUE((codes[0] == 0 && codes[1] == 3) || (codes[0] == 3 && codes[1] == 0)) << codes[0] << " " << codes[1];
        EXPECT_TRUE(identical(loadScene(path), docs[codes[0] == 0 ? 0 : 1]));
    }
}

}  // namespace
}  // namespace lacet
