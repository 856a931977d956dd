// `lacet render` refuses, before any work, an image it cannot hold (issue 12: a whole scene at a
// deep level died of std::bad_alloc after 30 s), saying how large it would be; a region that misses
// the scene is refused too; a small render still works.
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace lacet
