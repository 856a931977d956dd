#include "raster/appearance_areas.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>

#include <glm/geometric.hpp>

#include "raster/appearance_segments.h"
#include "raster/area_triangulation.h"
#include "raster/segment4.h"

namespace lacet::appearance {

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
    std::vector<Triangle> triangles;
    triangulateArea(loops, (t.bounds.min + t.bounds.max) * 0.5, triangles);
    if (counters) counters->triangles += triangles.size();
    // The canvas pixels the piece can change: the bounding box of its finite points and of its
    // triangles' vertices (the triangulation may add the intersections of crossing borders; the
    // rasterizer drops a triangle with a non-finite vertex, and no such segment is a candidate),
    // dilated by the border strip and a few pixels. Every pixel flagged below lies in there, and
    // is cleared there, so the canvas's flags are left clean for the next piece and tile.
    Vec2 reachMin(kInf), reachMax(-kInf);
    const auto reach = [&](Vec2 p) {
        if (finite(p)) reachMin = glm::min(reachMin, p), reachMax = glm::max(reachMax, p);
    };
    for (const auto& pts : loops)
        for (const Vec2& p : pts) reach(p);
    for (const Triangle& tri : triangles)
        for (const Vec2& p : tri) reach(p);
    if (!finite(reachMin)) return;  // nothing to draw
    const double px = canvas.pixelSize();
    const int side = canvas.side();
    const auto [x0, y0, x1, y1] = canvas.around(reachMin, reachMax, (wf + px) / px + 3.0);
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
    const float insideFall = wf > 0.0 ? 1.0f : 0.0f;  // smoothFall(0, wf): no strip without a width
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
            for (const Segment* sg : candidates) local.push_back(localSegment(sg->p0, sg->p1, origin));
            bool shaded = false;  // the surface's colours over the block, made once when needed
            for (int y = by; y < ey; ++y) {
                const std::size_t row = std::size_t(y) * std::size_t(side);
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
                // Squared distances to the real border along the row (infinite: none near), four
                // pixels at a time.
                Float4 d2[kBlock / 4];
                for (Float4& v : d2) v = splat(kInf);
                const float qy = float(double(y - by) * px);
                for (const LocalSegment& l : distances ? local : std::span<const LocalSegment>{})
                    for (int v = 0; v < kBlock / 4; ++v) d2[v] = min4(d2[v], distanceSquared4(l, qx[v], qy));
                // From them, four pixels at a time: the coverage of a pixel inside (edgeCoverage of
                // d) and outside (of -d), and the border strip's fall-off outside (smoothFall).
                Float4 coverIn[kBlock / 4] = {}, coverOut[kBlock / 4] = {}, fall[kBlock / 4] = {};
                if (distances)
                    for (int v = 0; v < kBlock / 4; ++v) {
                        const Float4 d = sqrt4(d2[v]), zero = splat(0.0f), one = splat(1.0f);
                        coverIn[v] = clamp4(d / pxf + 0.5f, zero, one);
                        coverOut[v] = clamp4(-d / pxf + 0.5f, zero, one);
                        fall[v] = smoothFall4(d, wff);
                    }
                const Rgbm* const surface = blockColour + (y - by) * kBlock;  // from pixel bx
                for (int x = bx; x < ex; ++x) {
                    const bool inside = (f[x] & kInside) != 0;
                    f[x] = 0;
                    if (inside ? insideNeedsDistance : !local.empty()) {
                        const int v = (x - bx) / 4, lane = (x - bx) % 4;
                        const float cov = inside ? coverIn[v][lane] : coverOut[v][lane];
                        const float stripAlpha = (1.0f - cov) * (inside ? insideFall : fall[v][lane]);
                        if (stripAlpha > 0.0f) blend(c[x], strip, stripAlpha);
                        if (cov <= 0.0f) continue;
                        if (!shaded) shader.block(origin, ex - bx, ey - by, blockColour, kBlock), shaded = true;
                        blend(c[x], surface[x - bx], cov);
                    } else if (inside) {  // coverage 1, no strip
                        if (!shaded) shader.block(origin, ex - bx, ey - by, blockColour, kBlock), shaded = true;
                        c[x] = surface[x - bx];
                    }
                }
            }
        }
}

}  // namespace lacet::appearance
