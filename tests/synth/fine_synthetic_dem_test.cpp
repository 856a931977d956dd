// The synthetic DEM finer than memory (synth/fine_synthetic_dem.h): deterministic rows, detail of
// the stated size away from rivers and none on them, rivers still running downhill at the fine
// resolution (and not without the fade), and the rows through a DEM LOD tree read back unchanged.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/dem_import_lod.h"
#include "io/dem_lod.h"
#include "io/sqlite_db.h"
#include "model/bezier.h"
#include "synth/fine_synthetic_dem.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet {
namespace {

constexpr int kFineSide = 700;  // samples: about 8 m cells over the 2,000-curve scene's 5.8 km

struct FineDemFixture {
    Scene scene = makeSyntheticScene({1, 2000});
    Dem base = makeSyntheticDem(scene, {1, 5000});  // 20 m cells
};
const FineDemFixture& fixture() {
    static const FineDemFixture f;
    return f;
}

// Every row, as a Dem (rows j growing with y) over the scene's extent.
Dem wholeDem(const FineSyntheticDem& fine, const Box& extent) {
    const int n = fine.side();
    std::vector<float> h(std::size_t(n) * std::size_t(n));
    for (int t = 0; t < n; ++t) fine.row(t, std::span<float>(h).subspan(std::size_t(n - 1 - t) * std::size_t(n), std::size_t(n)));
    return Dem(extent, n, n, std::move(h));
}

// Points along a curve about `step` metres apart.
std::vector<Vec2> along(const Curve& c, double step) {
    std::vector<Vec2> out{c.vertices.front().p};
    forEachPiece(c.vertices, [&](const BezierPiece& b, std::size_t) {
        double polygon = 0.0;
        for (int k = 0; k < b.degree; ++k) polygon += glm::distance(b.p[std::size_t(k)], b.p[std::size_t(k + 1)]);
        const auto n = std::max<std::size_t>(1, std::size_t(std::ceil(polygon / step)));
        for (std::size_t k = 1; k <= n; ++k) out.push_back(evaluate(b, double(k) / double(n)));
    });
    return out;
}

// The largest rise of `dem` walking each river downstream above its lowest value upstream (metres).
double worstRise(const Scene& scene, const Dem& dem) {
    double worst = 0.0;
    for (const Curve& c : scene.layers[kRiversLayer].curves) {
        if (!c.alive) continue;
        double lowest = INFINITY;
        for (const Vec2 p : along(c, 2.0)) {
            const double z = dem.sample(p);
            worst = std::max(worst, z - lowest);
            lowest = std::min(lowest, z);
        }
    }
    return worst;
}

TEST(FineSyntheticDem, RowsAreDeterministicAndSeeded) {
    const FineDemFixture& f = fixture();
    const FineSyntheticDem a(f.scene, f.base, {.side = kFineSide, .seed = 3});
    const FineSyntheticDem b(f.scene, f.base, {.side = kFineSide, .seed = 3});
    const FineSyntheticDem c(f.scene, f.base, {.side = kFineSide, .seed = 4});
    EXPECT_NEAR(a.cell(), f.scene.extent.size().x / kFineSide, 1e-9);
    std::vector<float> ra(kFineSide), rb(kFineSide), rc(kFineSide), again(kFineSide);
    for (const int t : {0, 123, kFineSide - 1}) {
        a.row(t, ra);
        b.row(t, rb);
        c.row(t, rc);
        EXPECT_EQ(ra, rb) << "row " << t;
        EXPECT_NE(ra, rc) << "row " << t << ": another seed, other detail";
    }
    a.row(5, again);
    a.row(123, ra);
    a.row(5, rb);
    EXPECT_EQ(again, rb) << "a row does not depend on the rows made before";
}

TEST(FineSyntheticDem, DetailAwayFromRiversNoneOnThem) {
    const FineDemFixture& f = fixture();
    const FineDemParams p{.side = kFineSide};
    const FineSyntheticDem fine(f.scene, f.base, p);
    double largest = 0.0;
    std::vector<float> row(kFineSide);
    for (int t = 0; t < kFineSide; t += 7) {
        fine.row(t, row);
        for (int i = 0; i < kFineSide; ++i) largest = std::max(largest, std::abs(row[std::size_t(i)] - f.base.sample(fine.position(i, t))));
    }
    EXPECT_GT(largest, 0.5 * p.amplitude) << "metres";
    EXPECT_LE(largest, p.amplitude + 1e-3) << "metres";
    std::size_t onRivers = 0;
    for (const Curve& c : f.scene.layers[kRiversLayer].curves)
        for (const Vec2 q : along(c, 10.0)) {
            ASSERT_EQ(fine.fade(q), 0.0);
            for (const Vec2 d : {Vec2(p.riverFade, 0.0), Vec2(0.0, -p.riverFade)}) ASSERT_EQ(fine.fade(q + 0.99 * d), 0.0);
            ++onRivers;
        }
    EXPECT_GT(onRivers, 100u);
    EXPECT_THROW(FineSyntheticDem(f.scene, f.base, {.side = 1}), std::invalid_argument);
}

TEST(FineSyntheticDem, RiversStillRunDownhillAtTheFineResolution) {
    constexpr double kRiseTolerance = 0.5;  // metres, the base's (tests/raster/dem_test.cpp)
    const FineDemFixture& f = fixture();
    const FineSyntheticDem fine(f.scene, f.base, {.side = kFineSide});
    const double rise = worstRise(f.scene, wholeDem(fine, f.scene.extent));
    std::printf("[   info   ] %d samples a side (%.1f m cells): worst rise %.3f m along the rivers (base: %.3f m)\n", kFineSide,
                fine.cell(), rise, worstRise(f.scene, f.base));
    EXPECT_LE(rise, kRiseTolerance);
    // Without the fade the same detail makes the rivers climb: the check can fail.
    const FineSyntheticDem unfaded(f.scene, f.base, {.side = kFineSide, .riverFade = 0.0, .distanceCell = 2.0});
    EXPECT_GT(worstRise(f.scene, wholeDem(unfaded, f.scene.extent)), kRiseTolerance);
}

TEST(FineSyntheticDem, RowsThroughALodTreeReadBackUnchanged) {
    const FineDemFixture& f = fixture();
    const FineSyntheticDem fine(f.scene, f.base, {.side = kFineSide});
    const DemLodLayout layout = DemLodLayout::make(kFineSide, kFineSide, fine.cell(), fine.topLeft(), 64);
    const auto path = std::filesystem::temp_directory_path() / ("lacet_test_fine_dem_" + std::to_string(::getpid()) + ".gpkg");
    std::filesystem::remove(path);
    const DemLodOutput out = writeDemLodFile(path.string(), layout, [&](int t, std::span<float> row) { fine.row(t, row); }, 256);
    EXPECT_EQ(out.layout.levels, 5) << "700 samples in blocks of 64: 64 x 2^4 = 1024 a side";
    ASSERT_TRUE(out.coarse);
    EXPECT_LE(out.coarse->width(), 256);
    const Dem whole = wholeDem(fine, f.scene.extent);
    const Dem back = readDemLevel(DemLodFile(path.string()), layout.levels - 1);
    EXPECT_EQ(back.heights(), whole.heights());
    for (int axis = 0; axis < 2; ++axis) {
        EXPECT_NEAR(back.extent().min[axis], whole.extent().min[axis], 1e-6);
        EXPECT_NEAR(back.extent().max[axis], whole.extent().max[axis], 1e-6);
    }
    EXPECT_EQ(out.coarse->heights(), readDemLevel(DemLodFile(path.string()), out.coarseLevel).heights());
    {
        // Scene metres: GeoPackage's undefined Cartesian CRS (-1), not its undefined geographic (0).
        SqliteDb db(path.string(), SqliteDb::Mode::ReadOnly);
        EXPECT_EQ(db.queryInteger("SELECT srs_id FROM gpkg_tile_matrix_set WHERE table_name = 'dem_lod'"), -1);
        EXPECT_EQ(db.queryInteger("SELECT srs_id FROM gpkg_contents WHERE table_name = 'dem_lod'"), -1);
    }
    std::filesystem::remove(path);
}

// `lacet synth --dem-side` writes its tree under a name of its own beside --out and removes only
// that: a user's file named like the old fixed temporary name (<out>.dem.tmp) survives.
TEST(FineSyntheticDem, SynthCliLeavesAUsersDemTmpFileAlone) {
    const auto dir = std::filesystem::temp_directory_path() / ("lacet_test_synth_cli_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string out = (dir / "scene.gpkg").string(), mine = out + ".dem.tmp", log = (dir.parent_path() / "synth_cli.log").string();
    std::ofstream(mine, std::ios::binary) << "my notes";
    const std::string cmd = std::string(LACET_BINARY) + " synth --curves 200 --dem-side 300 --json --out '" + out + "' > '" + log + "' 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(mine, std::ios::binary);
    EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), "my notes");
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"scene.gpkg", "scene.gpkg.dem.tmp"}));
    std::filesystem::remove_all(dir);
    std::filesystem::remove(log);
}

}  // namespace
}  // namespace lacet
