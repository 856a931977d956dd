// Bit-for-bit comparisons of the tests: a value saved and loaded, or made twice, must be the same
// bits (a NaN equals itself, 0.0 and -0.0 differ), which == does not say.
#pragma once

#include <bit>
#include <cstdint>

#include "model/types.h"

namespace lacet {

inline bool sameBits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
inline bool sameBits(float a, float b) { return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b); }
inline bool sameBits(Vec2 a, Vec2 b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y); }
inline bool sameBits(const Box& a, const Box& b) { return sameBits(a.min, b.min) && sameBits(a.max, b.max); }

}  // namespace lacet
