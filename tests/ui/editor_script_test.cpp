// The editor in a real window (Mesa's software OpenGL under xvfb-run): scripted sessions from
// tests/scripts replayed by `lacet edit --script`, on the Andorra scene when its data is beside the
// repository, else on a synthetic one.
//  - Drag: a road's on-curve vertex dragged 200 m lands there; the screenshot after the drag differs
//    from the one before around the new place, and the tiles there hold the road's flattened
//    footprint (b = 1, z_e off the DEM) and asphalt; undo gives back the first screenshot exactly,
//    redo the second, and the saved then reopened scene the second again.
//  - Drawing: a road drawn by clicking from an existing node joins it (a junction: the node's degree
//    grows by one) and one undo removes the road and the node made for its other end.
//  - A scene file read lazily (--vector-budget, editor/lazy_forest.h): viewed from high and low
//    with no background through the terrain and parts read; a save is refused and leaves the file
//    as it was.
//  - Flyover: from 3000 m down to 5 m above a road with a 1 ms production budget per frame, read on
//    a clock stepped 0.02 ms at each reading (model/work_clock.h), so that the same few tiles a
//    frame are made on any machine and many leaves are shown with coarser ancestors' tiles, some
//    of them several levels up (with a real 8 ms budget, cracks showed only in the slower
//    sanitizer build): no screenshot shows the background through the terrain.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/image_file.h"
#include "io/scene_file.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

bool haveXvfb() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

// Runs a script; returns its log.
nlohmann::json runScript(const std::string& script, const std::string& logName, const std::string& out) {
    fs::remove_all(out);
    fs::create_directories(out);
    const std::string andorra = std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra";
    // Under the sanitizers, leak checking is off for the editor's process: Mesa's driver keeps
    // allocations until exit and is unloaded before LeakSanitizer runs, so they cannot be named
    // or suppressed. Memory errors are still checked; the session's leaks by the in-process tests.
    const std::string cmd = std::string("ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1280x800x24' ") + LACET_BINARY +
                            " edit --script " + LACET_SOURCE_DIR + "/tests/scripts/" + script + " --out " + out + " --andorra " +
                            andorra + " --curves 20000 --width 800 --height 500 > " + out + "/stdout.txt 2>&1";
    const int rc = std::system(cmd.c_str());
    std::ifstream log(out + "/" + logName);
    if (rc != 0 || !log) {
        std::ifstream o(out + "/stdout.txt");
        ADD_FAILURE() << cmd << " failed (" << rc << "):\n" << std::string(std::istreambuf_iterator<char>(o), {});
        return {};
    }
    return nlohmann::json::parse(log);
}

// Pixels that differ between two images within `radius` of (x, y).
std::size_t differingNear(const Image8& a, const Image8& b, double x, double y, int radius) {
    std::size_t n = 0;
    for (int j = std::max(0, int(y) - radius); j < std::min(a.height, int(y) + radius); ++j)
        for (int i = std::max(0, int(x) - radius); i < std::min(a.width, int(x) + radius); ++i) {
            const std::size_t k = (std::size_t(j) * std::size_t(a.width) + std::size_t(i)) * std::size_t(a.channels);
            n += a.pixels[k] != b.pixels[k] || a.pixels[k + 1] != b.pixels[k + 1] || a.pixels[k + 2] != b.pixels[k + 2];
        }
    return n;
}

TEST(EditorScript, DraggingARoadPointMovesItsFootprintAndUndoSaveAndReopenAreExact) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/install_deps.sh installs it)";
    const std::string out = ::testing::TempDir() + "/lacet_editor_drag";
    const nlohmann::json log = runScript("drag_undo_save.json", "drag-log.json", out);
    ASSERT_FALSE(log.is_null());
    ASSERT_EQ(log["drags"].size(), 1u);
    const nlohmann::json& drag = log["drags"][0];
    EXPECT_NEAR(drag["moved_m"].get<double>(), 200.0, 3.0);
    EXPECT_LT(drag["error_m"].get<double>(), 3.0);  // within a pixel's footprint of the target
    // The tiles at the new place: the road's footprint, level across (b = 1, z_e set), and asphalt.
    const nlohmann::json& probe = log["probes"][0]["result"];
    EXPECT_EQ(probe["b"].get<double>(), 1.0);
    EXPECT_NE(probe["ze"].get<double>(), probe["zo"].get<double>());
    EXPECT_LT(probe["rgb"][0].get<int>(), 90);  // dark grey
    EXPECT_LT(std::abs(probe["rgb"][0].get<int>() - probe["rgb"][1].get<int>()), 12);
    const Image8 before = readImage8(out + "/before.png"), after = readImage8(out + "/after.png");
    const Image8 undone = readImage8(out + "/undone.png"), redone = readImage8(out + "/redone.png");
    const Image8 reopened = readImage8(out + "/reopened.png");
    EXPECT_GT(differingNear(before, after, drag["target_pixel"][0].get<double>(), drag["target_pixel"][1].get<double>(), 12), 40u);
    EXPECT_TRUE(undone.pixels == before.pixels) << "undo does not give back the first image";
    EXPECT_TRUE(redone.pixels == after.pixels) << "redo does not give back the edited image";
    EXPECT_TRUE(reopened.pixels == after.pixels) << "the saved and reopened scene does not show the edit";
    for (const auto& s : log["screenshots"]) EXPECT_EQ(s["background_pixels"].get<int>(), 0) << s["file"];
    std::cout << "[ figures  ] scene " << log["scene"] << ", vertex moved " << drag["moved_m"] << " m, b = " << probe["b"]
              << ", z_e - z_o = " << probe["ze"].get<double>() - probe["zo"].get<double>() << " m\n";
}

TEST(EditorScript, NoBackgroundShowsThroughTheTerrainAlongAFlyover) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/install_deps.sh installs it)";
    const std::string out = ::testing::TempDir() + "/lacet_editor_fly";
    const nlohmann::json log = runScript("flyover_cracks.json", "fly-log.json", out);
    ASSERT_FALSE(log.is_null());
    ASSERT_GE(log["screenshots"].size(), 8u);
    std::size_t coarser = 0;
    for (const auto& s : log["screenshots"]) {
        EXPECT_EQ(s["background_pixels"].get<int>(), 0) << s["file"];
        coarser += s["fallback_quads"].get<std::size_t>();
    }
    EXPECT_GT(coarser, 0u);  // the budget left leaves to be shown with their ancestors' tiles
    double sum = 0.0;
    for (const auto& f : log["frames"]) {
        EXPECT_EQ(f["missing"].get<int>(), 0);
        sum += f["update_ms"].get<double>();
    }
    std::cout << "[ figures  ] " << log["frames"].size() << " frames, mean update " << sum / double(log["frames"].size())
              << " ms, " << coarser << " leaves shown coarser in the screenshots\n";
}

// A scene file read lazily (a vector budget) in the window: viewed with its parts; a save with no
// edit writes nothing; a road point dragged is saved into the file in place, and the file then
// loads whole (its checksum checked) with that one curve changed.
TEST(EditorScript, ASceneReadLazilyIsEditedInTheWindowAndSavedInPlace) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/install_deps.sh installs it)";
    const std::string out = ::testing::TempDir() + "/lacet_editor_lazy";
    const std::string dir = ::testing::TempDir() + "/lacet_editor_lazy_scene";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string scene = dir + "/scene.gpkg";
    ASSERT_EQ(std::system((std::string(LACET_BINARY) + " synth --curves 20000 --out " + scene + " > " + dir + "/synth.txt 2>&1").c_str()), 0);
    const auto size = fs::file_size(scene);
    const auto written = fs::last_write_time(scene);
    const SceneDocument original = loadScene(scene);
    fs::remove_all(out);
    fs::create_directories(out);
    const std::string cmd = std::string("ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1280x800x24' ") + LACET_BINARY + " edit " +
                            scene + " --vector-budget 64 --part-level 3 --script " + LACET_SOURCE_DIR +
                            "/tests/scripts/lazy_view.json --out " + out + " --width 800 --height 500 > " + out + "/stdout.txt 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(out + "/lazy-log.json");
    ASSERT_TRUE(in) << cmd;
    const nlohmann::json log = nlohmann::json::parse(in);
    ASSERT_TRUE(log.contains("lazy"));
    EXPECT_EQ(log["lazy"]["part_level"].get<int>(), 3);
    ASSERT_EQ(log["screenshots"].size(), 4u);
    for (const auto& s : log["screenshots"]) EXPECT_EQ(s["background_pixels"].get<int>(), 0) << s["file"];
    std::vector<std::string> saves;
    for (const auto& m : log["messages"])
        if (m.get<std::string>().rfind("Saved", 0) == 0 || m.get<std::string>().rfind("Not saved", 0) == 0) saves.push_back(m);
    ASSERT_EQ(saves.size(), 2u) << log["messages"].dump();
    EXPECT_EQ(saves[0].rfind("Saved 0 edited elements", 0), 0u) << saves[0];  // nothing to save: the file untouched
    EXPECT_EQ(saves[1].rfind("Saved ", 0), 0u) << saves[1];
    EXPECT_EQ(saves[1].rfind("Saved 0 ", 0), std::string::npos) << saves[1];
    EXPECT_NE(fs::last_write_time(scene), written);
    EXPECT_GT(size, 0u);
    // The file saved in place loads whole, its checksum checked, with one road curve changed.
    const SceneDocument saved = loadScene(scene);
    std::size_t changed = 0;
    for (std::size_t l = 0; l < original.scene.layers.size(); ++l)
        for (std::size_t k = 0; k < original.scene.layers[l].curves.size(); ++k)
            changed += original.scene.layers[l].curves[k].vertices != saved.scene.layers[l].curves[k].vertices;
    EXPECT_EQ(changed, 1u);
    fs::remove_all(dir);
}

TEST(EditorScript, ARoadDrawnFromANodeJoinsItAndOneUndoRemovesIt) {
    if (!haveXvfb()) GTEST_SKIP() << "xvfb-run is not installed (scripts/install_deps.sh installs it)";
    const std::string out = ::testing::TempDir() + "/lacet_editor_draw";
    const nlohmann::json log = runScript("draw_road.json", "draw-log.json", out);
    ASSERT_FALSE(log.is_null());
    ASSERT_EQ(log["inspections"].size(), 3u);
    const nlohmann::json &before = log["inspections"][0], &drawn = log["inspections"][1], &undone = log["inspections"][2];
    ASSERT_TRUE(drawn.contains("selected")) << drawn.dump();
    const nlohmann::json& road = drawn["selected"];
    EXPECT_EQ(road["start"], before["focus_curve"]["start"]);  // snapped to the existing node
    EXPECT_EQ(road["start_degree"].get<int>(), before["focus_curve"]["start_degree"].get<int>() + 1);
    EXPECT_EQ(road["end_degree"].get<int>(), 1);
    EXPECT_EQ(road["vertices"].get<int>(), 7);  // three points: two cubic pieces
    EXPECT_EQ(drawn["curves"].get<int>(), before["curves"].get<int>() + 1);
    EXPECT_EQ(drawn["nodes"].get<int>(), before["nodes"].get<int>() + 1);
    EXPECT_EQ(undone["curves"], before["curves"]);
    EXPECT_EQ(undone["nodes"], before["nodes"]);
    EXPECT_EQ(undone["focus_curve"]["start_degree"], before["focus_curve"]["start_degree"]);
}

}  // namespace
}  // namespace lacet
