// Golden images of the appearance producer on small hand-made scenes (tests/golden/*.png),
// compared with a tolerance. After a deliberate change of the shading, regenerate them with
//   LACET_UPDATE_GOLDEN=1 ./build/tests/lacet_tests --gtest_filter='Golden*'
// and look at every image before committing them.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "io/image_file.h"
#include "tests/raster/hand_render.h"
#include "tests/raster/hand_scenes.h"

namespace lacet {
namespace {

constexpr int kMaxChannelDifference = 2;  // of 255: libm differences across machines
constexpr double kMaxMeanDifference = 0.05;

class Golden : public testing::TestWithParam<test::NamedScene> {};

TEST_P(Golden, AppearanceMatchesTheStoredImage) {
    const test::NamedScene& s = GetParam();
    const std::vector<std::uint8_t> image = test::renderHandScene(s.make());
    const int side = 256;
    const std::string path = std::string(LACET_SOURCE_DIR) + "/tests/golden/appearance_" + s.name + ".png";
    if (std::getenv("LACET_UPDATE_GOLDEN")) {
        writeImage8(path, side, side, 3, image);
        GTEST_SKIP() << "regenerated " << path;
    }
    const Image8 golden = readImage8(path);
    ASSERT_EQ(golden.width, side);
    ASSERT_EQ(golden.height, side);
    ASSERT_EQ(golden.channels, 3);
    int worst = 0;
    double sum = 0.0;
    for (std::size_t k = 0; k < image.size(); ++k) {
        const int d = std::abs(int(image[k]) - int(golden.pixels[k]));
        worst = std::max(worst, d);
        sum += d;
    }
    const double mean = sum / double(image.size());
    if (worst > kMaxChannelDifference || mean > kMaxMeanDifference) {
        const std::string actual = "golden_actual_" + s.name + ".png";
        writeImage8(actual, side, side, 3, image);
        ADD_FAILURE() << s.name << ": largest channel difference " << worst << ", mean " << mean << "; wrote " << actual;
    }
}

INSTANTIATE_TEST_SUITE_P(HandScenes, Golden, testing::ValuesIn(test::handScenes()),
                         [](const testing::TestParamInfo<test::NamedScene>& p) { return p.param.name; });

}  // namespace
}  // namespace lacet
