#pragma once
// Little-endian packing of integers and IEEE floats into byte strings (the BLOB columns of the scene
// file), independent of the host's byte order.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace lacet {

class ByteWriter {
public:
    void u8(std::uint8_t v) { bytes_.push_back(v); }
    void u32(std::uint32_t v) {
        for (int k = 0; k < 4; ++k) bytes_.push_back(std::uint8_t(v >> (8 * k)));
    }
    void u64(std::uint64_t v) {
        for (int k = 0; k < 8; ++k) bytes_.push_back(std::uint8_t(v >> (8 * k)));
    }
    void f32(float v) { u32(std::bit_cast<std::uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void clear() { bytes_.clear(); }
    std::span<const std::uint8_t> bytes() const { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
};

// Reads a blob; every read checks the remaining length (false when short).
class ByteReader {
public:
    explicit ByteReader(std::span<const std::uint8_t> b) : b_(b) {}
    std::size_t remaining() const { return b_.size() - pos_; }
    bool u8(std::uint8_t& v) {
        if (remaining() < 1) return false;
        v = b_[pos_++];
        return true;
    }
    bool u32(std::uint32_t& v) {
        if (remaining() < 4) return false;
        v = 0;
        for (int k = 0; k < 4; ++k) v |= std::uint32_t(b_[pos_++]) << (8 * k);
        return true;
    }
    bool u64(std::uint64_t& v) {
        if (remaining() < 8) return false;
        v = 0;
        for (int k = 0; k < 8; ++k) v |= std::uint64_t(b_[pos_++]) << (8 * k);
        return true;
    }
    bool f32(float& v) {
        std::uint32_t u;
        if (!u32(u)) return false;
        v = std::bit_cast<float>(u);
        return true;
    }
    bool f64(double& v) {
        std::uint64_t u;
        if (!u64(u)) return false;
        v = std::bit_cast<double>(u);
        return true;
    }

private:
    std::span<const std::uint8_t> b_;
    std::size_t pos_ = 0;
};

}  // namespace lacet
