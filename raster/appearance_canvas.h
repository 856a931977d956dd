#pragma once
// Internal to the appearance producer (raster/appearance_producer.cpp): the canvas a tile is
// drawn on (supersampled, border included), its per-thread buffers, and the resolve to texels.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "raster/appearance_segments.h"
#include "raster/appearance_shading.h"
#include "raster/appearance_tile.h"
#include "raster/area_triangulation.h"
#include "raster/float4.h"
#include "raster/rasterizer.h"
#include "raster/segment4.h"

namespace lacet::appearance {

constexpr float kInf = std::numeric_limits<float>::infinity();

inline bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
constexpr std::uint8_t kTouched = 1, kInside = 2, kCap = 4;  // kCap: nearest to a curve's end node, beyond it

// Per-thread buffers of one tile, on the supersampled canvas. Every drawing pass leaves dist
// infinite and flags 0 where it set them (clearTouched, drawArea's rectangle), so a tile that
// was drawn to the end leaves them `clean` for the next one; after an exception they are reset.
// A pixel of a road's markings found as its surface was drawn (appearance_curves.h:
// drawRoadSurface), blended once every road of the layer is down: its index and coverage.
struct MarkingTexel {
    std::uint32_t k = 0;
    float alpha = 0.0f;
};

struct Scratch {
    std::vector<Rgbm> colour;
    // The markings of a layer's roads (raster/appearance_producer.cpp).
    std::vector<MarkingTexel> marks;
    std::vector<float> dist, v, u;  // per element: distance to its border or axis, signed v, u
    std::vector<std::uint8_t> flags;
    std::vector<std::uint32_t> touched;
    // A block's candidate segments, and the same in the block's frame (appearance_curves.cpp).
    std::vector<const Segment*> candidates;
    std::vector<LocalSegment> local;
    bool clean = false;
    void reset(std::size_t n) {
        colour.resize(n);
        if (!clean || dist.size() != n) {
            dist.assign(n, kInf);
            flags.assign(n, 0);
        }
        clean = false;
        v.resize(n);
        u.resize(n);
        touched.clear();
    }
};

// c = c (1 - a) + src a, the four channels at once.
inline void blend(Rgbm& c, const Rgbm& src, float a) {
    static_assert(sizeof(Rgbm) == sizeof(Float4));
    Float4 dst, s;
    std::memcpy(&dst, &c, sizeof dst);
    std::memcpy(&s, &src, sizeof s);
    dst = dst * (1.0f - a) + s * a;
    std::memcpy(&c, &dst, sizeof dst);
}

class Canvas {
public:
    Canvas(const AppearanceTile& t, Scratch& s)
        : t_(t), s_(s), side_(t.stride * t.samples), pixel_(t.delta / double(t.samples)) {
        s_.reset(std::size_t(side_) * std::size_t(side_));
    }

    int side() const { return side_; }
    // What the canvas covers (the tile and its border), metres.
    Box box() const { return t_.bounds.dilated(double(t_.border) * t_.delta); }
    double pixelSize() const { return pixel_; }  // metres
    Scratch& scratch() { return s_; }
    Vec2 world(int x, int y) const {
        return t_.bounds.min + ((Vec2(double(x), double(y)) + 0.5) / double(t_.samples) - double(t_.border)) * t_.delta;
    }
    glm::dvec2 pixel(Vec2 p) const { return ((p - t_.bounds.min) / t_.delta + double(t_.border)) * double(t_.samples); }
    // The pixels [x0, x1) x [y0, y1) of the canvas within `slack` pixels of the box lo..hi
    // (finite, lo <= hi; metres).
    struct Rect {
        int x0, y0, x1, y1;
    };
    Rect around(Vec2 lo, Vec2 hi, double slack) const {
        const glm::dvec2 a = pixel(lo) - slack, b = pixel(hi) + slack;
        auto clamped = [&](double v) { return int(std::clamp(v, 0.0, double(side_))); };
        return {clamped(std::floor(a.x)), clamped(std::floor(a.y)), clamped(std::ceil(b.x)), clamped(std::ceil(b.y))};
    }

    template <class F>
    void triangle(const Triangle& tri, F&& f) {
        RasterVertex v[3];
        for (int i = 0; i < 3; ++i) v[i].p = pixel(tri[std::size_t(i)]);
        const std::size_t side = std::size_t(side_);  // a local: f's stores must not make it reload
        rasterizeTriangle(v[0], v[1], v[2], 0, side_, side_,
                          [&f, side](int x, int y, const float*) { f(std::size_t(y) * side + std::size_t(x), x, y); });
    }

    void touch(std::size_t k) {
        if (!(s_.flags[k] & kTouched)) {
            s_.flags[k] |= kTouched;
            s_.touched.push_back(std::uint32_t(k));
        }
    }
    void clearTouched() {
        for (std::uint32_t k : s_.touched) {
            s_.dist[k] = kInf;
            s_.flags[k] = 0;
        }
        s_.touched.clear();
    }
    void over(std::size_t k, glm::vec3 rgb, float mask, float alpha) {
        if (alpha > 0.0f) blend(s_.colour[k], Rgbm(rgb, mask), alpha);
    }

private:
    const AppearanceTile& t_;
    Scratch& s_;
    int side_;
    double pixel_;
};

// Box-filters the canvas down to the tile's texels (RGBM, 8 bits a channel).
void resolve(const Canvas& canvas, const Scratch& s, const AppearanceTile& t, std::vector<std::uint8_t>& out);
// This thread's buffers.
Scratch& threadScratch();

}  // namespace lacet::appearance
