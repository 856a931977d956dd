// The pyramid's tile arithmetic (pyramid/pyramid_tiles.h): a mipmap averages its four children
// into their quadrants, a half decode is the child at half size; mismatched sizes are refused.
#include "tests/pyramid/pyramid_fixtures.h"

namespace lacet {
namespace {

TEST(PyramidTiles, MipmapAveragesEachChildIntoItsQuadrant) {
    std::array<PyramidImage, 4> kids;
    for (int k = 0; k < 4; ++k) {
        kids[std::size_t(k)].size = 4;
        kids[std::size_t(k)].rgb.assign(48, std::uint8_t(10 * (k + 1)));
        kids[std::size_t(k)].water.assign(16, std::uint8_t(k == 3 ? 255 : 0));
    }
    kids[0].rgb[0] = 13;  // one texel of the lower-left child's top-left 2x2 block: (13 + 10 * 3 + 2) / 4 = 11
    const PyramidImage p = mipmap({&kids[0], &kids[1], &kids[2], &kids[3]});
    ASSERT_EQ(p.size, 4);
    // Rows top first: the top half comes from the upper children (2 left, 3 right).
    EXPECT_EQ(p.rgb[(0 * 4 + 0) * 3], 30);
    EXPECT_EQ(p.rgb[(0 * 4 + 3) * 3], 40);
    EXPECT_EQ(p.rgb[(2 * 4 + 0) * 3], 11);
    EXPECT_EQ(p.rgb[(3 * 4 + 3) * 3], 20);
    EXPECT_EQ(p.water[0 * 4 + 3], 255);
    EXPECT_EQ(p.water[3 * 4 + 0], 0);
    PyramidImage odd = kids[0];
    odd.size = 3;
    EXPECT_THROW(mipmap({&odd, &kids[1], &kids[2], &kids[3]}), std::invalid_argument);
}

// What a parent reads of a child tile: half size, near the 2 x 2 mean of the full decode for a
// JPEG (scaled IDCT), exactly it for a PNG.
TEST(PyramidTiles, HalfDecodeIsTheChildAtHalfSize) {
    PyramidImage image;
    image.size = 256;
    image.rgb.resize(256 * 256 * 3);
    image.water.assign(256 * 256, 0);
    for (std::size_t k = 0; k < image.rgb.size(); ++k) image.rgb[k] = std::uint8_t((k * 7 / 3 + (k / 768) * 5) % 251);
    const PyramidImage exact = halve(image);
    const DecodedImage png = decodeImageHalf(encodeRgb(image.rgb, 256, 256, parseEncoding("png:1")));
    ASSERT_EQ(png.width, 128);
    EXPECT_EQ(png.pixels, exact.rgb);
    for (int y = 0; y < 256; ++y)  // a smooth image: JPEG keeps it well
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c) image.rgb[std::size_t((y * 256 + x) * 3 + c)] = std::uint8_t((x + y + 40 * c) / 3);
    const PyramidImage smooth = halve(image);
    const DecodedImage jpeg = decodeImageHalf(encodeRgb(image.rgb, 256, 256, parseEncoding("jpeg:90")));
    ASSERT_EQ(jpeg.width, 128);
    ASSERT_EQ(jpeg.channels, 3);
    double worst = 0.0;
    for (std::size_t k = 0; k < jpeg.pixels.size(); ++k) worst = std::max(worst, std::abs(double(jpeg.pixels[k]) - smooth.rgb[k]));
    EXPECT_LE(worst, 6.0);
}
}  // namespace
}  // namespace lacet
