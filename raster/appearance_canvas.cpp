#include "raster/appearance_canvas.h"

#include <algorithm>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace lacet::appearance {
namespace {

std::uint8_t quantize(float c) { return std::uint8_t(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

}  // namespace

void resolve(const Canvas& canvas, const Scratch& s, const AppearanceTile& t, std::vector<std::uint8_t>& out) {
    const int n = t.samples, side = canvas.side();
    out.resize(std::size_t(t.stride) * std::size_t(t.stride) * 4);
    if (n == 1) {  // one sample per texel: a conversion (the common case, and a hot loop)
        const std::size_t count = std::size_t(t.stride) * std::size_t(t.stride);
        static_assert(sizeof(Rgbm) == 4 * sizeof(float), "the canvas is read as packed floats");
        const float* c = &s.colour[0][0];
        std::uint8_t* o = out.data();
        std::size_t k = 0;
#if defined(__SSE2__)
        // quantize() four texels at a time: the same clamp, scale, offset and truncation.
        const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), scale = _mm_set1_ps(255.0f), half = _mm_set1_ps(0.5f);
        for (; k + 16 <= 4 * count; k += 16) {
            __m128i q[4];
            for (int i = 0; i < 4; ++i) {
                const __m128 v = _mm_min_ps(_mm_max_ps(_mm_loadu_ps(c + k + 4 * std::size_t(i)), zero), one);
                q[i] = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(v, scale), half));
            }
            const __m128i bytes = _mm_packus_epi16(_mm_packs_epi32(q[0], q[1]), _mm_packs_epi32(q[2], q[3]));
            _mm_storeu_si128(reinterpret_cast<__m128i*>(o + k), bytes);
        }
#endif
        for (; k < 4 * count; ++k) o[k] = quantize(c[k]);
        return;
    }
    const float norm = 1.0f / float(n * n);
    for (int j = 0; j < t.stride; ++j)
        for (int i = 0; i < t.stride; ++i) {
            Rgbm sum(0.0f);
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) sum += s.colour[std::size_t(j * n + b) * std::size_t(side) + std::size_t(i * n + a)];
            sum *= norm;
            std::uint8_t* o = &out[4 * (std::size_t(j) * std::size_t(t.stride) + std::size_t(i))];
            for (int c = 0; c < 4; ++c) o[c] = quantize(sum[c]);
        }
}

Scratch& threadScratch() {
    thread_local Scratch scratch;
    return scratch;
}

}  // namespace lacet::appearance
