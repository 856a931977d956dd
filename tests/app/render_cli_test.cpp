// `lacet render` refuses, before any work, an image it cannot hold (issue 12: a whole scene at a
// deep level died of std::bad_alloc after 30 s), saying how large it would be; a region that misses
// the scene is refused too; a small render still works. A scene file rendered by parts gives the
// image of the scene read whole.
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "io/scene_features.h"
#include "io/sqlite_db.h"

namespace lacet {
namespace {

struct RenderRun {
    int code = -1;
    std::string said;
    double seconds = 0.0;
};

RenderRun render(const std::string& args, const std::filesystem::path& log) {
    const auto t0 = std::chrono::steady_clock::now();
    const int status = std::system((std::string(LACET_BINARY) + " render " + args + " > " + log.string() + " 2>&1").c_str());
    RenderRun r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    r.said = ss.str();
    return r;
}

TEST(RenderCli, RefusesAnImageItCannotHoldBeforeAnyWork) {
    const auto dir = std::filesystem::temp_directory_path() / ("lacet_render_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string png = (dir / "x.png").string();
    const RenderRun deep = render("--seed 1 --curves 1000 --level 14 --layer appearance --out " + png, dir / "log");
    EXPECT_EQ(deep.code, 1) << deep.said;
    EXPECT_NE(deep.said.find("268,435,456 tiles"), std::string::npos) << deep.said;  // 4^14
    EXPECT_NE(deep.said.find("--max-pixels"), std::string::npos) << deep.said;
    EXPECT_FALSE(std::filesystem::exists(png));

    const RenderRun away = render("--seed 1 --curves 1000 --level 2 --region 1e6,1e6,2e6,2e6 --out " + png, dir / "log");
    EXPECT_EQ(away.code, 1) << away.said;
    EXPECT_NE(away.said.find("does not meet the scene"), std::string::npos) << away.said;

    const RenderRun small = render("--seed 1 --curves 1000 --level 1 --layer appearance --out " + png, dir / "log");
    EXPECT_EQ(small.code, 0) << small.said;
    EXPECT_TRUE(std::filesystem::exists(png));
    std::filesystem::remove_all(dir);
}

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A scene file rendered by parts (--vectors region: each block of --part-tiles tiles read from the
// file alone, io/scene_region.h) gives the image of the scene read whole, byte for byte, over the
// whole scene and over a region whose blocks are cut by its border; a part over its budget is
// refused with the figure and no image is written.
TEST(RenderCli, AScenesPartsReadAloneGiveTheImageOfTheWholeScene) {
    const auto dir = std::filesystem::temp_directory_path() / ("lacet_render_parts_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string scene = (dir / "scene.gpkg").string();
    ASSERT_EQ(std::system((std::string(LACET_BINARY) + " synth --seed 5 --curves 3000 --out " + scene + " > " + (dir / "synth.log").string() +
                           " 2>&1")
                              .c_str()),
              0);
    const auto image = [&](const std::string& args, const std::string& name) {
        const std::string png = (dir / name).string();
        const RenderRun r = render("--scene " + scene + " " + args + " --out " + png, dir / (name + ".log"));
        EXPECT_EQ(r.code, 0) << r.said;
        return std::make_pair(fileBytes(png), r.said);
    };
    const auto whole = image("--level 4 --layer appearance --vectors whole", "whole.png");
    const auto parts = image("--level 4 --layer appearance --part-tiles 2", "parts.png");
    ASSERT_FALSE(whole.first.empty());
    EXPECT_TRUE(whole.first == parts.first) << "the image read by parts differs from the whole scene's";
    EXPECT_NE(parts.second.find("by parts (--vectors region) of at most 2 tiles a side: 64 reads"), std::string::npos) << parts.second;
    const std::string region = " --region 1500,2500,9000,7000";
    const auto wholeRegion = image("--level 5 --layer elevation --vectors whole" + region, "whole_region.png");
    const auto partsRegion = image("--level 5 --layer elevation --part-tiles 4" + region, "parts_region.png");
    ASSERT_FALSE(wholeRegion.first.empty());
    EXPECT_TRUE(wholeRegion.first == partsRegion.first) << "the region read by parts differs from the whole scene's";

    const std::string refusedPng = (dir / "refused.png").string();
    const RenderRun refused = render("--scene " + scene + " --level 4 --vector-budget 0.01 --out " + refusedPng, dir / "refused.log");
    EXPECT_EQ(refused.code, 1) << refused.said;
    EXPECT_NE(refused.said.find("budget of 0.01 MiB"), std::string::npos) << refused.said;
    EXPECT_NE(refused.said.find(scene), std::string::npos) << refused.said;
    EXPECT_FALSE(std::filesystem::exists(refusedPng));
    // Options of the reads by parts where there are none: refused.
    EXPECT_EQ(render("--scene " + scene + " --level 2 --vectors whole --part-tiles 4 --out " + refusedPng, dir / "whole.log").code, 1);
    EXPECT_EQ(render("--scene " + scene + " --level 2 --part-tiles 3 --out " + refusedPng, dir / "three.log").code, 1);

    // A file saved before the feature index: read whole, once, the same image.
    {
        SqliteDb db(scene, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("DROP TABLE ") + kFeatureIndexTable);
        db.close();
    }
    const auto old = image("--level 4 --layer appearance --part-tiles 2", "old.png");
    EXPECT_TRUE(old.first == whole.first) << "the file without its feature index renders otherwise";
    EXPECT_NE(old.second.find("1 reads"), std::string::npos) << old.second;
    EXPECT_NE(old.second.find("it was read whole, once"), std::string::npos) << old.second;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
