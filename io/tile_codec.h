#pragma once
// Encoders and decoders of the tiles of a GeoPackage tile pyramid: RGB (and grey) images as PNG
// (libpng), JPEG (libjpeg-turbo) or lossy WebP (libwebp), and elevation as the float32 TIFF of the
// GeoPackage "tiled gridded coverage" extension (OGC 17-066r1, TIFF encoding), written and read by
// hand (no libtiff).
//
// Order of calls: none; every function is pure and thread-safe. Encoders are deterministic (the
// same input and knobs give the same bytes). Decoders take untrusted bytes (a file read from disk):
// anything malformed or truncated throws TileDecodeError naming the reason, never reads out of
// bounds and never ends the process (libjpeg's and libpng's fatal errors are caught).
//
// Pixel layout everywhere: rows from the top (north) first, channels interleaved.

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

namespace lacet {

enum class TileFormat : std::uint8_t { Png, Jpeg, Webp };

struct TileEncoding {
    TileFormat format = TileFormat::Jpeg;
    int jpegQuality = 90;  // 1..100 (libjpeg-turbo's scale; 4:2:0 chroma, baseline, standard Huffman tables)
    int webpQuality = 90;  // 0..100, lossy WebP (libwebp's scale; method kWebpMethod)
    int pngLevel = 1;      // zlib level 0..9 (rows filtered with kPngFilter)
};

// A tile that cannot be decoded (bad signature, truncated, corrupt, unsupported variant).
class TileDecodeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The largest width or height (pixels) an encoder writes and a decoder accepts: a corrupt header
// cannot make a decoder allocate more than kMaxTileSide^2 pixels. GeoPackage tiles are 256 or 512
// pixels wide in practice.
inline constexpr int kMaxTileSide = 8192;

// Row filters of libpng (each row is filtered before zlib).
enum class PngFilter : std::uint8_t {
    None,      // no filter (zlib strategy Z_DEFAULT_STRATEGY)
    Sub,       // difference with the pixel on the left (zlib strategy Z_FILTERED)
    Adaptive,  // libpng's default: the best of the five filters chosen per row (Z_FILTERED)
};

// The filter encodeRgb and encodeGreyPng use. Measured on 32 real appearance tiles (256 x 256, the
// synthetic scene's shading: flat areas, furrow gradients, thin roads; bench/tile_codec_bench.cpp,
// BM_PngFilter; CPU time per tile, medians of 5 on 2 shared cores): at level 1, NONE 0.59 ms and
// 15.2 kB, SUB 0.80 ms and 19.4 kB, adaptive 2.31 ms and 19.2 kB; at level 6, NONE 1.54 ms and
// 11.2 kB, SUB 1.67 ms and 13.3 kB, adaptive 2.80 ms and 11.5 kB. NONE is the fastest and also the
// smallest on these tiles (their runs of equal texels repeat as they are; differences break them
// up). Photographic tiles would favour SUB or adaptive.
inline constexpr PngFilter kPngFilter = PngFilter::None;

// The libwebp method (0 fastest .. 6 smallest) encodeRgb uses. Measured on the same tiles: quality
// 90, method 0 1.60 ms and 5.9 kB, method 4 5.8 ms and 5.1 kB; quality 75, method 0 1.00 ms and
// 3.9 kB, method 4 5.3 ms and 2.7 kB. Method 4, libwebp's default (and GDAL's): WebP is chosen for
// its size, and method 0 gives up 15 to 41 % of it (JPEG, at 0.14 ms, is the fast choice).
inline constexpr int kWebpMethod = 4;

// rgb: width * height * 3 bytes, rows from the top; width and height in 1..kMaxTileSide.
// Throws std::invalid_argument ("encodeRgb(): ...") on a size mismatch or a knob out of its range.
std::vector<std::uint8_t> encodeRgb(std::span<const std::uint8_t> rgb, int width, int height, const TileEncoding& e);

// One 8-bit grey band as PNG at zlib level pngLevel (0..9).
std::vector<std::uint8_t> encodeGreyPng(std::span<const std::uint8_t> grey, int width, int height, int pngLevel);

// The PNG encoder behind both (for the benchmark of the filters): channels 1 (grey) or 3 (RGB).
std::vector<std::uint8_t> encodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                                    int level, PngFilter filter);

// The WebP encoder behind encodeRgb (for the benchmark of the methods): quality 0..100, method 0..6.
std::vector<std::uint8_t> encodeWebp(std::span<const std::uint8_t> rgb, int width, int height, int quality, int method);

// Float32 single band as the GeoPackage gridded coverage's TIFF encoding requires: 32-bit IEEE
// float (SampleFormat 3), 1 sample per pixel, PlanarConfiguration 1, little-endian, one strip,
// uncompressed. values: width * height, rows from the top; written bit for bit (NaN payloads too).
std::vector<std::uint8_t> encodeFloatTiff(std::span<const float> values, int width, int height);

// The same TIFF with its strip deflated (Compression 8, zlib `level` 1..9), and with TIFF's
// floating-point predictor (Predictor 3) when `floatPredictor`; decodeFloatTiff and GDAL read both.
// Throws std::invalid_argument as encodeFloatTiff does and for a level outside 1..9.
std::vector<std::uint8_t> encodeFloatTiffDeflate(std::span<const float> values, int width, int height, int level,
                                                 bool floatPredictor);

struct DecodedImage {
    int width = 0, height = 0, channels = 0;  // channels: 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
    std::vector<std::uint8_t> pixels;         // width * height * channels, rows from the top
};

// Recognises PNG, JPEG and WebP by their signatures. PNG: grey, grey + alpha, RGB, RGBA or
// paletted (expanded to RGB, or RGBA when the palette has transparency), at 1, 2, 4 or 8 bits;
// 16-bit samples are refused. JPEG: grey or YCbCr/RGB (to RGB); CMYK is refused; libjpeg's warnings
// (corrupt or truncated data) are errors. WebP: still images, RGB or RGBA. Messages name the format
// and the reason ("PNG: truncated PNG", "JPEG: Premature end of JPEG file", "not a PNG, JPEG or
// WebP image").
DecodedImage decodeImage(std::span<const std::uint8_t> bytes);

// The image at half its width and height, as a pyramid's parent tile needs it (§7's mipmap): a
// JPEG through libjpeg's scaled IDCT (a 4x4 inverse DCT of each 8x8 block: the block's low
// frequencies, about 3x faster than a full decode), any other image decoded whole and each 2 x 2
// block's rounded mean. Throws TileDecodeError as decodeImage() does, and for an odd-sized image.
DecodedImage decodeImageHalf(std::span<const std::uint8_t> bytes);

struct DecodedFloats {
    int width = 0, height = 0;
    std::vector<float> values;  // width * height, rows from the top
};

// Reads the first image of a float32 single-band TIFF: little- or big-endian, strips or tiles,
// compression none (1), LZW (5) or deflate (8, 32946), predictor none (1), horizontal (2) or
// floating point (3). Anything else throws TileDecodeError ("TIFF compression 7 not supported").
DecodedFloats decodeFloatTiff(std::span<const std::uint8_t> bytes);

}  // namespace lacet
