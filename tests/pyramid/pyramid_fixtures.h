#pragma once
// What the pyramid tests share: a small synthetic scene and pyramid, temporary files, the tiles of
// a pyramid compared, a DEM written as a LOD tree.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unordered_map>
#include <random>
#include <stdexcept>

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include "io/dem_lod.h"
#include "io/dem_stream.h"
#include "io/gpkg_dem.h"
#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "io/tile_codec.h"
#include "pyramid/pyramid_build.h"
#include "pyramid/pyramid_check.h"
#include "pyramid/pyramid_reader.h"
#include "pyramid/pyramid_tiles.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

inline SceneDocument smallScene(std::uint64_t seed = 7, std::size_t curves = 1500) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({seed, curves});
    doc.dem = makeSyntheticDem(doc.scene, {seed, 800});
    return doc;
}

inline PyramidParams smallParams() {
    PyramidParams p;
    p.minLevel = 0;
    p.maxLevel = 3;
    p.shardLevel = 1;
    p.encoding = parseEncoding("png:1");
    return p;
}

struct TempFile {
    std::string path;
    explicit TempFile(const std::string& name) : path((fs::temp_directory_path() / ("lacet_" + name)).string()) { fs::remove(path); }
    ~TempFile() { fs::remove(path); }
};

using Tiles = std::vector<std::pair<PyramidKey, std::vector<std::uint8_t>>>;
inline Tiles tilesOf(const std::string& path, const char* table) {
    PyramidStore s(path, PyramidStore::Mode::ReadOnly);
    return s.allTiles(table);
}

inline void expectSamePyramid(const std::string& a, const std::string& b) {
    for (const char* t : {kAppearanceTable, kWaterTable, kElevationTable}) {
        const Tiles ta = tilesOf(a, t), tb = tilesOf(b, t);
        ASSERT_EQ(ta.size(), tb.size()) << t;
        std::size_t differ = 0;
        for (std::size_t i = 0; i < ta.size(); ++i) {
            ASSERT_EQ(ta[i].first, tb[i].first) << t;
            if (ta[i].second != tb[i].second) ++differ;
        }
        EXPECT_EQ(differ, 0u) << t << ": tiles that differ";
    }
    PyramidStore sa(a, PyramidStore::Mode::ReadOnly), sb(b, PyramidStore::Mode::ReadOnly);
    EXPECT_EQ(sa.digests(), sb.digests());
}

// `dem` written as a LOD tree of 16-sample blocks into a new GeoPackage at `path`.
inline std::shared_ptr<const DemLodFile> writeTree(const Dem& dem, const std::string& path) {
    createEmptyGpkg(path);
    {
        SqliteDb db(path, SqliteDb::Mode::ReadWrite);
        writeDemLod(db, dem, 16, 0);
        db.close();
    }
    return std::make_shared<const DemLodFile>(path);
}

}  // namespace
}  // namespace lacet
