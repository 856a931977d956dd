#pragma once
// Four floats processed at once, with GCC's and Clang's vector extensions: SSE2 on x86-64 (its
// baseline), NEON on ARM, the same source everywhere. Each operation is the scalar one, lane by
// lane, in the same order, so a result equals the scalar code's bit for bit (no fused
// multiply-add is contracted on x86-64's baseline).

#include <cmath>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace lacet {

using Float4 = float __attribute__((vector_size(16)));

using Int4 = int __attribute__((vector_size(16)));  // also the lanes' masks of a comparison (-1 true, 0 false)

inline Float4 splat(float v) { return Float4{v, v, v, v}; }
inline Int4 splatInt(int v) { return Int4{v, v, v, v}; }
// std::min(a, b) and std::clamp(v, lo, hi), lane by lane.
inline Float4 min4(Float4 a, Float4 b) { return b < a ? b : a; }
inline Float4 clamp4(Float4 v, Float4 lo, Float4 hi) {
    const Float4 low = v < lo ? lo : v;
    return hi < v ? hi : low;
}

// std::sqrt, lane by lane (correctly rounded, as the scalar one).
inline Float4 sqrt4(Float4 v) {
#if defined(__SSE__)
    return _mm_sqrt_ps(v);
#else
    return Float4{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]), std::sqrt(v[3])};
#endif
}

}  // namespace lacet
