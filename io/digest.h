#pragma once
// A 64-bit digest of values fed to it in order: xxHash64-style rounds over 64-bit words, then a
// final avalanche. Doubles and floats count by their bits (-0.0 differs from 0.0, NaN payloads
// count). The same values give the same digest on any host. Not cryptographic: it detects damage
// and change, not tampering. The scene file's checksum (io/scene_checksum.h) and the pyramid's
// quad digests (pyramid/quad_digest.h) are made with it.

#include <bit>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "model/types.h"

namespace lacet {

class Digest {
public:
    Digest& word(std::uint64_t w) {
        w *= 0xC2B2AE3D27D4EB4FULL;
        w = std::rotl(w, 31) * 0x9E3779B185EBCA87ULL;
        h_ = std::rotl(h_ ^ w, 27) * 0x9E3779B185EBCA87ULL + 0x85EBCA77C2B2AE63ULL;
        return *this;
    }
    Digest& real(double v) { return word(std::bit_cast<std::uint64_t>(v)); }
    Digest& real(float v) { return word(std::bit_cast<std::uint32_t>(v)); }
    Digest& text(std::string_view t) {
        word(t.size());
        std::uint64_t w = 0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            w |= std::uint64_t(static_cast<unsigned char>(t[k])) << (8 * (k % 8));
            if (k % 8 == 7 || k + 1 == t.size()) {
                word(w);
                w = 0;
            }
        }
        return *this;
    }
    Digest& reals(std::span<const float> v) {
        word(v.size());
        for (float x : v) real(x);
        return *this;
    }
    Digest& reals(std::span<const double> v) {
        word(v.size());
        for (double x : v) real(x);
        return *this;
    }
    Digest& ids(const std::vector<ElementId>& v) {
        word(v.size());
        for (ElementId id : v) word(id);
        return *this;
    }
    std::uint64_t value() const {
        std::uint64_t h = h_;
        h ^= h >> 33;
        h *= 0xC2B2AE3D27D4EB4FULL;
        h ^= h >> 29;
        return h;
    }

private:
    std::uint64_t h_ = 0x27D4EB2F165667C5ULL;
};

}  // namespace lacet
