// The float TIFF tiles of a GeoPackage gridded coverage (io/tile_codec.h: encodeFloatTiff,
// decodeFloatTiff): written by hand in the one layout the encoding needs, read with every offset
// checked, in either byte order, from strips or tiles, uncompressed, deflate or LZW.
#include "io/tile_codec.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

#include "io/tile_codec_args.h"

namespace lacet {
namespace {

// ---- TIFF ----

constexpr std::uint16_t kTagWidth = 256, kTagHeight = 257, kTagBitsPerSample = 258, kTagCompression = 259,
                        kTagPhotometric = 262, kTagStripOffsets = 273, kTagSamplesPerPixel = 277,
                        kTagRowsPerStrip = 278, kTagStripByteCounts = 279, kTagPlanarConfig = 284, kTagPredictor = 317,
                        kTagTileWidth = 322, kTagTileLength = 323, kTagTileOffsets = 324, kTagTileByteCounts = 325,
                        kTagSampleFormat = 339;
constexpr std::uint16_t kTypeByte = 1, kTypeShort = 3, kTypeLong = 4;

[[noreturn]] void tiffFail(const std::string& reason) { throw TileDecodeError("TIFF: " + reason); }

// Bounds-checked reads of a TIFF blob in its byte order.
class TiffBytes {
public:
    TiffBytes(std::span<const std::uint8_t> b, bool bigEndian) : b_(b), big_(bigEndian) {}
    std::size_t size() const { return b_.size(); }
    bool bigEndian() const { return big_; }
    void need(std::uint64_t offset, std::uint64_t length, const char* what) const {
        if (offset > b_.size() || length > b_.size() - offset)
            tiffFail(std::string("truncated (") + what + " at byte " + std::to_string(offset) + ", " +
                     std::to_string(length) + " bytes, beyond the end at " + std::to_string(b_.size()) + ")");
    }
    std::uint32_t read(std::uint64_t offset, int bytes, const char* what) const {
        need(offset, std::uint64_t(bytes), what);
        std::uint32_t v = 0;
        for (int k = 0; k < bytes; ++k) {
            const std::uint32_t byte = b_[std::size_t(offset) + std::size_t(k)];
            v |= byte << (8 * (big_ ? bytes - 1 - k : k));
        }
        return v;
    }
    std::span<const std::uint8_t> span(std::uint64_t offset, std::uint64_t length, const char* what) const {
        need(offset, length, what);
        return b_.subspan(std::size_t(offset), std::size_t(length));
    }

private:
    std::span<const std::uint8_t> b_;
    bool big_;
};

struct TiffEntry {
    std::uint16_t type = 0;
    std::uint32_t count = 0;
    std::uint64_t at = 0;  // offset of the entry in the blob
};

class TiffIfd {
public:
    TiffIfd(const TiffBytes& b, std::uint64_t offset) : b_(b) {
        const std::uint32_t n = b.read(offset, 2, "IFD");
        b.need(offset + 2, std::uint64_t(n) * 12, "IFD entries");
        for (std::uint32_t i = 0; i < n; ++i) {
            const std::uint64_t at = offset + 2 + std::uint64_t(i) * 12;
            const auto tag = std::uint16_t(b.read(at, 2, "IFD entry"));
            entries_.push_back({tag, {std::uint16_t(b.read(at + 2, 2, "IFD entry")), b.read(at + 4, 4, "IFD entry"), at}});
        }
    }
    bool has(std::uint16_t tag) const { return find(tag) != nullptr; }
    // The integer values of a tag (BYTE, SHORT or LONG), at least `minCount` and at most `maxCount` read.
    std::vector<std::uint32_t> ints(std::uint16_t tag, std::uint64_t minCount, std::uint64_t maxCount) const {
        const TiffEntry* e = find(tag);
        if (!e) tiffFail("tag " + std::to_string(tag) + " missing");
        const int size = e->type == kTypeByte ? 1 : e->type == kTypeShort ? 2 : e->type == kTypeLong ? 4 : 0;
        if (size == 0) tiffFail("tag " + std::to_string(tag) + " has type " + std::to_string(e->type) + ", not an integer");
        if (e->count < minCount) tiffFail("tag " + std::to_string(tag) + " has " + std::to_string(e->count) + " values, " + std::to_string(minCount) + " expected");
        const std::uint64_t total = std::uint64_t(e->count) * std::uint64_t(size);
        const std::uint64_t values = total <= 4 ? e->at + 8 : b_.read(e->at + 8, 4, "IFD entry");
        const std::uint64_t n = std::min<std::uint64_t>(e->count, maxCount);
        b_.need(values, n * std::uint64_t(size), "tag values");
        std::vector<std::uint32_t> out(static_cast<std::size_t>(n));
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = b_.read(values + i * std::uint64_t(size), size, "tag values");
        return out;
    }
    std::uint32_t value(std::uint16_t tag, std::uint32_t fallback) const { return has(tag) ? ints(tag, 1, 1)[0] : fallback; }

private:
    const TiffEntry* find(std::uint16_t tag) const {
        for (const auto& [t, e] : entries_)
            if (t == tag) return &e;
        return nullptr;
    }
    const TiffBytes& b_;
    std::vector<std::pair<std::uint16_t, TiffEntry>> entries_;
};

void inflateBlock(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) {
    z_stream z{};
    if (inflateInit(&z) != Z_OK) throw std::bad_alloc();
    z.next_in = const_cast<Bytef*>(in.data());
    z.avail_in = uInt(in.size());
    z.next_out = out.data();
    z.avail_out = uInt(out.size());
    const int r = inflate(&z, Z_FINISH);
    inflateEnd(&z);
    if (z.avail_out != 0 || (r != Z_STREAM_END && r != Z_OK && r != Z_BUF_ERROR))
        tiffFail("corrupt or truncated deflate data");
}

// TIFF's LZW (TIFF 6.0 section 13): codes of 9 to 12 bits, most significant bit first, 256 clears
// the table, 257 ends; the code width grows one code early (at 511, 1023 and 2047 entries), as libtiff
// writes it.
void lzwBlock(std::span<const std::uint8_t> in, std::span<std::uint8_t> out) {
    constexpr int kClear = 256, kEnd = 257, kFirst = 258, kTableSize = 4096, kMaxWidth = 12;
    if (in.size() >= 2 && in[0] == 0 && (in[1] & 1)) tiffFail("old-style LZW not supported");
    std::vector<std::uint16_t> prefix(kTableSize), length(kTableSize);
    std::vector<std::uint8_t> suffix(kTableSize), first(kTableSize);
    for (int i = 0; i < 256; ++i) {
        length[std::size_t(i)] = 1;
        suffix[std::size_t(i)] = first[std::size_t(i)] = std::uint8_t(i);
    }
    std::uint64_t bit = 0;
    const std::uint64_t bits = std::uint64_t(in.size()) * 8;
    auto readCode = [&](int width) {
        if (bit + std::uint64_t(width) > bits) return -1;
        int code = 0;
        for (int k = 0; k < width; ++k, ++bit) code = (code << 1) | ((in[std::size_t(bit >> 3)] >> (7 - (bit & 7))) & 1);
        return code;
    };
    std::size_t o = 0;
    int width = 9, next = kFirst, previous = -1;
    while (o < out.size()) {
        const int code = readCode(width);
        if (code < 0 || code == kEnd) break;
        if (code == kClear) {
            width = 9;
            next = kFirst;
            previous = -1;
            continue;
        }
        if (previous < 0) {
            if (code > 255) tiffFail("corrupt LZW data (code " + std::to_string(code) + " after a clear)");
        } else {
            if (code > next || (code == next && next >= kTableSize)) tiffFail("corrupt LZW data (code " + std::to_string(code) + ")");
            if (next < kTableSize) {
                const auto p = std::size_t(previous), n = std::size_t(next);
                prefix[n] = std::uint16_t(previous);
                suffix[n] = code < next ? first[std::size_t(code)] : first[p];
                first[n] = first[p];
                length[n] = std::uint16_t(length[p] + 1);
                ++next;
                if (next == (1 << width) - 1 && width < kMaxWidth) ++width;
            }
        }
        const std::size_t len = length[std::size_t(code)];
        std::size_t c = std::size_t(code);
        for (std::size_t k = len; k-- > 0;) {
            if (o + k < out.size()) out[o + k] = suffix[c];
            c = prefix[c];
        }
        o = std::min(o + len, out.size());
        previous = code;
    }
    if (o < out.size()) tiffFail("truncated or corrupt LZW data");
}

}  // namespace

namespace {

// The one-strip TIFF of a float32 band whose strip holds `data` (already compressed when
// `compression` is not 1), with a Predictor tag unless `predictor` is 1.
std::vector<std::uint8_t> floatTiff(std::span<const std::uint8_t> data, int width, int height, std::uint16_t compression,
                                    std::uint16_t predictor) {
    // Header, one IFD of `entries`, then the strip at a 4-byte boundary.
    const std::uint32_t entries = predictor == 1 ? 11 : 12, kIfd = 8, dataAt = (kIfd + 2 + entries * 12 + 4 + 3) / 4 * 4;
    const auto dataBytes = std::uint32_t(data.size());
    std::vector<std::uint8_t> out;
    out.reserve(dataAt + dataBytes);
    auto u16 = [&](std::uint32_t v) {
        out.push_back(std::uint8_t(v));
        out.push_back(std::uint8_t(v >> 8));
    };
    auto u32 = [&](std::uint32_t v) {
        u16(v & 0xffff);
        u16(v >> 16);
    };
    auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t value) {
        u16(tag);
        u16(type);
        u32(1);
        if (type == kTypeShort) {
            u16(value);
            u16(0);
        } else {
            u32(value);
        }
    };
    out.push_back('I');
    out.push_back('I');
    u16(42);
    u32(kIfd);
    u16(entries);
    entry(kTagWidth, kTypeLong, std::uint32_t(width));
    entry(kTagHeight, kTypeLong, std::uint32_t(height));
    entry(kTagBitsPerSample, kTypeShort, 32);
    entry(kTagCompression, kTypeShort, compression);
    entry(kTagPhotometric, kTypeShort, 1);  // BlackIsZero
    entry(kTagStripOffsets, kTypeLong, dataAt);
    entry(kTagSamplesPerPixel, kTypeShort, 1);
    entry(kTagRowsPerStrip, kTypeLong, std::uint32_t(height));
    entry(kTagStripByteCounts, kTypeLong, dataBytes);
    entry(kTagPlanarConfig, kTypeShort, 1);
    if (predictor != 1) entry(kTagPredictor, kTypeShort, predictor);
    entry(kTagSampleFormat, kTypeShort, 3);  // IEEE floating point
    u32(0);                                  // no next IFD
    out.resize(dataAt, 0);
    out.insert(out.end(), data.begin(), data.end());
    return out;
}

}  // namespace

std::vector<std::uint8_t> encodeFloatTiff(std::span<const float> values, int width, int height) {
    checkImageArgs("encodeFloatTiff()", values.size(), width, height, 1);
    std::vector<std::uint8_t> data;
    data.reserve(values.size() * 4);
    for (float v : values) {
        const std::uint32_t b = std::bit_cast<std::uint32_t>(v);
        for (int k = 0; k < 4; ++k) data.push_back(std::uint8_t(b >> (8 * k)));
    }
    return floatTiff(data, width, height, 1, 1);
}

std::vector<std::uint8_t> encodeFloatTiffDeflate(std::span<const float> values, int width, int height, int level,
                                                 bool floatPredictor) {
    checkImageArgs("encodeFloatTiffDeflate()", values.size(), width, height, 1);
    if (level < 1 || level > 9)
        throw std::invalid_argument("encodeFloatTiffDeflate(): zlib level " + std::to_string(level) + " not in 1..9");
    const std::size_t w = std::size_t(width), rowBytes = w * 4;
    std::vector<std::uint8_t> raw(values.size() * 4);
    for (std::size_t y = 0; y < std::size_t(height); ++y) {
        std::uint8_t* r = raw.data() + y * rowBytes;
        const float* v = values.data() + y * w;
        if (floatPredictor) {
            // TIFF's floating point predictor (Adobe technical note 3): the row's bytes as planes, most
            // significant first, then each byte minus the one before it.
            for (std::size_t i = 0; i < w; ++i) {
                const std::uint32_t b = std::bit_cast<std::uint32_t>(v[i]);
                for (std::size_t k = 0; k < 4; ++k) r[k * w + i] = std::uint8_t(b >> (8 * (3 - k)));
            }
            for (std::size_t i = rowBytes; i-- > 1;) r[i] = std::uint8_t(r[i] - r[i - 1]);
        } else {
            for (std::size_t i = 0; i < w; ++i) {
                const std::uint32_t b = std::bit_cast<std::uint32_t>(v[i]);
                for (std::size_t k = 0; k < 4; ++k) r[4 * i + k] = std::uint8_t(b >> (8 * k));
            }
        }
    }
    uLongf packedSize = compressBound(uLong(raw.size()));
    std::vector<std::uint8_t> packed(packedSize);
    if (compress2(packed.data(), &packedSize, raw.data(), uLong(raw.size()), level) != Z_OK) throw std::bad_alloc();
    packed.resize(packedSize);
    return floatTiff(packed, width, height, 8, floatPredictor ? 3 : 1);
}

DecodedFloats decodeFloatTiff(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < 8) tiffFail("truncated (" + std::to_string(bytes.size()) + " bytes, no header)");
    const bool big = bytes[0] == 'M' && bytes[1] == 'M';
    if (!big && !(bytes[0] == 'I' && bytes[1] == 'I')) throw TileDecodeError("not a TIFF file");
    const TiffBytes b(bytes, big);
    const std::uint32_t magic = b.read(2, 2, "header");
    if (magic == 43) tiffFail("BigTIFF not supported");
    if (magic != 42) throw TileDecodeError("not a TIFF file");
    const TiffIfd ifd(b, b.read(4, 4, "header"));

    const std::uint32_t width = ifd.ints(kTagWidth, 1, 1)[0], height = ifd.ints(kTagHeight, 1, 1)[0];
    if (width < 1 || height < 1 || width > std::uint32_t(kMaxTileSide) || height > std::uint32_t(kMaxTileSide))
        tiffFail(std::to_string(width) + " x " + std::to_string(height) + " pixels, not in 1.." + std::to_string(kMaxTileSide));
    if (ifd.value(kTagSamplesPerPixel, 1) != 1) tiffFail(std::to_string(ifd.value(kTagSamplesPerPixel, 1)) + " samples per pixel, 1 expected");
    for (std::uint32_t bits : ifd.ints(kTagBitsPerSample, 1, 1))
        if (bits != 32) tiffFail(std::to_string(bits) + " bits per sample, 32 expected");
    const std::uint32_t format = ifd.value(kTagSampleFormat, 1);
    if (format != 3) tiffFail("sample format " + std::to_string(format) + ", 3 (IEEE floating point) expected");
    const std::uint32_t compression = ifd.value(kTagCompression, 1);
    if (compression != 1 && compression != 5 && compression != 8 && compression != 32946)
        throw TileDecodeError("TIFF compression " + std::to_string(compression) + " not supported");
    const std::uint32_t predictor = compression == 1 ? 1 : ifd.value(kTagPredictor, 1);
    if (predictor < 1 || predictor > 3) tiffFail("predictor " + std::to_string(predictor) + " not supported");

    // Blocks: tiles, or strips as tiles as wide as the image (the last one may be shorter).
    const bool tiled = ifd.has(kTagTileWidth);
    std::uint32_t blockWidth = width, blockHeight = height;
    if (tiled) {
        blockWidth = ifd.ints(kTagTileWidth, 1, 1)[0];
        blockHeight = ifd.ints(kTagTileLength, 1, 1)[0];
        if (blockWidth < 1 || blockHeight < 1 || blockWidth > std::uint32_t(kMaxTileSide) || blockHeight > std::uint32_t(kMaxTileSide))
            tiffFail("tile of " + std::to_string(blockWidth) + " x " + std::to_string(blockHeight) + " pixels");
    } else {
        blockHeight = std::clamp<std::uint32_t>(ifd.value(kTagRowsPerStrip, height), 1, height);
    }
    const std::uint32_t across = (width + blockWidth - 1) / blockWidth, down = (height + blockHeight - 1) / blockHeight;
    const std::uint64_t blocks = std::uint64_t(across) * down;
    const auto offsets = ifd.ints(tiled ? kTagTileOffsets : kTagStripOffsets, blocks, blocks);
    const auto counts = ifd.ints(tiled ? kTagTileByteCounts : kTagStripByteCounts, blocks, blocks);

    DecodedFloats out;
    out.width = int(width);
    out.height = int(height);
    out.values.resize(std::size_t(width) * height);
    std::vector<std::uint8_t> block;
    std::vector<std::uint32_t> row(blockWidth);
    const std::size_t rowBytes = std::size_t(blockWidth) * 4;
    for (std::uint32_t by = 0; by < down; ++by)
        for (std::uint32_t bx = 0; bx < across; ++bx) {
            const std::size_t k = std::size_t(by) * across + bx;
            const std::uint32_t rows = tiled ? blockHeight : std::min(blockHeight, height - by * blockHeight);
            block.resize(rowBytes * rows);
            const auto data = b.span(offsets[k], counts[k], tiled ? "tile" : "strip");
            if (compression == 1) {
                if (data.size() < block.size()) tiffFail("truncated (block " + std::to_string(k) + " holds " + std::to_string(data.size()) + " bytes, " + std::to_string(block.size()) + " expected)");
                std::copy_n(data.begin(), block.size(), block.begin());
            } else if (compression == 5) {
                lzwBlock(data, block);
            } else {
                inflateBlock(data, block);
            }
            for (std::uint32_t y = 0; y < rows; ++y) {
                const std::uint8_t* r = block.data() + y * rowBytes;
                if (predictor == 3) {
                    // Floating point predictor: bytes differenced along the row, then the row holds
                    // the most significant bytes of every sample first, independent of the byte order.
                    std::uint8_t* w = block.data() + y * rowBytes;
                    for (std::size_t i = 1; i < rowBytes; ++i) w[i] = std::uint8_t(w[i] + w[i - 1]);
                    for (std::size_t i = 0; i < blockWidth; ++i)
                        row[i] = std::uint32_t(r[i]) << 24 | std::uint32_t(r[blockWidth + i]) << 16 |
                                 std::uint32_t(r[2 * blockWidth + i]) << 8 | std::uint32_t(r[3 * blockWidth + i]);
                } else {
                    for (std::size_t i = 0; i < blockWidth; ++i) {
                        const std::uint8_t* s = r + 4 * i;
                        row[i] = big ? std::uint32_t(s[0]) << 24 | std::uint32_t(s[1]) << 16 | std::uint32_t(s[2]) << 8 | s[3]
                                     : std::uint32_t(s[3]) << 24 | std::uint32_t(s[2]) << 16 | std::uint32_t(s[1]) << 8 | s[0];
                    }
                    if (predictor == 2)
                        for (std::size_t i = 1; i < blockWidth; ++i) row[i] += row[i - 1];
                }
                const std::uint32_t y0 = by * blockHeight + y, x0 = bx * blockWidth;
                if (y0 >= height) break;
                const std::uint32_t n = std::min(blockWidth, width - x0);
                float* dst = out.values.data() + std::size_t(y0) * width + x0;
                for (std::uint32_t i = 0; i < n; ++i) dst[i] = std::bit_cast<float>(row[i]);
            }
        }
    return out;
}

}  // namespace lacet
