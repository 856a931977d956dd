// `lacet synth --out` writes the fields while the file is saved (issue 23: a scene larger than
// memory); the file holds the very scene makeSyntheticScene makes, and --base-dem-max-side bounds the
// in-memory DEM a --dem-side DEM is made from.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/dem_lod.h"
#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"

namespace lacet {
namespace {

// Exit status and JSON of `lacet synth ARGS --json`.
std::pair<int, nlohmann::json> synth(const std::string& args, const std::filesystem::path& dir) {
    const std::filesystem::path out = dir / "synth.json";
    const int status = std::system((std::string(LACET_BINARY) + " synth " + args + " --json > " + out.string() + " 2> " +
                                    (dir / "synth.err").string()).c_str());
    const int code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream in(out);
    return {code, code == 0 ? nlohmann::json::parse(in) : nlohmann::json()};
}

// The checksum of a scene alone (no DEM, no georeference).
std::string sceneSum(const Scene& scene) {
    SceneDocument doc;
    doc.scene = scene;
    return sceneChecksumText(doc);
}

TEST(SynthCli, TheSceneFileHoldsTheSyntheticSceneMadeAPartAtATime) {
    const auto dir = test::scratchDir("synth_cli");
    const std::string path = (dir / "s.gpkg").string();
    const auto [code, json] = synth("--seed 4 --curves 30000 --dem-resolution 500 --out " + path, dir);
    ASSERT_EQ(code, 0);
    EXPECT_TRUE(json["scene_file"]["fields_made_while_saving"].get<bool>());
    const Scene expected = makeSyntheticScene({4, 30000});
    EXPECT_EQ(json["curves"].get<std::size_t>(), count(expected).curves);
    EXPECT_GT(expected.layers[kFieldsLayer].curves.size(), 3 * 8192u) << "not several parts";
    const SceneDocument back = loadScene(path);  // its checksum checked
    EXPECT_EQ(sceneSum(back.scene), sceneSum(expected));
    ASSERT_TRUE(back.dem.has_value());
    std::filesystem::remove_all(dir);
}

TEST(SynthCli, TheBaseOfAFineDemIsNoLargerThanAsked) {
    const auto dir = test::scratchDir("synth_cli");
    const std::string path = (dir / "s.gpkg").string();
    // 3000 curves: 7071 m a side, 354 base samples at the default 20 m cells; 64 asked.
    const auto [code, json] = synth("--seed 2 --curves 3000 --dem-side 256 --base-dem-max-side 64 --out " + path, dir);
    ASSERT_EQ(code, 0);
    const auto& lod = json["scene_file"]["dem_lod"];
    EXPECT_LE(lod["base_dem_samples"][0].get<int>(), 64);
    EXPECT_GE(lod["base_dem_samples"][0].get<int>(), 60);
    EXPECT_EQ(lod["dem_side"].get<int>(), 256);
    const SceneDocument back = loadScene(path);
    ASSERT_TRUE(back.demLod);
    EXPECT_EQ(back.demLod->layout().width, 256);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lacet
