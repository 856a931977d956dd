#include "io/tile_codec.h"

#include <stdio.h>  // jpeglib.h uses FILE and size_t without including their header

#include <jpeglib.h>
#include <png.h>
#include <webp/decode.h>
#include <webp/encode.h>

#include <algorithm>
#include <array>
#include <bit>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "io/tile_codec_args.h"

// libpng and libjpeg report fatal errors through a callback that must not return: it longjmps back to
// a setjmp in a small function (pngWriteRows, jpegReadHeader...) whose frame, like the C frames it
// skips, holds no object with a destructor. What must outlive the jump (the output, the message)
// lives in a state struct in the caller's frame, which then throws.

namespace lacet {
namespace {

// ---- arguments ----

// checkImageArgs(): io/tile_codec_args.h.

void checkRange(const char* what, int value, int lo, int hi) {
    if (value < lo || value > hi)
        throw std::invalid_argument(std::string(what) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi) +
                                    ", got " + std::to_string(value));
}

// ---- PNG ----

struct PngState {
    std::jmp_buf jump;
    char message[200] = {};
    std::vector<std::uint8_t>* out = nullptr;  // writing
    const std::uint8_t* in = nullptr;          // reading
    std::size_t inSize = 0, inPos = 0;
};

[[noreturn]] void pngError(png_structp png, png_const_charp message) {
    auto* s = static_cast<PngState*>(png_get_error_ptr(png));
    std::snprintf(s->message, sizeof s->message, "%s", message);
    std::longjmp(s->jump, 1);
}

void pngIgnoreWarning(png_structp, png_const_charp) {}

void pngWriteBytes(png_structp png, png_bytep data, std::size_t n) {
    auto* s = static_cast<PngState*>(png_get_io_ptr(png));
    bool ok = true;
    try {
        s->out->insert(s->out->end(), data, data + n);
    } catch (const std::bad_alloc&) {
        ok = false;
    }
    if (!ok) png_error(png, "out of memory");
}

void pngReadBytes(png_structp png, png_bytep data, std::size_t n) {
    auto* s = static_cast<PngState*>(png_get_io_ptr(png));
    if (s->inSize - s->inPos < n) png_error(png, "truncated PNG");
    std::memcpy(data, s->in + s->inPos, n);
    s->inPos += n;
}

int pngFilterMask(PngFilter f) {
    switch (f) {
    case PngFilter::None: return PNG_FILTER_NONE;
    case PngFilter::Sub: return PNG_FILTER_SUB;
    case PngFilter::Adaptive: return PNG_ALL_FILTERS;
    }
    return PNG_ALL_FILTERS;
}

bool pngWriteRows(png_structp png, png_infop info, PngState& s, png_bytepp rows, int width, int height, int channels,
                  int level, int filterMask) {
    if (setjmp(s.jump)) return false;
    png_set_write_fn(png, &s, pngWriteBytes, nullptr);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, level);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, filterMask);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    return true;
}

struct PngHeader {
    int width = 0, height = 0, channels = 0;
};

// Reads the header and sets the expansions to 8-bit grey, grey + alpha, RGB or RGBA.
bool pngReadHeader(png_structp png, png_infop info, PngState& s, PngHeader& h) {
    if (setjmp(s.jump)) return false;
    png_set_read_fn(png, &s, pngReadBytes);
    png_set_user_limits(png, kMaxTileSide, kMaxTileSide);
    png_read_info(png, info);
    const int depth = png_get_bit_depth(png, info);
    const int type = png_get_color_type(png, info);
    if (depth == 16) png_error(png, "16-bit PNG not supported");
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    h.width = int(png_get_image_width(png, info));
    h.height = int(png_get_image_height(png, info));
    h.channels = png_get_channels(png, info);
    if (png_get_rowbytes(png, info) != std::size_t(h.width) * std::size_t(h.channels))
        png_error(png, "unexpected PNG row size");
    return true;
}

bool pngReadRows(png_structp png, png_infop info, PngState& s, png_bytepp rows) {
    if (setjmp(s.jump)) return false;
    png_read_image(png, rows);
    png_read_end(png, info);
    return true;
}

DecodedImage decodePng(std::span<const std::uint8_t> bytes) {
    PngState s;
    s.in = bytes.data();
    s.inSize = bytes.size();
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, pngError, pngIgnoreWarning);
    if (!png) throw std::bad_alloc();
    png_infop info = png_create_info_struct(png);
    struct Guard {
        png_structp& png;
        png_infop& info;
        ~Guard() { png_destroy_read_struct(&png, info ? &info : nullptr, nullptr); }
    } guard{png, info};
    if (!info) throw std::bad_alloc();

    PngHeader h;
    if (!pngReadHeader(png, info, s, h)) throw TileDecodeError(std::string("PNG: ") + s.message);
    DecodedImage image;
    image.width = h.width;
    image.height = h.height;
    image.channels = h.channels;
    image.pixels.resize(std::size_t(h.width) * std::size_t(h.height) * std::size_t(h.channels));
    std::vector<png_bytep> rows(static_cast<std::size_t>(h.height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = image.pixels.data() + y * std::size_t(h.width) * std::size_t(h.channels);
    if (!pngReadRows(png, info, s, rows.data())) throw TileDecodeError(std::string("PNG: ") + s.message);
    return image;
}

// ---- JPEG ----

struct JpegState {
    jpeg_error_mgr manager;  // first: libjpeg hands the callbacks &manager as cinfo->err
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = {};
    unsigned char* buffer = nullptr;  // jpeg_mem_dest's output, malloc'ed by libjpeg
    unsigned long size = 0;
};

[[noreturn]] void jpegErrorExit(j_common_ptr c) {
    auto* s = reinterpret_cast<JpegState*>(c->err);
    (*c->err->format_message)(c, s->message);
    std::longjmp(s->jump, 1);
}

// Warnings (level -1) are what libjpeg says of corrupt or truncated data before it fills the rest
// with grey: errors here. Trace messages (level >= 0) are ignored.
void jpegEmitMessage(j_common_ptr c, int level) {
    if (level < 0) jpegErrorExit(c);
}

void jpegInstallErrors(JpegState& s) {
    jpeg_std_error(&s.manager);
    s.manager.error_exit = jpegErrorExit;
    s.manager.emit_message = jpegEmitMessage;
}

bool jpegCompress(jpeg_compress_struct& c, JpegState& s, JSAMPARRAY rows, int width, int height, int quality) {
    if (setjmp(s.jump)) return false;
    jpeg_create_compress(&c);
    jpeg_mem_dest(&c, &s.buffer, &s.size);
    c.image_width = JDIMENSION(width);
    c.image_height = JDIMENSION(height);
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, quality, TRUE);
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) jpeg_write_scanlines(&c, rows + c.next_scanline, c.image_height - c.next_scanline);
    jpeg_finish_compress(&c);
    return true;
}

std::vector<std::uint8_t> encodeJpeg(std::span<const std::uint8_t> rgb, int width, int height, int quality) {
    std::vector<JSAMPROW> rows(static_cast<std::size_t>(height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<JSAMPROW>(rgb.data() + y * std::size_t(width) * 3);
    JpegState s;
    jpeg_compress_struct c{};
    c.err = &s.manager;
    jpegInstallErrors(s);
    const bool ok = jpegCompress(c, s, rows.data(), width, height, quality);
    jpeg_destroy_compress(&c);
    struct Free {
        unsigned char* p;
        ~Free() { std::free(p); }
    } freeBuffer{s.buffer};
    if (!ok) throw std::runtime_error(std::string("encodeRgb(): libjpeg: ") + s.message);
    return std::vector<std::uint8_t>(s.buffer, s.buffer + s.size);
}

bool jpegReadHeader(jpeg_decompress_struct& c, JpegState& s, std::span<const std::uint8_t> bytes) {
    if (setjmp(s.jump)) return false;
    jpeg_create_decompress(&c);
    jpeg_mem_src(&c, bytes.data(), static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&c, TRUE);
    return true;
}

bool jpegReadRows(jpeg_decompress_struct& c, JpegState& s, JSAMPARRAY rows) {
    if (setjmp(s.jump)) return false;
    jpeg_start_decompress(&c);
    while (c.output_scanline < c.output_height) jpeg_read_scanlines(&c, rows + c.output_scanline, c.output_height - c.output_scanline);
    jpeg_finish_decompress(&c);
    return true;
}

// denom 2: libjpeg's scaled IDCT gives the image at half its size directly (4x4 of each 8x8
// block's coefficients), at a fraction of a full decode's cost.
DecodedImage decodeJpeg(std::span<const std::uint8_t> bytes, unsigned denom = 1) {
    JpegState s;
    jpeg_decompress_struct c{};
    c.err = &s.manager;
    jpegInstallErrors(s);
    struct Guard {
        jpeg_decompress_struct& c;
        ~Guard() { jpeg_destroy_decompress(&c); }
    } guard{c};
    if (!jpegReadHeader(c, s, bytes)) throw TileDecodeError(std::string("JPEG: ") + s.message);
    DecodedImage image;
    switch (c.jpeg_color_space) {
    case JCS_GRAYSCALE: c.out_color_space = JCS_GRAYSCALE; image.channels = 1; break;
    case JCS_YCbCr:
    case JCS_RGB: c.out_color_space = JCS_RGB; image.channels = 3; break;
    default: throw TileDecodeError("JPEG: colour space " + std::to_string(int(c.jpeg_color_space)) + " (CMYK or YCCK) not supported");
    }
    if (c.image_width > JDIMENSION(kMaxTileSide) || c.image_height > JDIMENSION(kMaxTileSide))
        throw TileDecodeError("JPEG: " + std::to_string(c.image_width) + " x " + std::to_string(c.image_height) +
                              " pixels, more than " + std::to_string(kMaxTileSide) + " on a side");
    if (c.image_width % denom != 0 || c.image_height % denom != 0)  // libjpeg would round an odd side up
        throw TileDecodeError(std::to_string(c.image_width) + " x " + std::to_string(c.image_height) +
                              " pixels: not of even size, cannot halve");
    c.scale_num = 1;
    c.scale_denom = denom;
    jpeg_calc_output_dimensions(&c);
    image.width = int(c.output_width);
    image.height = int(c.output_height);
    image.pixels.resize(std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels));
    std::vector<JSAMPROW> rows(static_cast<std::size_t>(image.height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = image.pixels.data() + y * std::size_t(image.width) * std::size_t(image.channels);
    if (!jpegReadRows(c, s, rows.data())) throw TileDecodeError(std::string("JPEG: ") + s.message);
    return image;
}

// ---- WebP ----

const char* webpStatus(VP8StatusCode status) {
    switch (status) {
    case VP8_STATUS_OUT_OF_MEMORY: return "out of memory";
    case VP8_STATUS_INVALID_PARAM: return "invalid parameter";
    case VP8_STATUS_BITSTREAM_ERROR: return "corrupt bitstream";
    case VP8_STATUS_UNSUPPORTED_FEATURE: return "unsupported feature";
    case VP8_STATUS_SUSPENDED: return "suspended";
    case VP8_STATUS_USER_ABORT: return "aborted";
    case VP8_STATUS_NOT_ENOUGH_DATA: return "truncated WebP";
    default: return "unknown error";
    }
}

DecodedImage decodeWebp(std::span<const std::uint8_t> bytes) {
    WebPDecoderConfig config;
    if (!WebPInitDecoderConfig(&config)) throw std::runtime_error("decodeImage(): libwebp version mismatch");
    VP8StatusCode status = WebPGetFeatures(bytes.data(), bytes.size(), &config.input);
    if (status != VP8_STATUS_OK) throw TileDecodeError(std::string("WebP: ") + webpStatus(status));
    if (config.input.has_animation) throw TileDecodeError("WebP: animated WebP not supported");
    DecodedImage image;
    image.width = config.input.width;
    image.height = config.input.height;
    image.channels = config.input.has_alpha ? 4 : 3;
    if (image.width < 1 || image.height < 1 || image.width > kMaxTileSide || image.height > kMaxTileSide)
        throw TileDecodeError("WebP: " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                              " pixels, more than " + std::to_string(kMaxTileSide) + " on a side");
    image.pixels.resize(std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels));
    config.output.colorspace = image.channels == 4 ? MODE_RGBA : MODE_RGB;
    config.output.is_external_memory = 1;
    config.output.u.RGBA.rgba = image.pixels.data();
    config.output.u.RGBA.stride = image.width * image.channels;
    config.output.u.RGBA.size = image.pixels.size();
    status = WebPDecode(bytes.data(), bytes.size(), &config);
    WebPFreeDecBuffer(&config.output);
    if (status != VP8_STATUS_OK) throw TileDecodeError(std::string("WebP: ") + webpStatus(status));
    return image;
}

// ---- signatures ----

constexpr std::array<std::uint8_t, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::array<std::uint8_t, 3> kJpegSignature = {0xff, 0xd8, 0xff};

bool startsWith(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> prefix) {
    return bytes.size() >= prefix.size() && std::equal(prefix.begin(), prefix.end(), bytes.begin());
}

// A blob shorter than a signature that begins it (a tile cut short) is named as truncated.
bool truncatedSignature(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> signature) {
    return !bytes.empty() && bytes.size() < signature.size() && std::equal(bytes.begin(), bytes.end(), signature.begin());
}

bool isWebp(std::span<const std::uint8_t> b) {
    return b.size() >= 12 && std::memcmp(b.data(), "RIFF", 4) == 0 && std::memcmp(b.data() + 8, "WEBP", 4) == 0;
}

}  // namespace

// ---- encoders ----

std::vector<std::uint8_t> encodePng(std::span<const std::uint8_t> pixels, int width, int height, int channels,
                                    int level, PngFilter filter) {
    if (channels != 1 && channels != 3) throw std::invalid_argument("encodePng(): channels must be 1 or 3");
    checkImageArgs("encodePng()", pixels.size(), width, height, channels);
    checkRange("encodePng(): level", level, 0, 9);
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    for (std::size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(pixels.data() + y * std::size_t(width) * std::size_t(channels));
    std::vector<std::uint8_t> out;
    out.reserve(pixels.size() / 2 + 1024);
    PngState s;
    s.out = &out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &s, pngError, pngIgnoreWarning);
    if (!png) throw std::bad_alloc();
    png_infop info = png_create_info_struct(png);
    struct Guard {
        png_structp& png;
        png_infop& info;
        ~Guard() { png_destroy_write_struct(&png, info ? &info : nullptr); }
    } guard{png, info};
    if (!info) throw std::bad_alloc();
    if (!pngWriteRows(png, info, s, rows.data(), width, height, channels, level, pngFilterMask(filter)))
        throw std::runtime_error(std::string("encodePng(): libpng: ") + s.message);
    return out;
}

std::vector<std::uint8_t> encodeWebp(std::span<const std::uint8_t> rgb, int width, int height, int quality, int method) {
    checkImageArgs("encodeWebp()", rgb.size(), width, height, 3);
    checkRange("encodeWebp(): quality", quality, 0, 100);
    checkRange("encodeWebp(): method", method, 0, 6);
    WebPConfig config;
    if (!WebPConfigInit(&config)) throw std::runtime_error("encodeWebp(): libwebp version mismatch");
    config.quality = float(quality);
    config.method = method;
    WebPPicture picture;
    if (!WebPPictureInit(&picture)) throw std::runtime_error("encodeWebp(): libwebp version mismatch");
    WebPMemoryWriter writer;
    WebPMemoryWriterInit(&writer);
    struct Guard {
        WebPPicture& picture;
        WebPMemoryWriter& writer;
        ~Guard() {
            WebPPictureFree(&picture);
            WebPMemoryWriterClear(&writer);
        }
    } guard{picture, writer};
    picture.width = width;
    picture.height = height;
    picture.writer = WebPMemoryWrite;
    picture.custom_ptr = &writer;
    if (!WebPPictureImportRGB(&picture, rgb.data(), width * 3) || !WebPEncode(&config, &picture))
        throw std::runtime_error("encodeWebp(): libwebp error " + std::to_string(int(picture.error_code)));
    return std::vector<std::uint8_t>(writer.mem, writer.mem + writer.size);
}

std::vector<std::uint8_t> encodeRgb(std::span<const std::uint8_t> rgb, int width, int height, const TileEncoding& e) {
    checkImageArgs("encodeRgb()", rgb.size(), width, height, 3);
    switch (e.format) {
    case TileFormat::Png:
        checkRange("TileEncoding::pngLevel", e.pngLevel, 0, 9);
        return encodePng(rgb, width, height, 3, e.pngLevel, kPngFilter);
    case TileFormat::Jpeg:
        checkRange("TileEncoding::jpegQuality", e.jpegQuality, 1, 100);
        return encodeJpeg(rgb, width, height, e.jpegQuality);
    case TileFormat::Webp:
        checkRange("TileEncoding::webpQuality", e.webpQuality, 0, 100);
        return encodeWebp(rgb, width, height, e.webpQuality, kWebpMethod);
    }
    throw std::invalid_argument("encodeRgb(): unknown TileFormat " + std::to_string(int(e.format)));
}

std::vector<std::uint8_t> encodeGreyPng(std::span<const std::uint8_t> grey, int width, int height, int pngLevel) {
    return encodePng(grey, width, height, 1, pngLevel, kPngFilter);
}

// ---- decoders ----

DecodedImage decodeImage(std::span<const std::uint8_t> bytes) {
    static constexpr std::array<std::uint8_t, 4> kRiff = {'R', 'I', 'F', 'F'};
    if (startsWith(bytes, kPngSignature)) return decodePng(bytes);
    if (startsWith(bytes, kJpegSignature)) return decodeJpeg(bytes);
    if (isWebp(bytes)) return decodeWebp(bytes);
    if (truncatedSignature(bytes, kPngSignature)) throw TileDecodeError("truncated PNG");
    if (truncatedSignature(bytes, kJpegSignature)) throw TileDecodeError("truncated JPEG");
    if (startsWith(bytes, kRiff) && bytes.size() < 12) throw TileDecodeError("truncated WebP");
    if (bytes.empty()) throw TileDecodeError("empty tile: not a PNG, JPEG or WebP image");
    throw TileDecodeError("not a PNG, JPEG or WebP image");
}

DecodedImage decodeImageHalf(std::span<const std::uint8_t> bytes) {
    if (startsWith(bytes, kJpegSignature)) {
        return decodeJpeg(bytes, 2);
    }
    const DecodedImage full = decodeImage(bytes);
    if (full.width % 2 != 0 || full.height % 2 != 0)
        throw TileDecodeError(std::to_string(full.width) + " x " + std::to_string(full.height) + " pixels: not of even size, cannot halve");
    DecodedImage half;
    half.width = full.width / 2;
    half.height = full.height / 2;
    half.channels = full.channels;
    const std::size_t ch = std::size_t(full.channels), rowBytes = std::size_t(full.width) * ch;
    half.pixels.resize(std::size_t(half.width) * std::size_t(half.height) * ch);
    for (std::size_t y = 0; y < std::size_t(half.height); ++y) {
        const std::uint8_t* top = full.pixels.data() + 2 * y * rowBytes;
        const std::uint8_t* bottom = top + rowBytes;
        std::uint8_t* out = half.pixels.data() + y * std::size_t(half.width) * ch;
        for (std::size_t x = 0; x < std::size_t(half.width) * ch; ++x) {
            const std::size_t a = (x / ch) * 2 * ch + x % ch;
            out[x] = std::uint8_t((unsigned(top[a]) + top[a + ch] + bottom[a] + bottom[a + ch] + 2) / 4);
        }
    }
    return half;
}

}  // namespace lacet
