#pragma once
// The scene file both lazy forest suites read (tests/editor/lazy_forest_test.cpp: what a lazy
// session shows; lazy_forest_edit_test.cpp: its edits), and the comparisons with a whole session.
// A synthetic scene of 3,000 curves saved in a temporary directory, once per suite.
#include "editor/lazy_forest.h"

#include <sqlite3.h>

#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "editor/edit_session.h"
#include "editor/lazy_edit_check.h"
#include "tests/io/gis_fixtures.h"
#include "tests/sanitized.h"
#include "editor/pyramid_link.h"
#include "io/scene_file.h"
#include "io/tile_codec.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_reader.h"
#include "model/edits.h"
#include "model/work_clock.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

constexpr int kPartLevel = 2;

inline SessionParams sessionParams() {
    SessionParams params;
    params.view.maxLevel = 6;
    params.cacheTiles = 1u << 20;  // nothing evicted: every tile made stays to be compared
    return params;
}

inline LazyParams lazyParams(double budgetMiB, bool background = false) {
    LazyParams lazy;
    lazy.partLevel = kPartLevel;
    lazy.vectorBudgetMiB = budgetMiB;
    lazy.background = background;
    return lazy;
}

class LazyForestTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::filesystem::path(test::scratchDir("lazy_forest"));
        SceneDocument doc;
        doc.scene = makeSyntheticScene({.seed = 11, .curves = 3000, .roundaboutFraction = 0.3});
        doc.dem = makeSyntheticDem(doc.scene, {.seed = 11, .resolution = 1000});
        path_ = new std::string((*dir_ / "scene.gpkg").string());
        saveScene(*path_, doc);
    }
    static void TearDownTestSuite() {
        std::filesystem::remove_all(*dir_);
        delete path_;
        delete dir_;
    }
    // Viewers low over random points of the scene (fixed seed).
    static std::vector<glm::dvec3> viewers(const Box& extent, int n, std::uint32_t seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(0.0, 1.0), h(30.0, 400.0);
        std::vector<glm::dvec3> out;
        for (int i = 0; i < n; ++i) {
            const Vec2 p = extent.min + Vec2(u(rng), u(rng)) * extent.size();
            out.push_back({p.x, p.y, h(rng)});
        }
        return out;
    }
    // A pyramid of the scene file, levels 0..3 made from vector data at 3 (L = 3), PNG tiles, in
    // the scratch directory as `name`.
    static std::string buildTestPyramid(const std::string& name) {
        const std::string pyramid = (*dir_ / name).string();
        PyramidParams pp;
        pp.maxLevel = 3;
        pp.vectorLevels = 1;
        pp.encoding.format = TileFormat::Png;
        buildPyramid(*path_, pyramid, pp, /*force=*/true, nullptr);
        return pyramid;
    }
    // The top tree's vector data and the largest part's (MiB), read with room for all by viewers
    // over random points.
    static std::pair<double, double> partSizes() {
        EditSession probe(*path_, lazyParams(1024.0), sessionParams());
        for (const glm::dvec3& v : viewers(probe.document().scene.extent, 8, 5)) probe.frame(v, 0.0);
        return {probe.lazyForest()->stats().topMiB, probe.lazyForest()->stats().largestPartMiB};
    }
    static std::filesystem::path* dir_;
    static std::string* path_;
};
std::filesystem::path* LazyForestTest::dir_ = nullptr;
std::string* LazyForestTest::path_ = nullptr;

// Every tile of `whole` that its last frame drew is `lazy`'s too, and every tile both hold made
// is the same. `lazy` may hold more of the part level: the tiles of its quads drawn from the top
// tree while their parts were read, and those an arriving part made dirty that no frame showed
// since (an ancestor's, made again when shown); with `anyMore`, of any level (budgeted frames
// show leaves whose subdivision waits). It may hold fewer, or dirty ones, that no frame shows: an
// edit that makes a part anew makes every tile below it again when shown (the whole session only
// those UPDATE changed).
inline void expectSameTiles(const EditSession& lazy, const EditSession& whole, int partLevel = kPartLevel, bool anyMore = false) {
    for (const auto& [key, t] : lazy.tiles()) {
        if (!whole.tile(key) && !anyMore) {
            EXPECT_EQ(std::get<0>(key), partLevel) << "a tile only the lazy session made";
        }
    }
    // Every tile the whole session's last frame drew stands for its leaf in the lazy session too.
    std::set<QuadKey> drawn;
    for (const DrawItem& item : whole.plan().items)
        if (item.tile) drawn.insert(item.tileKey);
    for (const auto& [key, w] : whole.tiles()) {
        const CachedTile* t = lazy.tile(key);
        const auto [level, x, y] = key;
        // Not drawn now: one that a part made anew by an edit dropped, or made dirty below it
        // (made again when shown).
        if ((!t || t->dirty) && !drawn.count(key)) continue;
        ASSERT_NE(t, nullptr) << level << "/" << x << "/" << y;
        if (t->dirty) {
            EXPECT_EQ(level, partLevel) << x << "/" << y;
            continue;
        }
        EXPECT_EQ(t->texels(), w.texels()) << level << "/" << x << "/" << y;
        EXPECT_EQ(t->elevation.zm, w.elevation.zm) << level << "/" << x << "/" << y;
        EXPECT_EQ(t->objects.indices.size(), w.objects.indices.size()) << level << "/" << x << "/" << y;
    }
}

// The report of checkLazyEdits (editor/lazy_edit_check.h): no mismatch, and enough done to mean it.
// `asked`: the edits the check was asked for (most are made; some are refused alike by both).
inline void expectSameEdits(const LazyEditCheckReport& r, bool pyramid, std::size_t asked) {
    for (const std::string& d : r.details) ADD_FAILURE() << d;
    EXPECT_EQ(r.mismatches, 0u);
    EXPECT_EQ(r.refusedDifferently, 0u);
    EXPECT_GT(r.edits, asked * 2 / 3);
    EXPECT_GT(r.undos, 0u);
    EXPECT_GT(r.tilesCompared, 50 * r.edits);
    EXPECT_GT(r.partsRenewed, 0u);
    if (pyramid) {
        // Narrow roads and fields do not read the top again (rivers and lakes always do: a river
        // anywhere may be one a road of the top bridges).
        EXPECT_GT(r.commands - r.topReads, r.commands / 4);
    }
}

}  // namespace
}  // namespace lacet
