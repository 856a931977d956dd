// The editor and the pyramid (§7, Fig. 10; issue 15): below the pyramid's first vector level L the
// session's appearance tiles are the pyramid's, at L and deeper (and every elevation tile) they are
// produced live; after an edit the quads below L it changed are produced live (equal to a session
// without the pyramid) and the others still read; a corrupt tile falls back to live production
// and is counted. The pyramid is built in a temporary file, lossless (PNG), levels 0..4.
#include "editor/edit_session.h"

#include <unistd.h>

#include <sqlite3.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/tile_codec.h"
#include "model/edits.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_tiles.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

constexpr int kMaxLevel = 4, kVectorLevels = 2;  // L = 3: levels 0..2 read, 3 and 4 made from vectors

SceneDocument pyramidDocument() {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({5, 1500});
    doc.dem = makeSyntheticDem(doc.scene, {5, 1000});
    return doc;
}

SessionParams sessionParams() {
    SessionParams params;
    params.view.maxLevel = 6;
    params.view.K = 1.0;  // coarser views than the default 2.8: many leaves below L
    params.cacheTiles = 1u << 20;  // nothing evicted: every tile made stays to be compared
    return params;
}

// Raw SQLite, as a GIS tool would see the file (the test reads and spoils tiles behind the reader).
struct Sql {
    sqlite3* db = nullptr;
    explicit Sql(const std::string& path) {
        if (sqlite3_open(path.c_str(), &db) != SQLITE_OK) ADD_FAILURE() << "cannot open " << path;
    }
    ~Sql() { sqlite3_close(db); }
    std::optional<std::vector<std::uint8_t>> blob(const char* table, int level, std::uint32_t tx, std::uint32_t ty) {
        const std::string sql = std::string("SELECT tile_data FROM ") + table + " WHERE zoom_level = ? AND tile_column = ? AND tile_row = ?";
        sqlite3_stmt* st = nullptr;
        EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
        sqlite3_bind_int(st, 1, level);
        sqlite3_bind_int64(st, 2, tx);
        sqlite3_bind_int64(st, 3, (std::int64_t(1) << level) - 1 - std::int64_t(ty));  // GeoPackage rows from the north
        std::optional<std::vector<std::uint8_t>> out;
        if (sqlite3_step(st) == SQLITE_ROW) {
            const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(st, 0));
            out.emplace(p, p + sqlite3_column_bytes(st, 0));
        }
        sqlite3_finalize(st);
        return out;
    }
    // Overwrites every tile of `level` with a PNG signature followed by garbage.
    void spoil(const char* table, int level) {
        const std::string sql = std::string("UPDATE ") + table + " SET tile_data = X'89504E470D0A1A0A0000DEADBEEF' WHERE zoom_level = ?";
        sqlite3_stmt* st = nullptr;
        ASSERT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &st, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
        sqlite3_bind_int(st, 1, level);
        ASSERT_EQ(sqlite3_step(st), SQLITE_DONE);
        sqlite3_finalize(st);
        EXPECT_EQ(sqlite3_changes(db), 1 << (2 * level));
    }
};

// The editor's tile of quad q as the pyramid file holds it, decoded without the reader.
AppearanceTile pyramidTile(Sql& sql, const Quad& q, int border, int size) {
    PyramidImage image;
    image.size = size;
    const auto rgb = sql.blob("lacet_appearance", q.level, q.tx, q.ty);
    EXPECT_TRUE(rgb.has_value());
    if (!rgb) return {};
    const DecodedImage d = decodeImage(*rgb);
    EXPECT_EQ(d.width, size);
    EXPECT_EQ(d.channels, 3);
    image.rgb = d.pixels;
    image.water.assign(std::size_t(size) * std::size_t(size), 0);
    if (const auto water = sql.blob("lacet_water", q.level, q.tx, q.ty)) image.water = decodeImage(*water).pixels;
    return appearanceTile(image, q.bounds, border);
}

class EditSessionPyramid : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = std::filesystem::temp_directory_path() / ("lacet_pyramid_test_" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        path_ = (dir_ / "scene.pyramid.gpkg").string();
        PyramidParams params;
        params.maxLevel = kMaxLevel;
        params.vectorLevels = kVectorLevels;
        params.encoding.format = TileFormat::Png;
        const PyramidStats f = buildPyramid(pyramidDocument(), path_, params, /*force=*/true, nullptr);
        std::cout << "[ figures  ] pyramid of " << f.quads << " quads, " << f.tilesMade << " tiles made in " << f.wallSeconds << " s\n";
    }
    static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

    // The flight every session makes: from above the scene down to 40 m over (x, y), each frame's
    // leaves made (no budget).
    static std::vector<glm::dvec3> flight(const SceneDocument& doc) {
        const Box e = doc.scene.extent;
        const Vec2 a = e.min + 0.3 * e.size(), b = e.min + 0.7 * e.size();
        return {{a.x, a.y, 1e9}, {a.x, a.y, 0.6 * e.size().x}, {a.x, a.y, 0.2 * e.size().x}, {b.x, b.y, 0.1 * e.size().x},
                {b.x, b.y, 300.0}, {a.x, a.y, 40.0}};
    }

    static inline std::filesystem::path dir_;
    static inline std::string path_;
};

// Walks the leaves of `s` below `level` that have a clean tile.
void forCleanLeaves(const EditSession& s, const std::function<void(const Quad&, const CachedTile&)>& f) {
    s.quadtree().forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        const CachedTile* t = s.tile(keyOf(q));
        if (t && !t->dirty) f(q, *t);
    });
}

TEST_F(EditSessionPyramid, CoarseQuadsReadThePyramidAndTheRestIsLive) {
    auto reader = std::make_shared<PyramidReader>(path_, pyramidDocument());
    ASSERT_EQ(reader->vectorLevel(), kMaxLevel - kVectorLevels + 1);
    EXPECT_TRUE(reader->serves(0) && reader->serves(2));
    EXPECT_FALSE(reader->serves(3) || reader->serves(4) || reader->serves(5));
    const SessionParams params = sessionParams();
    EditSession with(pyramidDocument(), params), without(pyramidDocument(), params);
    with.setPyramid(reader);
    Sql sql(path_);
    const int L = reader->vectorLevel(), border = params.refine.appearanceBorder;
    std::size_t read = 0, live = 0;
    for (const glm::dvec3& v : flight(with.document())) {
        const FrameReport r = with.frame(v, 0.0);
        without.frame(v, 0.0);
        EXPECT_EQ(r.pyramidFailed, 0u);
        forCleanLeaves(with, [&](const Quad& q, const CachedTile& t) {
            const CachedTile* other = without.tile(keyOf(q));
            ASSERT_NE(other, nullptr);
            EXPECT_TRUE(t.elevation == other->elevation) << "elevation of a level " << q.level << " quad";
            if (q.level < L) {
                EXPECT_TRUE(t.appearance == pyramidTile(sql, q, border, reader->tileSize())) << "level " << q.level;
                ++read;
            } else {
                EXPECT_TRUE(t.appearance == other->appearance) << "level " << q.level;
                ++live;
            }
        });
    }
    EXPECT_GT(read, 10u);
    EXPECT_GT(live, 10u);
    EXPECT_GT(with.pyramidUse().read, 10u);
    EXPECT_EQ(with.pyramidUse().failed, 0u);
    EXPECT_EQ(with.pyramidUse().read, reader->stats().read);
    std::cout << "[ figures  ] " << read << " leaf tiles compared with the pyramid's, " << live << " with live ones; "
              << with.pyramidUse().read << " read, " << with.pyramidUse().live << " made live; read " << reader->stats().readMs
              << " ms, decode " << reader->stats().decodeMs << " ms in all\n";
}

TEST_F(EditSessionPyramid, QuadsAnEditChangedAreMadeLiveAndTheOthersStillRead) {
    auto reader = std::make_shared<PyramidReader>(path_, pyramidDocument());
    const SessionParams params = sessionParams();
    EditSession with(pyramidDocument(), params), without(pyramidDocument(), params);
    with.setPyramid(reader);
    const std::vector<glm::dvec3> path = flight(with.document());
    for (const glm::dvec3& v : path) with.frame(v, 0.0), without.frame(v, 0.0);
    // Move a road's middle control point by 20 m, the first road that accepts it near (0.3, 0.3).
    const Box e = with.document().scene.extent;
    const Vec2 target = e.min + 0.3 * e.size();
    const Layer& roads = with.document().scene.layers[kRoadsLayer];
    std::vector<std::pair<double, ElementId>> byDistance;
    for (ElementId c = 0; c < roads.curves.size(); ++c)
        if (roads.curves[c].alive && roads.curves[c].vertices.size() >= 3)
            byDistance.push_back({glm::length(roads.curves[c].vertices[1].p - target), c});
    std::sort(byDistance.begin(), byDistance.end());
    bool moved = false;
    for (std::size_t k = 0; k < byDistance.size() && !moved; ++k) {
        const Curve& c = roads.curves[byDistance[k].second];
        const std::size_t i = c.vertices.size() / 2;
        const MoveVertexCmd cmd{kRoadsLayer, byDistance[k].second, i, c.vertices[i].p + Vec2(20.0, 0.0)};
        try {
            with.execute(cmd);
            without.execute(cmd);
            moved = true;
        } catch (const EditError&) {
        }
    }
    ASSERT_TRUE(moved);
    Sql sql(path_);
    const int L = reader->vectorLevel(), border = params.refine.appearanceBorder;
    std::size_t touched = 0, untouched = 0;
    for (const glm::dvec3& v : path) {
        with.frame(v, 0.0);
        without.frame(v, 0.0);
        forCleanLeaves(with, [&](const Quad& q, const CachedTile& t) {
            if (q.level >= L) return;
            const CachedTile* other = without.tile(keyOf(q));
            ASSERT_NE(other, nullptr);
            if (with.readsPyramid(q)) {
                EXPECT_TRUE(t.appearance == pyramidTile(sql, q, border, reader->tileSize())) << "untouched, level " << q.level;
                ++untouched;
            } else {
                EXPECT_TRUE(t.appearance == other->appearance) << "touched, level " << q.level;
                ++touched;
            }
        });
    }
    EXPECT_GT(touched, 0u);
    EXPECT_GT(untouched, 0u);
    EXPECT_GT(with.pyramidUse().touched, 0u);
    // The root and the quads below L holding the road are touched; those far from it are not.
    EXPECT_FALSE(with.readsPyramid(with.quadtree().root()));
    std::cout << "[ figures  ] after the edit: " << touched << " leaf tiles below L made live, " << untouched
              << " still the pyramid's\n";
    // A pyramid of the edited document (as after a save and an update) serves them all again.
    with.setPyramid(reader, with.editCount());
    EXPECT_TRUE(with.readsPyramid(with.quadtree().root()));
}

TEST_F(EditSessionPyramid, ACorruptTileIsMadeLiveAndCounted) {
    const std::string spoilt = (dir_ / "spoilt.pyramid.gpkg").string();
    std::filesystem::copy_file(path_, spoilt, std::filesystem::copy_options::overwrite_existing);
    {
        Sql sql(spoilt);
        sql.spoil("lacet_appearance", 0);  // the root: every session makes its tile first
        sql.spoil("lacet_appearance", 2);
    }
    auto reader = std::make_shared<PyramidReader>(spoilt, pyramidDocument());
    const SessionParams params = sessionParams();
    EditSession with(pyramidDocument(), params), without(pyramidDocument(), params);
    with.setPyramid(reader);
    std::size_t failed = 0, compared = 0;
    Sql sql(spoilt);
    for (const glm::dvec3& v : flight(with.document())) {
        failed += with.frame(v, 0.0).pyramidFailed;
        without.frame(v, 0.0);
        forCleanLeaves(with, [&](const Quad& q, const CachedTile& t) {
            if (q.level != 0 && q.level != 2) return;
            EXPECT_TRUE(t.appearance == without.tile(keyOf(q))->appearance) << "level " << q.level;
            ++compared;
        });
    }
    EXPECT_GE(failed, 2u);
    EXPECT_GE(compared, 2u);
    EXPECT_EQ(with.pyramidUse().failed, failed);
    EXPECT_EQ(reader->stats().corrupt, failed);
    EXPECT_GT(reader->stats().read, 0u);  // level 1 is whole
    std::cout << "[ figures  ] " << failed << " corrupt tiles made live\n";
}

TEST_F(EditSessionPyramid, APyramidOfAnotherSceneIsRefusedWithItsReason) {
    SceneDocument other = pyramidDocument();
    other.scene.extent.max += Vec2(1.0, 1.0);
    try {
        PyramidReader r(path_, other);
        FAIL() << "opened";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("extent"), std::string::npos) << e.what();
    }
    try {
        PyramidReader r((dir_ / "none.gpkg").string(), pyramidDocument());
        FAIL() << "opened";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("none.gpkg"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace lacet
