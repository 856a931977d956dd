#include "raster/appearance_producer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <glm/geometric.hpp>

#include "model/junctions.h"
#include "raster/appearance_shading.h"
#include "raster/area_triangulation.h"
#include "raster/float4.h"
#include "raster/rasterizer.h"

namespace lacet {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

bool finite(Vec2 p) { return std::isfinite(p.x) && std::isfinite(p.y); }
constexpr std::uint8_t kTouched = 1, kInside = 2, kCap = 4;  // kCap: nearest to a curve's end node, beyond it

// Per-thread buffers of one tile, on the supersampled canvas. Every drawing pass leaves dist
// infinite and flags 0 where it set them (clearTouched, drawArea's rectangle), so a tile that
// was drawn to the end leaves them `clean` for the next one; after an exception they are reset.
struct Scratch {
    std::vector<Rgbm> colour;
    std::vector<float> dist, v, u;  // per element: distance to its border or axis, signed v, u
    std::vector<std::uint8_t> flags;
    std::vector<std::uint32_t> touched;
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

// --- Ground ------------------------------------------------------------------------------------

void drawGround(Canvas& canvas, const AppearanceTile& t, const Dem& dem, int cells) {
    const double cell = t.bounds.size().x / double(cells);
    // Nodes -1 .. cells + 1 cover the border texels (border * delta < one cell).
    const int nodes = cells + 3;
    std::vector<glm::vec3> grid(std::size_t(nodes) * std::size_t(nodes));
    for (int j = 0; j < nodes; ++j)
        for (int i = 0; i < nodes; ++i) {
            const Vec2 p = t.bounds.min + Vec2(double(i - 1), double(j - 1)) * cell;
            Vec2 gradient;
            const double z = dem.sampleAndGradient(p, gradient);
            grid[std::size_t(j) * std::size_t(nodes) + std::size_t(i)] = groundColour(z, glm::length(gradient));
        }
    const int side = canvas.side();
    std::vector<int> i0(std::size_t(side), 0);
    std::vector<float> fx(std::size_t(side), 0.0f);
    for (int x = 0; x < side; ++x) {
        const double g = std::clamp((canvas.world(x, 0).x - t.bounds.min.x) / cell + 1.0, 0.0, double(nodes - 1) - 1e-9);
        i0[std::size_t(x)] = int(g);
        fx[std::size_t(x)] = float(g - std::floor(g));
    }
    // Runs of texels between the same two nodes along x (i0 does not decrease).
    struct Run {
        std::size_t node;
        int begin, end;
    };
    std::vector<Run> runs;
    for (int x = 0; x < side; ++x)
        if (runs.empty() || runs.back().node != std::size_t(i0[std::size_t(x)])) runs.push_back({std::size_t(i0[std::size_t(x)]), x, x + 1});
        else runs.back().end = x + 1;
    Scratch& s = canvas.scratch();
    std::vector<glm::vec3> row(static_cast<std::size_t>(nodes));
    for (int y = 0; y < side; ++y) {
        const double g = std::clamp((canvas.world(0, y).y - t.bounds.min.y) / cell + 1.0, 0.0, double(nodes - 1) - 1e-9);
        const int j0 = int(g);
        const float fy = float(g - std::floor(g));
        // The row of nodes at this y first, then along x: bilinear, one lerp per texel.
        const glm::vec3* r0 = &grid[std::size_t(j0) * std::size_t(nodes)];
        const glm::vec3* r1 = r0 + nodes;
        for (int i = 0; i < nodes; ++i) row[std::size_t(i)] = r0[i] + (r1[i] - r0[i]) * fy;
        Rgbm* out = &s.colour[std::size_t(y) * std::size_t(side)];
        for (const Run& run : runs) {
            const glm::vec3 a = row[run.node], d = row[run.node + 1] - row[run.node];
            const Float4 a4{a.r, a.g, a.b, 0.0f}, d4{d.r, d.g, d.b, 0.0f};  // the three channels at once
            for (int x = run.begin; x < run.end; ++x) {
                const Float4 c = a4 + d4 * fx[std::size_t(x)];
                std::memcpy(&out[x], &c, sizeof c);
            }
        }
    }
}

// --- Curves ------------------------------------------------------------------------------------

struct Segment {
    Vec2 p0, p1;
    double u0 = 0.0, u1 = 0.0;
    bool startCap = false, endCap = false;  // p0 (p1) is the ancestor's start (end) node
};

std::vector<Segment> segmentsOf(const std::vector<ClippedCurve>& pieces, const CurveDataCache* data, LayerId l, ElementId a) {
    std::vector<Segment> out;
    for (const ClippedCurve& run : pieces) {
        Vec2 prev{};
        double prevU = 0.0;
        std::size_t k = 0;
        const std::size_t first = out.size();
        for (const Vertex& vx : run.vertices) {
            if (!vx.onCurve) continue;
            const double u = data ? data->u(l, a, run.s[k]) : 0.0;
            if (k > 0) out.push_back({prev, vx.p, prevU, u});
            prev = vx.p;
            prevU = u;
            ++k;
        }
        if (out.size() > first) {
            out[first].startCap = run.startsAtNode;
            out.back().endCap = run.endsAtNode;
        }
    }
    return out;
}

double segmentDistance(const Segment& sg, Vec2 q) {
    const Vec2 seg = sg.p1 - sg.p0;
    const double len2 = glm::dot(seg, seg);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(q - sg.p0, seg) / len2, 0.0, 1.0) : 0.0;
    return glm::length(q - (sg.p0 + seg * t));
}

// Lower bound of the distance from any point of `box` to the segment: the distance from the
// segment's bounding box to `box`.
double lowerBound(const Segment& sg, const Box& box) {
    const Vec2 lo = glm::min(sg.p0, sg.p1), hi = glm::max(sg.p0, sg.p1);
    const Vec2 gap = glm::max(glm::max(box.min - hi, lo - box.max), Vec2(0.0));
    return glm::length(gap);
}

// The segments that can be nearest to some point of `box` within `reach`: a segment whose
// lower bound (the distance from its bounding box) exceeds the reach, or exceeds some segment's
// upper bound over the box (the distance to a segment is convex, so its maximum over the box is
// at a corner), is nearest nowhere in it. Returns the least lower bound of those kept.
double candidatesNear(const std::vector<Segment>& segments, const Box& box, double reach,
                      std::vector<const Segment*>& out) {
    out.clear();
    for (const Segment& sg : segments)
        if (lowerBound(sg, box) <= reach) out.push_back(&sg);
    if (out.empty()) return kInf;
    // The least upper bound among those in reach bounds the nearest distance at every point of
    // the box (if that is within reach at all).
    const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, {box.min.x, box.max.y}, box.max};
    double upper = kInf;
    for (const Segment* sg : out) {
        double farthest = 0.0;
        for (const Vec2& c : corners) farthest = std::max(farthest, segmentDistance(*sg, c));
        upper = std::min(upper, farthest);
    }
    double nearest = kInf;
    std::size_t kept = 0;
    for (const Segment* sg : out) {
        const double lower = lowerBound(*sg, box);
        if (lower > upper) continue;
        out[kept++] = sg;
        nearest = std::min(nearest, lower);
    }
    out.resize(kept);
    return nearest;
}

constexpr int kBlock = 16;  // pixels: the blocks whose candidate segments are found together

// Fills dist (distance to the polyline), v (signed: > 0 on the left of the direction of travel)
// and u of the nearest segment, for the pixels within `reach` metres (and a pixel) of the
// polyline, and lists them as touched. Block by block (kBlock pixels), only the candidate
// segments (candidatesNear) are measured: wide roads seen from close would otherwise compute
// every segment of their margin at every texel. Among segments at the same distance the first
// one wins.
void distanceField(Canvas& canvas, const std::vector<Segment>& segments, double reach) {
    Scratch& s = canvas.scratch();
    const double px = canvas.pixelSize();
    const double within = reach + px;
    Vec2 lo(kInf), hi(-kInf);  // of the finite segments (a non-finite one is nobody's candidate)
    for (const Segment& sg : segments)
        if (finite(sg.p0) && finite(sg.p1)) lo = glm::min(lo, glm::min(sg.p0, sg.p1)), hi = glm::max(hi, glm::max(sg.p0, sg.p1));
    if (!finite(lo)) return;  // no finite segment
    const int side = canvas.side();
    const auto [x0, y0, x1, y1] = canvas.around(lo, hi, within / px + 2.0);
    std::vector<const Segment*> candidates;
    for (int by = y0; by < y1; by += kBlock)
        for (int bx = x0; bx < x1; bx += kBlock) {
            const int ex = std::min(bx + kBlock, x1), ey = std::min(by + kBlock, y1);
            if (candidatesNear(segments, {canvas.world(bx, by), canvas.world(ex - 1, ey - 1)}, within, candidates) > within) continue;
            for (int y = by; y < ey; ++y)
                for (int x = bx; x < ex; ++x) {
                    const Vec2 q = canvas.world(x, y);
                    float best = kInf;
                    const Segment* nearest = nullptr;
                    double bestT = 0.0;
                    Vec2 bestR(0.0);
                    for (const Segment* sg : candidates) {
                        const Vec2 seg = sg->p1 - sg->p0, r = q - sg->p0;
                        const double len2 = glm::dot(seg, seg);
                        const double t = len2 > 0.0 ? std::clamp(glm::dot(r, seg) / len2, 0.0, 1.0) : 0.0;
                        const float d = float(glm::length(r - seg * t));
                        if (d < best) best = d, nearest = sg, bestT = t, bestR = r;
                    }
                    if (!nearest || double(best) > within) continue;
                    const std::size_t k = std::size_t(y) * std::size_t(side) + std::size_t(x);
                    const Vec2 seg = nearest->p1 - nearest->p0;
                    s.dist[k] = best;
                    s.v[k] = float(seg.x * bestR.y - seg.y * bestR.x >= 0.0 ? double(best) : -double(best));
                    s.u[k] = float(nearest->u0 + (nearest->u1 - nearest->u0) * bestT);
                    const bool cap = (bestT == 0.0 && nearest->startCap) || (bestT == 1.0 && nearest->endCap);
                    s.flags[k] = std::uint8_t(cap ? (s.flags[k] | kCap) : (s.flags[k] & ~kCap));
                    canvas.touch(k);
                }
        }
}

template <class Real>
float smoothFall(Real d, Real width) {  // 1 at d <= 0, 0 at d >= width
    if (width <= Real(0) || d >= width) return 0.0f;
    if (d <= Real(0)) return 1.0f;
    const Real t = Real(1) - d / width;
    return float(t * t * (Real(3) - Real(2) * t));
}

// smoothFall(d, width) of four distances.
Float4 smoothFall4(Float4 d, float width) {
    if (width <= 0.0f) return splat(0.0f);
    const Float4 t = 1.0f - d / width;
    const Float4 f = t * t * (3.0f - 2.0f * t);
    return width <= d ? splat(0.0f) : d <= 0.0f ? splat(1.0f) : f;
}

// Rivers in two passes over all the rivers of a layer, so no bank is drawn over water where
// rivers meet: banks (between w/2 and wf/2), then water (mask 1) within w/2.
void drawRiverBanks(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c) {
    const double hw = 0.5 * double(c.w), hwf = std::max(hw, 0.5 * double(c.wf));
    distanceField(canvas, segments, hwf);
    Scratch& s = canvas.scratch();
    const float px = float(canvas.pixelSize());
    for (std::uint32_t k : s.touched) {
        const float d = s.dist[k];
        const float cov = bandCoverage(d / px, float(hw) / px);
        canvas.over(k, riverBankColour(), 0.0f, (1.0f - cov) * smoothFall(double(d) - hw, hwf - hw));
    }
    canvas.clearTouched();
}

void drawRiverWater(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c) {
    const double hw = 0.5 * double(c.w);
    distanceField(canvas, segments, hw);
    Scratch& s = canvas.scratch();
    const float px = float(canvas.pixelSize());
    const glm::vec3 water = glm::vec3(surfaceColour({Surface::Water, 0, 0}, Vec2(0.0), 1.0));
    for (std::uint32_t k : s.touched) canvas.over(k, water, 1.0f, bandCoverage(s.dist[k] / px, float(hw) / px));
    canvas.clearTouched();
}

void drawRoadSurface(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c) {
    const double hw = 0.5 * double(c.w);
    distanceField(canvas, segments, hw);
    Scratch& s = canvas.scratch();
    const float px = float(canvas.pixelSize());
    const glm::vec3 asphalt = roadColour(c.cls);
    for (std::uint32_t k : s.touched) canvas.over(k, asphalt, 0.0f, bandCoverage(s.dist[k] / px, float(hw) / px));
    canvas.clearTouched();
}

// What a road's markings need to know about its ends, from the ancestor graph.
struct RoadEnds {
    double length = 0.0;
    double startRadius = 0.0, endRadius = 0.0;  // junction radius, 0 if not a junction
    bool startStop = false, endStop = false;
};

void drawMarkings(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, const RoadEnds& ends) {
    const MarkingGeometry g;
    const double hw = 0.5 * double(c.w);
    distanceField(canvas, segments, hw);
    Scratch& s = canvas.scratch();
    const double px = canvas.pixelSize();
    const float halfLine = float(0.5 * g.lineWidth / px);
    const float sideAxis = float((hw - g.sideInset - 0.5 * g.lineWidth) / px);
    const double laneHalf = 0.5 * (hw - g.sideInset);
    for (std::uint32_t k : s.touched) {
        const double d = s.dist[k], v = s.v[k], u = s.u[k];
        if (d > hw || (s.flags[k] & kCap)) continue;  // no side line around the round end caps
        // Side lines and the dashed centre line, stopping at junctions.
        float m = bandCoverage(float(d / px) - sideAxis, halfLine);  // d = |v|: both sides at once
        double phase = u - g.dashPeriod * std::floor(u / g.dashPeriod);  // [0, period)
        const double dashCentre = 0.5 * g.dashLength;
        const double along = std::min(std::abs(phase - dashCentre), std::abs(phase - dashCentre - g.dashPeriod));
        m = std::max(m, bandCoverage(float(v / px), halfLine) * bandCoverage(float(along / px), float(dashCentre / px)));
        if (ends.startRadius > 0.0) m *= edgeCoverage(float((u - ends.startRadius) / px));
        if (ends.endRadius > 0.0) m *= edgeCoverage(float((ends.length - ends.endRadius - u) / px));
        // Stop lines across the lane that enters the junction (traffic on the right).
        const auto stopLine = [&](double fromNode, double radius, double laneSide) {
            const double centre = radius + g.stopLineGap + 0.5 * g.stopLineWidth;
            return bandCoverage(float((fromNode - centre) / px), float(0.5 * g.stopLineWidth / px)) *
                   bandCoverage(float((laneSide * v - laneHalf) / px), float(laneHalf / px));
        };
        if (ends.startStop) m = std::max(m, stopLine(u, ends.startRadius, 1.0));
        if (ends.endStop) m = std::max(m, stopLine(ends.length - u, ends.endRadius, -1.0));
        canvas.over(k, markingColour(), 0.0f, m);
    }
    canvas.clearTouched();
}

// --- Areas -------------------------------------------------------------------------------------

// Every texel of the canvas at coverage 1 (an area covering the quad), row by row; also how a
// uniform tile's texels are made (tileTexels), so the two agree bit for bit.
void shadeWhole(Canvas& canvas, SurfaceShader& shader) {
    constexpr int n = SurfaceShader::kMaxBlock;
    shader.prepareBlocks(canvas.pixelSize());
    const int side = canvas.side();
    for (int y = 0; y < side; y += n)
        for (int x = 0; x < side; x += n)
            shader.block(canvas.world(x, y), std::min(n, side - x), std::min(n, side - y),
                         &canvas.scratch().colour[std::size_t(y) * std::size_t(side) + std::size_t(x)], std::size_t(side));
}

void drawArea(Canvas& canvas, const AppearanceTile& t, const ClippedArea& area, const SurfaceShade& shade, double wf,
              AppearanceCounters* counters) {
    Scratch& s = canvas.scratch();
    SurfaceShader shader(shade, t.delta);
    shader.prepare(canvas.box());
    if (area.coversQuad) {
        shadeWhole(canvas, shader);
        return;
    }
    std::vector<std::vector<Vec2>> loops;
    std::vector<Segment> border;  // the real border, not the closing paths
    for (const ClippedLoop& loop : area.loops) {
        std::vector<Vec2> pts;
        bool closing = false;
        for (const Vertex& vx : loop.vertices) {
            if (!vx.onCurve) continue;
            if (!pts.empty() && !closing) border.push_back({pts.back(), vx.p});
            pts.push_back(vx.p);
            closing = vx.closing;
        }
        loops.push_back(std::move(pts));
    }
    // The canvas pixels the piece can change: the bounding box of its finite points (the
    // rasterizer drops a triangle with a non-finite vertex, and no such segment is a candidate),
    // dilated by the border strip and a few pixels. Every pixel it flags below lies in there, and
    // is cleared there.
    Vec2 reachMin(kInf), reachMax(-kInf);
    for (const auto& pts : loops)
        for (const Vec2& p : pts)
            if (finite(p)) reachMin = glm::min(reachMin, p), reachMax = glm::max(reachMax, p);
    if (!finite(reachMin)) return;  // nothing to draw
    const double px = canvas.pixelSize();
    const int side = canvas.side();
    const auto [x0, y0, x1, y1] = canvas.around(reachMin, reachMax, (wf + px) / px + 3.0);

    std::vector<Triangle> triangles;
    triangulateArea(loops, (t.bounds.min + t.bounds.max) * 0.5, triangles);
    if (counters) counters->triangles += triangles.size();
    std::uint8_t* const flags = s.flags.data();
    Rgbm* const colour = s.colour.data();
    for (const Triangle& tri : triangles) canvas.triangle(tri, [flags](std::size_t k, int, int) { flags[k] |= kInside; });
    // The distance to the real border, block by block: only the candidate segments
    // (candidatesNear) within reach of the strip (wf + px), so a pixel costs one or two segment
    // distances rather than one per overlapping capsule. Beyond that reach the distance changes
    // nothing (no strip, full coverage), and inside pixels farther than a pixel from the border
    // need none: they take the surface's colour (coverage 1) without blending.
    const double reachDistance = wf + px;
    const Rgbm strip(borderStripColour(shade.surface), 0.0f);
    const float wff = float(wf);
    struct LocalSegment {
        float x0, y0, dx, dy, invLen2;
    };
    std::vector<const Segment*> candidates;
    std::vector<LocalSegment> local;
    static_assert(kBlock == SurfaceShader::kMaxBlock && kBlock % 4 == 0);
    Rgbm blockColour[kBlock * kBlock];
    shader.prepareBlocks(px);
    // Pixel centres of a block row, in metres from the block's first pixel centre.
    Float4 qx[kBlock / 4];
    for (int i = 0; i < kBlock; ++i) qx[i / 4][i % 4] = float(double(i) * px);
    const float pxf = float(px);
    for (int by = y0; by < y1; by += kBlock)
        for (int bx = x0; bx < x1; bx += kBlock) {
            const int ex = std::min(bx + kBlock, x1), ey = std::min(by + kBlock, y1);
            const double nearest = candidatesNear(border, {canvas.world(bx, by), canvas.world(ex - 1, ey - 1)}, reachDistance, candidates);
            const bool insideNeedsDistance = nearest < px;
            // The candidates in block-local float metres (from the block's first pixel centre):
            // a rounding of about 1e-7 of the segments' extent, far below a texel at every level.
            const Vec2 origin = canvas.world(bx, by);
            local.clear();
            for (const Segment* sg : candidates) {
                const Vec2 p0 = sg->p0 - origin, seg = sg->p1 - sg->p0;
                const double len2 = glm::dot(seg, seg);
                local.push_back({float(p0.x), float(p0.y), float(seg.x), float(seg.y), len2 > 0.0 ? float(1.0 / len2) : 0.0f});
            }
            bool shaded = false;  // the surface's colours over the block, made once when needed
            for (int y = by; y < ey; ++y) {
                const std::size_t row = std::size_t(y) * std::size_t(side);
                // Squared distances to the real border along the row (infinite: none near), four
                // pixels at a time.
                std::uint8_t* const f = flags + row;
                int insideCount = 0;
                for (int x = bx; x < ex; ++x) insideCount += (f[x] & kInside) != 0;
                Rgbm* const c = colour + row;
                if (insideCount == ex - bx && !insideNeedsDistance) {  // the whole row at coverage 1, no strip
                    if (!shaded) shader.block(origin, ex - bx, ey - by, blockColour, kBlock), shaded = true;
                    std::memcpy(c + bx, blockColour + (y - by) * kBlock, sizeof(Rgbm) * std::size_t(ex - bx));
                    std::memset(f + bx, 0, std::size_t(ex - bx));
                    continue;
                }
                if (insideCount == 0 && local.empty()) continue;  // nothing here (and no flag to clear)
                // Only rows with a pixel that needs them: outside pixels, or any near the border.
                const bool distances = !local.empty() && (insideNeedsDistance || insideCount < ex - bx);
                Float4 d2[kBlock / 4];
                for (Float4& v : d2) v = splat(kInf);
                const float qy = float(double(y - by) * px);
                for (const LocalSegment& l : distances ? local : std::span<const LocalSegment>{}) {
                    const Float4 dx = splat(l.dx), dy = splat(l.dy);
                    const float ry = qy - l.y0;
                    for (int v = 0; v < kBlock / 4; ++v) {
                        const Float4 rx = qx[v] - l.x0;
                        const Float4 tt = clamp4((rx * dx + ry * dy) * l.invLen2, splat(0.0f), splat(1.0f));
                        const Float4 exv = rx - dx * tt, eyv = ry - dy * tt;
                        d2[v] = min4(d2[v], exv * exv + eyv * eyv);
                    }
                }
                // From them, four pixels at a time: the coverage of a pixel inside (edgeCoverage of
                // d) and outside (of -d), and the border strip's fall-off outside (smoothFall).
                Float4 coverIn[kBlock / 4], coverOut[kBlock / 4], fall[kBlock / 4];
                if (distances)
                    for (int v = 0; v < kBlock / 4; ++v) {
                        const Float4 d = sqrt4(d2[v]), zero = splat(0.0f), one = splat(1.0f);
                        coverIn[v] = clamp4(d / pxf + 0.5f, zero, one);
                        coverOut[v] = clamp4(-d / pxf + 0.5f, zero, one);
                        fall[v] = smoothFall4(d, wff);
                    }
                const Rgbm* const surface = blockColour + (y - by) * kBlock - bx;
                for (int x = bx; x < ex; ++x) {
                    const bool inside = (f[x] & kInside) != 0;
                    f[x] = 0;
                    if (inside ? insideNeedsDistance : !local.empty()) {
                        const int v = (x - bx) / 4, lane = (x - bx) % 4;
                        const float cov = inside ? coverIn[v][lane] : coverOut[v][lane];
                        const float stripAlpha = (1.0f - cov) * (inside ? 1.0f : fall[v][lane]);
                        if (stripAlpha > 0.0f) blend(c[x], strip, stripAlpha);
                        if (cov <= 0.0f) continue;
                        if (!shaded) shader.block(origin, ex - bx, ey - by, blockColour, kBlock), shaded = true;
                        blend(c[x], surface[x], cov);
                    } else if (inside) {  // coverage 1, no strip
                        if (!shaded) shader.block(origin, ex - bx, ey - by, blockColour, kBlock), shaded = true;
                        c[x] = surface[x];
                    }
                }
            }
        }
}

// --- Drawing order and uniform quads ------------------------------------------------------------

struct DrawItem {
    LayerId layer;
    bool area;
    ElementId id;
};

int rank(LayerKind kind) {
    switch (kind) {
        case LayerKind::Lakes: return 1;
        case LayerKind::Rivers: return 2;
        case LayerKind::Roads: return 3;
        default: return 0;
    }
}

template <class Map>
std::vector<ElementId> sortedKeys(const Map& m) {
    std::vector<ElementId> ids;
    ids.reserve(m.size());
    for (const auto& [id, pieces] : m) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    return ids;
}

std::vector<DrawItem> drawList(const Quad& quad, const Scene& scene, const std::vector<bool>& hidden) {
    std::vector<LayerId> layers(quad.layers.size());
    for (LayerId l = 0; l < layers.size(); ++l) layers[l] = l;
    std::stable_sort(layers.begin(), layers.end(),
                     [&](LayerId a, LayerId b) { return rank(scene.layers[a].kind) < rank(scene.layers[b].kind); });
    std::vector<DrawItem> items;
    for (LayerId l : layers) {
        if (l < hidden.size() && hidden[l]) continue;
        const LayerKind kind = scene.layers[l].kind;
        if (surfaceOf(kind) != Surface::None)
            for (ElementId id : sortedKeys(quad.layers[l].areas)) items.push_back({l, true, id});
        if (kind == LayerKind::Roads || kind == LayerKind::Rivers)
            for (ElementId id : sortedKeys(quad.layers[l].curves)) items.push_back({l, false, id});
    }
    return items;
}

// The shade of the last item when it covers the whole tile (border texels included).
std::optional<SurfaceShade> coveringShade(const Quad& quad, const Quadtree& qt, const AppearanceTile& t, const DrawItem& last) {
    const Scene& scene = qt.scene();
    const LayerKind kind = scene.layers[last.layer].kind;
    if (last.area) {
        const auto& pieces = quad.layers[last.layer].areas.at(last.id);
        if (pieces.size() == 1 && pieces.front().coversQuad)
            return SurfaceShade{surfaceOf(kind), scene.layers[last.layer].areas[last.id].cls, last.id};
        return std::nullopt;
    }
    if (kind != LayerKind::Rivers) return std::nullopt;
    const Curve& c = qt.ancestorCurve(last.layer, last.id);
    const double limit = 0.5 * double(c.w) - t.delta / double(t.samples);
    if (limit <= 0.0) return std::nullopt;
    const Box box = t.bounds.dilated(double(t.border) * t.delta);
    const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, {box.min.x, box.max.y}, box.max};
    for (const Segment& sg : segmentsOf(quad.layers[last.layer].curves.at(last.id), nullptr, last.layer, last.id)) {
        const Vec2 seg = sg.p1 - sg.p0;
        const double len2 = glm::dot(seg, seg);
        const bool holds = std::all_of(std::begin(corners), std::end(corners), [&](Vec2 q) {
            const double tt = len2 > 0.0 ? std::clamp(glm::dot(q - sg.p0, seg) / len2, 0.0, 1.0) : 0.0;
            return glm::length(q - (sg.p0 + seg * tt)) <= limit;  // a capsule is convex
        });
        if (holds) return SurfaceShade{Surface::Water, 0, last.id};
    }
    return std::nullopt;
}

std::uint8_t quantize(float c) { return std::uint8_t(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

// Box-filters the canvas down to the tile's texels.
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

}  // namespace

AppearanceTile produceAppearance(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData,
                                 const Dem& dem, const AppearanceParams& params, AppearanceCounters* counters) {
    const int n = quadtree.params().resolution;
    if (n <= 0 || params.border < 0 || params.samples < 1 || params.samples > 8 || params.groundCells < 1 ||
        !(params.groundCellMin >= 0.0))
        throw std::invalid_argument("produceAppearance(): resolution > 0, border >= 0, 1 <= samples <= 8, groundCells >= 1 and groundCellMin >= 0 required");
    if (params.border > quadtree.params().appearanceBorder)
        throw std::invalid_argument("produceAppearance(): the tile border is wider than the quadtree clips for (RefineParams::appearanceBorder)");
    AppearanceTile t;
    t.bounds = quad.bounds;
    t.resolution = n;
    t.border = params.border;
    t.stride = n + 2 * params.border;
    t.samples = params.samples;
    t.delta = quad.bounds.size().x / double(n);
    if (counters) ++counters->tiles;

    const Scene& scene = quadtree.scene();
    const std::vector<DrawItem> items = drawList(quad, scene, params.hiddenLayers);
    if (params.detectUniform && !items.empty())
        if (const auto shade = coveringShade(quad, quadtree, t, items.back())) {
            t.uniform = true;
            t.shade = *shade;
            if (counters) {
                ++counters->uniformTiles;
                if (shade->surface == Surface::Water) counters->waterTexels += std::size_t(t.stride) * std::size_t(t.stride);
            }
            return t;
        }

    Canvas canvas(t, threadScratch());
    // Cells of groundCellMin at least, from the level's nominal size (the root's halved `level`
    // times, exact), so quads of a level agree on their grid and share its nodes.
    const double size = std::ldexp(quadtree.root().bounds.size().x, -quad.level);
    const double fit = std::ceil(size / std::max(params.groundCellMin, 1e-9) - 1e-9);
    const int cells = int(std::clamp(fit, 1.0, double(params.groundCells)));
    drawGround(canvas, t, dem, cells);
    const MarkingGeometry marking;
    const bool markingsShow = marking.lineWidth >= params.markingMinTexels * t.delta;
    for (std::size_t i = 0; i < items.size(); ++i) {
        const DrawItem& it = items[i];
        const Layer& layer = scene.layers[it.layer];
        if (it.area) {
            const Area& a = layer.areas[it.id];
            const SurfaceShade shade{surfaceOf(layer.kind), a.cls, it.id};
            for (const ClippedArea& piece : quad.layers[it.layer].areas.at(it.id)) {
                drawArea(canvas, t, piece, shade, double(a.wf), counters);
                if (counters) ++counters->areaPieces;
            }
            continue;
        }
        // The curves of one layer are consecutive items: draw them together, in two passes.
        std::size_t last = i;
        while (last + 1 < items.size() && !items[last + 1].area && items[last + 1].layer == it.layer) ++last;
        const auto& curves = quad.layers[it.layer].curves;
        if (counters) counters->curvesDrawn += last - i + 1;
        for (std::size_t r = i; r <= last; ++r) {
            const Curve& c = quadtree.ancestorCurve(it.layer, items[r].id);
            const auto segments = segmentsOf(curves.at(items[r].id), nullptr, it.layer, items[r].id);
            if (layer.kind == LayerKind::Rivers) drawRiverBanks(canvas, segments, c);
            else drawRoadSurface(canvas, segments, c);
        }
        for (std::size_t r = i; r <= last; ++r) {
            const ElementId id = items[r].id;
            const Curve& c = quadtree.ancestorCurve(it.layer, id);
            if (layer.kind == LayerKind::Rivers) {
                drawRiverWater(canvas, segmentsOf(curves.at(id), nullptr, it.layer, id), c);
                continue;
            }
            if (!roadHasMarkings(c.cls)) continue;
            if (!markingsShow) {
                if (counters) ++counters->markingsBelowTexel;
                continue;
            }
            RoadEnds ends;
            ends.length = curveData.length(it.layer, id);
            ends.startRadius = junctionRadius(layer, c.start);
            ends.endRadius = junctionRadius(layer, c.end);
            ends.startStop = hasStopLine(layer, c.start, id);
            ends.endStop = hasStopLine(layer, c.end, id);
            drawMarkings(canvas, segmentsOf(curves.at(id), &curveData, it.layer, id), c, ends);
            if (counters) ++counters->curvesWithMarkings;
        }
        i = last;
    }
    canvas.scratch().clean = true;
    resolve(canvas, canvas.scratch(), t, t.rgbm);
    if (counters) {
        std::size_t water = 0;
        for (std::size_t k = 3; k < t.rgbm.size(); k += 4) water += t.rgbm[k] > 0;
        counters->waterTexels += water;
    }
    return t;
}

std::vector<std::uint8_t> tileTexels(const AppearanceTile& tile) {
    if (!tile.uniform) return tile.rgbm;
    Canvas canvas(tile, threadScratch());
    std::fill(canvas.scratch().colour.begin(), canvas.scratch().colour.end(), Rgbm(0.0f));
    SurfaceShader shader(tile.shade, tile.delta);
    shader.prepare(canvas.box());
    shadeWhole(canvas, shader);
    canvas.scratch().clean = true;  // shadeWhole sets neither dist nor flags
    std::vector<std::uint8_t> out;
    resolve(canvas, canvas.scratch(), tile, out);
    return out;
}

}  // namespace lacet
