// The tile codecs (io/tile_codec.h): round trips of every format (PNG and TIFF bit for bit, JPEG and
// WebP within a tolerance), deterministic encoders, truncated and corrupt tiles refused with
// TileDecodeError, TIFFs written by GDAL's GTiff driver read back (every compression and predictor
// supported, strips and tiles, both byte orders), and our tiles read by GDAL (what GIS tools see).
#include "io/tile_codec.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>

namespace lacet {
namespace {

using Bytes = std::vector<std::uint8_t>;

// A terrain-like picture: smooth colour gradients, a sharp road-like band and a little noise.
Bytes testImage(int width, int height, int channels) {
    Bytes out(std::size_t(width) * std::size_t(height) * std::size_t(channels));
    std::uint32_t noise = 12345;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c) {
                noise = noise * 1664525u + 1013904223u;
                const double smooth = 110.0 + 60.0 * std::sin(double(x) / 23.0 + double(c)) * std::cos(double(y) / 31.0);
                const bool road = std::abs(x - y / 2 - width / 4) < 4;
                const double v = road ? 200.0 + 10.0 * double(c) : smooth + double(noise >> 29);
                out[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels) + std::size_t(c)] =
                    std::uint8_t(std::clamp(v, 0.0, 255.0));
            }
    return out;
}

// Peak signal-to-noise ratio (dB) of b against a, 8-bit samples.
double psnr(const Bytes& a, const Bytes& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += (double(a[i]) - double(b[i])) * (double(a[i]) - double(b[i]));
    return 10.0 * std::log10(255.0 * 255.0 / (sum / double(a.size())));
}

int maxDifference(const Bytes& a, const Bytes& b) {
    int m = 0;
    for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(int(a[i]) - int(b[i])));
    return m;
}

std::vector<float> testFloats(int width, int height) {
    std::vector<float> v(std::size_t(width) * std::size_t(height));
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = 812.25f + 37.5f * std::sin(float(i) * 0.37f) + float(i % 7) * 0.001f;
    v[0] = -std::numeric_limits<float>::infinity();
    v[1] = std::numeric_limits<float>::infinity();
    v[2] = -0.0f;
    v[3] = std::numeric_limits<float>::denorm_min();
    v[4] = std::numeric_limits<float>::max();
    v[5] = std::numeric_limits<float>::lowest();
    return v;
}

void expectSameBits(const std::vector<float>& expected, const std::vector<float>& actual) {
    ASSERT_EQ(expected.size(), actual.size());
    for (std::size_t i = 0; i < expected.size(); ++i)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(expected[i]), std::bit_cast<std::uint32_t>(actual[i])) << "value " << i;
}

Bytes truncated(const Bytes& b, std::size_t n) { return Bytes(b.begin(), b.begin() + std::ptrdiff_t(n)); }

// ---- GDAL ----

std::string memPath(const std::string& extension) {
    static int counter = 0;
    return "/vsimem/tile_codec_test_" + std::to_string(counter++) + "." + extension;
}

Bytes takeMemFile(const std::string& path) {
    vsi_l_offset length = 0;
    GByte* data = VSIGetMemFileBuffer(path.c_str(), &length, TRUE);
    Bytes out(data, data + length);
    CPLFree(data);
    return out;
}

// A float32 single-band GeoTIFF written by GDAL's GTiff driver with creation options.
Bytes gdalTiff(const std::vector<float>& values, int width, int height, const std::vector<std::string>& options) {
    GDALAllRegister();
    CPLStringList list;
    for (const auto& o : options) list.AddString(o.c_str());
    const std::string path = memPath("tif");
    GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), width, height, 1, GDT_Float32, list.List());
    EXPECT_NE(ds, nullptr);
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, width, height, const_cast<float*>(values.data()), width,
                                             height, GDT_Float32, 0, 0, nullptr),
              CE_None);
    GDALClose(ds);
    return takeMemFile(path);
}

// An 8-bit image of 1 to 4 bands written by a GDAL driver (PNG, JPEG) from a MEM dataset.
Bytes gdalImage(const char* driver, const Bytes& pixels, int width, int height, int bands, const GDALColorTable* palette,
                const std::vector<std::string>& options) {
    GDALAllRegister();
    GDALDataset* mem = GetGDALDriverManager()->GetDriverByName("MEM")->Create("", width, height, bands, GDT_Byte, nullptr);
    EXPECT_EQ(mem->RasterIO(GF_Write, 0, 0, width, height, const_cast<std::uint8_t*>(pixels.data()), width, height, GDT_Byte,
                            bands, nullptr, bands, std::int64_t(width) * bands, 1, nullptr),
              CE_None);
    if (palette) mem->GetRasterBand(1)->SetColorTable(const_cast<GDALColorTable*>(palette));
    CPLStringList list;
    for (const auto& o : options) list.AddString(o.c_str());
    const std::string path = memPath("img");
    GDALDataset* out = GetGDALDriverManager()->GetDriverByName(driver)->CreateCopy(path.c_str(), mem, FALSE, list.List(), nullptr, nullptr);
    EXPECT_NE(out, nullptr);
    GDALClose(out);
    GDALClose(mem);
    return takeMemFile(path);
}

// What GDAL reads from a blob: its bands interleaved (8-bit), or its first band as float32.
struct GdalRead {
    int width = 0, height = 0, bands = 0;
    Bytes pixels;
    std::vector<float> floats;
    std::string driver;
};

GdalRead gdalRead(const Bytes& blob, bool asFloat) {
    GDALAllRegister();
    const std::string path = memPath("blob");
    VSIFCloseL(VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(blob.data()), vsi_l_offset(blob.size()), FALSE));
    GdalRead r;
    GDALDataset* ds = GDALDataset::FromHandle(GDALOpen(path.c_str(), GA_ReadOnly));
    EXPECT_NE(ds, nullptr);
    if (ds) {
        r.width = ds->GetRasterXSize();
        r.height = ds->GetRasterYSize();
        r.bands = ds->GetRasterCount();
        r.driver = ds->GetDriver()->GetDescription();
        if (asFloat) {
            EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Float32);
            r.floats.resize(std::size_t(r.width) * std::size_t(r.height));
            EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, r.width, r.height, r.floats.data(), r.width, r.height,
                                                     GDT_Float32, 0, 0, nullptr),
                      CE_None);
        } else {
            r.pixels.resize(std::size_t(r.width) * std::size_t(r.height) * std::size_t(r.bands));
            EXPECT_EQ(ds->RasterIO(GF_Read, 0, 0, r.width, r.height, r.pixels.data(), r.width, r.height, GDT_Byte, r.bands,
                                   nullptr, r.bands, std::int64_t(r.width) * r.bands, 1, nullptr),
                      CE_None);
        }
        GDALClose(ds);
    }
    VSIUnlink(path.c_str());
    return r;
}

// ---- round trips ----

TEST(TileCodec, PngRoundTripsAreExactForRgbAndGreyWithEveryFilter) {
    const Bytes rgb = testImage(256, 256, 3), grey = testImage(200, 120, 1);
    for (PngFilter f : {PngFilter::None, PngFilter::Sub, PngFilter::Adaptive})
        for (int level : {0, 1, 6, 9}) {
            const DecodedImage a = decodeImage(encodePng(rgb, 256, 256, 3, level, f));
            EXPECT_EQ(a.width, 256);
            EXPECT_EQ(a.height, 256);
            EXPECT_EQ(a.channels, 3);
            EXPECT_EQ(a.pixels, rgb) << "level " << level;
            const DecodedImage b = decodeImage(encodePng(grey, 200, 120, 1, level, f));
            EXPECT_EQ(b.channels, 1);
            EXPECT_EQ(b.pixels, grey) << "level " << level;
        }
    TileEncoding e;
    e.format = TileFormat::Png;
    EXPECT_EQ(decodeImage(encodeRgb(rgb, 256, 256, e)).pixels, rgb);
    EXPECT_EQ(decodeImage(encodeGreyPng(grey, 200, 120, 3)).pixels, grey);
}

TEST(TileCodec, JpegAndWebpRoundTripsAreWithinTolerance) {
    const Bytes rgb = testImage(256, 256, 3);
    struct Case {
        TileFormat format;
        int quality;
        double minPsnr;  // dB
        int maxError;    // 8-bit levels, at the sharp band's edges
    };
    // Measured: JPEG q90 38.8 dB and 47 at most, q75 36.6 dB and 64; WebP q90 38.6 dB and 44, q75
    // 36.8 dB and 46 (the picture's noise of 0..7 levels bounds the PSNR).
    for (const Case c : {Case{TileFormat::Jpeg, 90, 38.0, 56}, Case{TileFormat::Jpeg, 75, 35.5, 72},
                         Case{TileFormat::Webp, 90, 37.5, 52}, Case{TileFormat::Webp, 75, 35.5, 56}}) {
        TileEncoding e;
        e.format = c.format;
        e.jpegQuality = e.webpQuality = c.quality;
        const DecodedImage d = decodeImage(encodeRgb(rgb, 256, 256, e));
        EXPECT_EQ(d.width, 256);
        EXPECT_EQ(d.height, 256);
        ASSERT_EQ(d.channels, 3);
        EXPECT_GT(psnr(rgb, d.pixels), c.minPsnr) << int(c.format) << " q" << c.quality;
        EXPECT_LE(maxDifference(rgb, d.pixels), c.maxError) << int(c.format) << " q" << c.quality;
    }
    // WebP's other methods decode as well.
    for (int method = 0; method <= 6; ++method)
        EXPECT_GT(psnr(rgb, decodeImage(encodeWebp(rgb, 256, 256, 90, method)).pixels), 37.5) << "method " << method;
}

TEST(TileCodec, TiffRoundTripIsBitExactIncludingInfinitiesAndNanPayloads) {
    std::vector<float> v = testFloats(24, 24);
    v[6] = std::bit_cast<float>(0x7fc00001u);  // quiet NaN with a payload
    v[7] = std::bit_cast<float>(0xffa00000u);  // signalling NaN, sign set
    v[8] = std::numeric_limits<float>::quiet_NaN();
    const Bytes tiff = encodeFloatTiff(v, 24, 24);
    EXPECT_EQ(tiff.size(), 148u + 24u * 24u * 4u);
    const DecodedFloats d = decodeFloatTiff(tiff);
    EXPECT_EQ(d.width, 24);
    EXPECT_EQ(d.height, 24);
    expectSameBits(v, d.values);

    const std::vector<float> wide = testFloats(300, 7);
    const DecodedFloats w = decodeFloatTiff(encodeFloatTiff(wide, 300, 7));
    EXPECT_EQ(w.width, 300);
    EXPECT_EQ(w.height, 7);
    expectSameBits(wide, w.values);
}

TEST(TileCodec, EncodersAreDeterministic) {
    const Bytes rgb = testImage(256, 256, 3), grey = testImage(64, 64, 1);
    for (TileFormat f : {TileFormat::Png, TileFormat::Jpeg, TileFormat::Webp}) {
        TileEncoding e;
        e.format = f;
        EXPECT_EQ(encodeRgb(rgb, 256, 256, e), encodeRgb(rgb, 256, 256, e)) << int(f);
    }
    EXPECT_EQ(encodeWebp(rgb, 256, 256, 75, 4), encodeWebp(rgb, 256, 256, 75, 4));
    EXPECT_EQ(encodeGreyPng(grey, 64, 64, 6), encodeGreyPng(grey, 64, 64, 6));
    const std::vector<float> v = testFloats(24, 24);
    EXPECT_EQ(encodeFloatTiff(v, 24, 24), encodeFloatTiff(v, 24, 24));
}

TEST(TileCodec, EncodersRefuseBadArguments) {
    const Bytes rgb = testImage(16, 16, 3);
    TileEncoding e;
    EXPECT_THROW(encodeRgb(rgb, 16, 15, e), std::invalid_argument);
    EXPECT_THROW(encodeRgb(rgb, 0, 16, e), std::invalid_argument);
    e.jpegQuality = 0;
    EXPECT_THROW(encodeRgb(rgb, 16, 16, e), std::invalid_argument);
    e = {};
    e.format = TileFormat::Webp;
    e.webpQuality = 101;
    EXPECT_THROW(encodeRgb(rgb, 16, 16, e), std::invalid_argument);
    e = {};
    e.format = TileFormat::Png;
    e.pngLevel = 10;
    EXPECT_THROW(encodeRgb(rgb, 16, 16, e), std::invalid_argument);
    EXPECT_THROW(encodeGreyPng(rgb, 16, 16, 1), std::invalid_argument);
    EXPECT_THROW(encodeWebp(rgb, 16, 16, 90, 7), std::invalid_argument);
    EXPECT_THROW(encodeFloatTiff(std::vector<float>(10), 3, 3), std::invalid_argument);
    EXPECT_THROW(encodeFloatTiff(std::vector<float>(std::size_t(kMaxTileSide + 1)), kMaxTileSide + 1, 1), std::invalid_argument);
}

// ---- PNG variants other writers make ----

TEST(TileCodec, DecodesPngOfEveryColourTypeWrittenByGdal) {
    const int w = 37, h = 21;
    for (int bands : {1, 2, 3, 4}) {
        const Bytes pixels = testImage(w, h, bands);
        const DecodedImage d = decodeImage(gdalImage("PNG", pixels, w, h, bands, nullptr, {}));
        EXPECT_EQ(d.width, w);
        EXPECT_EQ(d.height, h);
        EXPECT_EQ(d.channels, bands);
        EXPECT_EQ(d.pixels, pixels) << bands << " bands";
    }
    // 1-bit grey, expanded to 0 and 255.
    Bytes bits(std::size_t(w) * h);
    for (std::size_t i = 0; i < bits.size(); ++i) bits[i] = std::uint8_t((i * 7919) % 5 < 2 ? 1 : 0);
    const DecodedImage one = decodeImage(gdalImage("PNG", bits, w, h, 1, nullptr, {"NBITS=1"}));
    ASSERT_EQ(one.channels, 1);
    for (std::size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(one.pixels[i], bits[i] ? 255 : 0) << i;

    // Paletted, opaque (expanded to RGB) and with a transparent entry (expanded to RGBA).
    for (bool transparent : {false, true}) {
        GDALColorTable palette;
        for (short i = 0; i < 4; ++i) {
            const GDALColorEntry c{short(i * 60), short(255 - i * 50), short(i * 20 + 7), short(transparent && i == 2 ? 0 : 255)};
            palette.SetColorEntry(i, &c);
        }
        Bytes index(std::size_t(w) * h);
        for (std::size_t i = 0; i < index.size(); ++i) index[i] = std::uint8_t((i * 31) % 4);
        const DecodedImage d = decodeImage(gdalImage("PNG", index, w, h, 1, &palette, {}));
        ASSERT_EQ(d.channels, transparent ? 4 : 3);
        for (std::size_t i = 0; i < index.size(); ++i) {
            const GDALColorEntry* c = palette.GetColorEntry(index[i]);
            const std::uint8_t* p = d.pixels.data() + i * std::size_t(d.channels);
            ASSERT_EQ(p[0], c->c1);
            ASSERT_EQ(p[1], c->c2);
            ASSERT_EQ(p[2], c->c3);
            if (transparent) {
                ASSERT_EQ(p[3], c->c4);
            }
        }
    }
}

TEST(TileCodec, DecodesGreyJpegWrittenByGdal) {
    const Bytes grey = testImage(64, 48, 1);
    const DecodedImage d = decodeImage(gdalImage("JPEG", grey, 64, 48, 1, nullptr, {"QUALITY=95"}));
    EXPECT_EQ(d.width, 64);
    EXPECT_EQ(d.height, 48);
    ASSERT_EQ(d.channels, 1);
    EXPECT_GT(psnr(grey, d.pixels), 38.0);
}

// ---- truncated and corrupt tiles ----

TEST(TileCodec, TruncatedImagesThrow) {
    const Bytes rgb = testImage(64, 64, 3);
    for (TileFormat f : {TileFormat::Png, TileFormat::Jpeg, TileFormat::Webp}) {
        TileEncoding e;
        e.format = f;
        const Bytes full = encodeRgb(rgb, 64, 64, e);
        std::vector<std::size_t> cuts = {0, 1, 2, 3, 7, 8, 11, 12, 16, 20, 33, 40, 64, 100};
        for (std::size_t k = 1; k < 8; ++k) cuts.push_back(full.size() * k / 8);
        for (std::size_t k = 1; k <= 16; ++k) cuts.push_back(full.size() - k);
        for (std::size_t n : cuts) {
            ASSERT_LT(n, full.size());
            EXPECT_THROW(decodeImage(truncated(full, n)), TileDecodeError) << int(f) << " cut at " << n << " of " << full.size();
        }
    }
}

std::string decodeMessage(const Bytes& b) {
    try {
        decodeImage(b);
    } catch (const TileDecodeError& e) {
        return e.what();
    }
    return "decoded";
}

TEST(TileCodec, TruncatedImagesSaySo) {
    const Bytes rgb = testImage(64, 64, 3);
    TileEncoding e;
    e.format = TileFormat::Png;
    const Bytes png = encodeRgb(rgb, 64, 64, e);
    EXPECT_EQ(decodeMessage(truncated(png, png.size() / 2)), "PNG: truncated PNG");
    EXPECT_EQ(decodeMessage(truncated(png, 5)), "truncated PNG");
    e.format = TileFormat::Jpeg;
    const Bytes jpeg = encodeRgb(rgb, 64, 64, e);
    EXPECT_EQ(decodeMessage(truncated(jpeg, jpeg.size() / 2)), "JPEG: Premature end of JPEG file");
    e.format = TileFormat::Webp;
    const Bytes webp = encodeRgb(rgb, 64, 64, e);
    EXPECT_EQ(decodeMessage(truncated(webp, webp.size() / 2)), "WebP: truncated WebP");
    EXPECT_EQ(decodeMessage({}), "empty tile: not a PNG, JPEG or WebP image");
    const std::vector<float> v = testFloats(24, 24);
    try {
        decodeFloatTiff(truncated(encodeFloatTiff(v, 24, 24), 1000));
        FAIL() << "decoded";
    } catch (const TileDecodeError& x) {
        EXPECT_STREQ(x.what(), "TIFF: truncated (strip at byte 148, 2304 bytes, beyond the end at 1000)");
    }
}

TEST(TileCodec, CorruptImagesThrowOrDecodeButNeverCrash) {
    const Bytes rgb = testImage(48, 32, 3);
    const Bytes garbage = {'G', 'I', 'F', '8', '9', 'a', 0, 0, 0, 0, 0, 0, 0};
    try {
        decodeImage(garbage);
        FAIL() << "garbage decoded";
    } catch (const TileDecodeError& e) {
        EXPECT_STREQ(e.what(), "not a PNG, JPEG or WebP image");
    }
    const Bytes jpegHeaderOnly = {0xff, 0xd8, 0xff, 0xe0, 0, 0, 0, 0, 0, 0};
    EXPECT_THROW(decodeImage(jpegHeaderOnly), TileDecodeError);
    for (TileFormat f : {TileFormat::Png, TileFormat::Jpeg, TileFormat::Webp}) {
        TileEncoding e;
        e.format = f;
        const Bytes full = encodeRgb(rgb, 48, 32, e);
        std::size_t thrown = 0;
        for (std::size_t i = 0; i < full.size(); i += 3) {
            Bytes bad = full;
            bad[i] ^= 0x5a;
            try {
                const DecodedImage d = decodeImage(bad);
                EXPECT_EQ(d.pixels.size(), std::size_t(d.width) * std::size_t(d.height) * std::size_t(d.channels));
            } catch (const TileDecodeError&) {
                ++thrown;
            }
        }
        // PNG's CRCs catch every flipped byte; JPEG and WebP have no checksum over their data.
        if (f == TileFormat::Png) {
            EXPECT_EQ(thrown, (full.size() + 2) / 3);
        }
        EXPECT_GT(thrown, 0u) << int(f);
    }
}

TEST(TileCodec, TruncatedTiffThrowsAtEveryLength) {
    const std::vector<float> v = testFloats(24, 24);
    const Bytes full = encodeFloatTiff(v, 24, 24);
    for (std::size_t n = 0; n < full.size(); ++n) EXPECT_THROW(decodeFloatTiff(truncated(full, n)), TileDecodeError) << "cut at " << n;

    // GDAL's files may end with bytes the image does not need: a cut there decodes the same image.
    for (const auto& options : std::vector<std::vector<std::string>>{{"COMPRESS=DEFLATE", "PREDICTOR=3"}, {"COMPRESS=LZW"}}) {
        const Bytes g = gdalTiff(v, 24, 24, options);
        for (std::size_t n = 0; n < g.size(); ++n) {
            try {
                expectSameBits(v, decodeFloatTiff(truncated(g, n)).values);
            } catch (const TileDecodeError&) {
            }
        }
    }
}

TEST(TileCodec, CorruptTiffThrowsOrDecodesButNeverReadsOutOfBounds) {
    const std::vector<float> v = testFloats(24, 24);
    for (const Bytes& full : {encodeFloatTiff(v, 24, 24), gdalTiff(v, 24, 24, {"COMPRESS=LZW", "PREDICTOR=3"}),
                              gdalTiff(v, 24, 24, {"COMPRESS=DEFLATE"})}) {
        for (std::size_t i = 0; i < std::min<std::size_t>(full.size(), 400); ++i)
            for (std::uint8_t flip : {std::uint8_t(0x01), std::uint8_t(0x80), std::uint8_t(0xff)}) {
                Bytes bad = full;
                bad[i] ^= flip;
                try {
                    const DecodedFloats d = decodeFloatTiff(bad);
                    EXPECT_EQ(d.values.size(), std::size_t(d.width) * std::size_t(d.height));
                } catch (const TileDecodeError&) {
                }
            }
    }
    const Bytes good = encodeFloatTiff(v, 24, 24);
    // The width entry's value (IFD at 8, first entry, value at 8 + 2 + 8).
    Bytes wide = good;
    wide[18] = 0x28;  // 9000 = 0x2328
    wide[19] = 0x23;
    EXPECT_THROW(decodeFloatTiff(wide), TileDecodeError);
    Bytes notTiff = good;
    notTiff[2] = 41;
    EXPECT_THROW(decodeFloatTiff(notTiff), TileDecodeError);
}

// ---- GDAL's TIFFs read by us ----

TEST(TileCodec, ReadsTiffsWrittenByGdal) {
    struct Case {
        int width, height;
        std::vector<std::string> options;
        // GDAL 3.6.2 with libtiff 4.5.0 writes big-endian files with the floating point predictor
        // that it reads back as other values itself (1001.5 as 8.9e-39): there we read what GDAL reads.
        bool gdalWritesWrongValues = false;
    };
    const std::vector<Case> cases = {
        {24, 24, {}},
        {24, 24, {"COMPRESS=DEFLATE"}},
        {24, 24, {"COMPRESS=DEFLATE", "PREDICTOR=3"}},
        {24, 24, {"COMPRESS=LZW"}},
        {24, 24, {"COMPRESS=LZW", "PREDICTOR=3"}},
        {24, 24, {"COMPRESS=LZW", "PREDICTOR=2"}},
        {24, 24, {"ENDIANNESS=BIG"}},
        {24, 24, {"ENDIANNESS=BIG", "COMPRESS=LZW"}},
        {24, 24, {"ENDIANNESS=BIG", "COMPRESS=DEFLATE", "PREDICTOR=2"}},
        {24, 24, {"ENDIANNESS=BIG", "COMPRESS=DEFLATE", "PREDICTOR=3"}, true},
        {300, 200, {}},  // several strips, the last one shorter
        {300, 200, {"COMPRESS=LZW", "PREDICTOR=3"}},
        {300, 200, {"COMPRESS=DEFLATE", "BLOCKYSIZE=7"}},
        {300, 200, {"TILED=YES", "BLOCKXSIZE=128", "BLOCKYSIZE=64"}},  // tiles past the image's edges
        {300, 200, {"TILED=YES", "COMPRESS=LZW", "PREDICTOR=3"}},
        {300, 200, {"TILED=YES", "COMPRESS=DEFLATE", "PREDICTOR=2", "ENDIANNESS=BIG"}},
    };
    for (const Case& c : cases) {
        std::string name;
        for (const auto& o : c.options) name += o + " ";
        SCOPED_TRACE(name);
        std::vector<float> v = testFloats(c.width, c.height);
        v[9] = std::numeric_limits<float>::quiet_NaN();
        const Bytes tiff = gdalTiff(v, c.width, c.height, c.options);
        DecodedFloats d;
        ASSERT_NO_THROW(d = decodeFloatTiff(tiff));
        EXPECT_EQ(d.width, c.width);
        EXPECT_EQ(d.height, c.height);
        expectSameBits(gdalRead(tiff, true).floats, d.values);
        if (!c.gdalWritesWrongValues) expectSameBits(v, d.values);
        if (HasFailure()) return;
    }
    const Bytes packbits = gdalTiff(testFloats(24, 24), 24, 24, {"COMPRESS=PACKBITS"});
    try {
        decodeFloatTiff(packbits);
        FAIL() << "PackBits decoded";
    } catch (const TileDecodeError& e) {
        EXPECT_STREQ(e.what(), "TIFF compression 32773 not supported");
    }
}

// ---- our tiles read by GDAL ----

TEST(TileCodec, GdalReadsOurTilesAsWeDo) {
    std::vector<float> v = testFloats(24, 24);
    v[6] = std::bit_cast<float>(0x7fc00001u);
    const GdalRead t = gdalRead(encodeFloatTiff(v, 24, 24), true);
    EXPECT_EQ(t.driver, "GTiff");
    EXPECT_EQ(t.width, 24);
    EXPECT_EQ(t.height, 24);
    EXPECT_EQ(t.bands, 1);
    expectSameBits(v, t.floats);

    const Bytes rgb = testImage(256, 256, 3);
    for (TileFormat f : {TileFormat::Png, TileFormat::Jpeg, TileFormat::Webp}) {
        TileEncoding e;
        e.format = f;
        const Bytes tile = encodeRgb(rgb, 256, 256, e);
        const GdalRead g = gdalRead(tile, false);
        EXPECT_EQ(g.driver, f == TileFormat::Png ? "PNG" : f == TileFormat::Jpeg ? "JPEG" : "WEBP");
        EXPECT_EQ(g.width, 256);
        EXPECT_EQ(g.height, 256);
        EXPECT_EQ(g.bands, 3);
        const DecodedImage ours = decodeImage(tile);
        // GDAL decodes with the same libpng, libjpeg-turbo and libwebp: the same pixels.
        EXPECT_EQ(g.pixels, ours.pixels) << int(f);
    }
    const Bytes grey = testImage(40, 30, 1);
    const GdalRead g = gdalRead(encodeGreyPng(grey, 40, 30, 1), false);
    EXPECT_EQ(g.bands, 1);
    EXPECT_EQ(g.pixels, grey);
}

}  // namespace
}  // namespace lacet
