#include "raster/elevation_producer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "model/segment.h"
#include "raster/appearance_segments.h"
#include "raster/rasterizer.h"

namespace lacet {
namespace {

constexpr double kSqrt2 = std::numbers::sqrt2;

// The blending profile b(d): 1 up to `inner`, 0 from `outer`, smoothstep between.
float blend(double d, double inner, double outer) {
    if (d <= inner) return 1.0f;
    if (d >= outer) return 0.0f;
    const double t = (outer - d) / (outer - inner);
    return float(t * t * (3.0 - 2.0 * t));
}

class FootprintCanvas {
public:
    FootprintCanvas(ElevationTile& tile) : t_(tile), d_(tile.b.size(), std::numeric_limits<float>::infinity()) {}

    // MAX combination: the larger b wins and brings its z_e; for equal b the nearer axis (or
    // border) wins, then the lower z_e. A total order, so the result does not depend on the
    // drawing order; and inside one curve, where every segment near a sample gives b = 1, the
    // nearest segment's z_e is kept, which is z at the nearest point of the polyline (a lower
    // z from the round end cap of the next segment would make steps along sloping roads).
    void put(std::size_t k, float b, float z, float d) {
        if (b <= 0.0f) return;
        if (b > t_.b[k] || (b == t_.b[k] && (d < d_[k] || (d == d_[k] && z < t_.ze[k])))) {
            t_.b[k] = b;
            t_.ze[k] = z;
            d_[k] = d;
        }
    }

    // Tile pixel coordinates of a scene point: sample (i, j) is pixel (i + border, j + border).
    glm::dvec2 pixel(Vec2 p) const { return (p - t_.bounds.min) / t_.delta + double(t_.border) + 0.5; }

    // Calls f(k, position) for every sample within `radius` metres of segment a-b (a superset:
    // the capsule's oriented bounding rectangle, rasterized).
    template <class F>
    void capsule(Vec2 a, Vec2 b, double radius, F&& f) const {
        const glm::dvec2 pa = pixel(a), pb = pixel(b);
        const double r = radius / t_.delta + 1.0;  // one sample of slack: the test below is exact
        glm::dvec2 d = pb - pa;
        const double len = glm::length(d);
        d = len > 0.0 ? d / len : glm::dvec2(1.0, 0.0);
        const glm::dvec2 n(-d.y, d.x);
        RasterVertex v[4];
        v[0].p = pa - d * r - n * r;
        v[1].p = pa - d * r + n * r;
        v[2].p = pb + d * r - n * r;
        v[3].p = pb + d * r + n * r;
        auto shade = [&](int x, int y, const float*) {
            const int i = x - t_.border, j = y - t_.border;
            f(t_.index(i, j), t_.position(i, j));
        };
        rasterizeTriangle(v[0], v[1], v[2], 0, t_.stride, t_.stride, shade);
        rasterizeTriangle(v[1], v[3], v[2], 0, t_.stride, t_.stride, shade);
    }

private:
    ElevationTile& t_;
    std::vector<float> d_;  // distance to the axis or border of the element that gave b and z_e
};

void drawCurve(FootprintCanvas& canvas, const ElevationTile& tile, LayerId l, AncestorId a,
               const std::vector<ClippedCurve>& pieces, const Curve& c, const CurveDataCache& data) {
    // b = 1 within w/2 + 2 sqrt(2) delta: the sqrt(2) delta of §5.2 (bilinear interpolation of the
    // samples), plus sqrt(2) delta for the 3x3 filter, which reads one more sample out; so z_m
    // inside the road's width is the filtered z_e alone and the road stays level across.
    const double inner = 0.5 * double(c.w) + 2.0 * kSqrt2 * tile.delta;
    const double outer = std::max(inner, 0.5 * double(c.wf) + 2.0 * kSqrt2 * tile.delta);
    const ZProfile& profile = data.zProfile(l, a);
    std::vector<Vec2> pts;
    std::vector<double> us;
    for (const ClippedCurve& run : pieces) {
        pts.clear();
        us.clear();
        std::size_t k = 0;
        for (const Vertex& v : run.vertices)
            if (v.onCurve) {
                pts.push_back(v.p);
                us.push_back(data.u(l, a, run.s[k++]));
            }
        for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
            const Vec2 p0 = pts[i], p1 = pts[i + 1];
            canvas.capsule(p0, p1, outer, [&](std::size_t idx, Vec2 q) {
                const SegmentNearest n = nearestOnSegment(q, p0, p1);
                const double d = std::sqrt(n.distance2);
                const float b = blend(d, inner, outer);
                if (b > 0.0f) canvas.put(idx, b, float(profile.at(us[i] + (us[i + 1] - us[i]) * n.t)), float(d));
            });
        }
    }
}

bool insideLoops(const std::vector<ClippedLoop>& loops, Vec2 q) {
    bool inside = false;
    for (const auto& l : loops) {
        const auto& v = l.vertices;
        Vec2 prev = v.front().p;
        for (std::size_t i = 1; i < v.size(); ++i) {
            if (!v[i].onCurve) continue;
            const Vec2 cur = v[i].p;
            if ((cur.y > q.y) != (prev.y > q.y) && q.x < (prev.x - cur.x) * (q.y - cur.y) / (prev.y - cur.y) + cur.x)
                inside = !inside;
            prev = cur;
        }
    }
    return inside;
}

// An area's footprint (§5.2, the three steps of areas): b = 1 inside, b falling to 0 at wf outside
// the real border (not the closing curves of clipped areas), and z_e = level(k) at sample k in
// both regions: the lake level, or a river area's axial profile (AxialHeights).
template <class Level>
void drawAreaFootprint(FootprintCanvas& canvas, ElevationTile& tile, const std::vector<ClippedArea>& pieces, double wf,
                       Level&& level) {
    const double reach = wf + kSqrt2 * tile.delta;
    for (const ClippedArea& area : pieces) {
        // Inside: every sample of the tile is tested (tiles are small: 25 x 25 plus border).
        for (int j = -tile.border; j <= tile.resolution + tile.border; ++j)
            for (int i = -tile.border; i <= tile.resolution + tile.border; ++i)
                if (area.coversQuad || insideLoops(area.loops, tile.position(i, j)))
                    canvas.put(tile.index(i, j), 1.0f, level(tile.index(i, j)), 0.0f);
        if (area.coversQuad) continue;
        // Banks: outside the real border, down to 0 at wf.
        for (const ClippedLoop& loop : area.loops) {
            Vec2 prev = loop.vertices.front().p;
            bool closing = loop.vertices.front().closing;
            for (std::size_t i = 1; i < loop.vertices.size(); ++i) {
                const Vertex& v = loop.vertices[i];
                if (!v.onCurve) continue;
                if (!closing) {
                    const Vec2 p0 = prev, p1 = v.p;
                    canvas.capsule(p0, p1, reach, [&](std::size_t idx, Vec2 q) {
                        const double d = distanceToSegment(q, p0, p1);
                        canvas.put(idx, blend(d, kSqrt2 * tile.delta, reach), level(idx), float(d));
                    });
                }
                prev = v.p;
                closing = v.closing;
            }
        }
    }
}

// A river area's z_e (§5.2: "z_e <- z(u) ... by drawing a strip based on the axial curve"): at
// every sample of the tile, the z-profile of the area's river (axialRiver: its axial curve and
// the river on through the area) at its point nearest to the sample. The curves are the root
// curves, whole (the nearest point may lie outside the quad). Only the Bezier pieces that can hold
// the nearest point of some sample are flattened (a piece whose control box is farther from the
// tile than some piece's start is from every corner of the tile is nearest nowhere in it); then,
// per block of samples, the candidate segments (appearance::candidatesNear) are measured
// (model/segment.h).
class AxialHeights {
public:
    AxialHeights(const ElevationTile& tile, LayerId l, const Layer& layer, const std::vector<ElementId>& river,
                 const CurveDataCache& data)
        : z_(tile.b.size(), 0.0f) {
        const Box box{tile.position(-tile.border, -tile.border),
                      tile.position(tile.resolution + tile.border, tile.resolution + tile.border)};
        const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, {box.min.x, box.max.y}, box.max};
        struct Piece {
            BezierPiece b;
            ElementId curve;
            std::size_t k;  // index of the piece in its curve
        };
        std::vector<Piece> pieces;
        for (ElementId c : river)
            forEachPiece(layer.curves[c].vertices, [&](const BezierPiece& b, std::size_t) {
                const std::size_t k = pieces.empty() || pieces.back().curve != c ? 0 : pieces.back().k + 1;
                pieces.push_back({b, c, k});
            });
        if (pieces.empty()) return;
        std::vector<double> lower(pieces.size());
        double upper = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            lower[i] = boxDistance(box, controlBounds(pieces[i].b));
            double farthest = 0.0;
            for (const Vec2& c : corners) farthest = std::max(farthest, glm::length(c - pieces[i].b.start()));
            upper = std::min(upper, farthest);
        }
        const double step = std::max(tile.delta, kMinAxialStep);
        for (std::size_t i = 0; i < pieces.size(); ++i) {
            if (lower[i] > upper) continue;
            const BezierPiece& b = pieces[i].b;
            double polygon = 0.0;
            for (int d = 0; d < b.degree; ++d) polygon += glm::length(b.p[std::size_t(d) + 1] - b.p[std::size_t(d)]);
            const int n = b.degree == 1 ? 1 : std::clamp(int(std::ceil(polygon / step)), kMinAxialSegments, kMaxAxialSegments);
            // u at the piece's ends is exact; inside, it follows the chords' length.
            const ElementId c = pieces[i].curve;
            const double u0 = data.u(l, c, double(pieces[i].k)), u1 = data.u(l, c, double(pieces[i].k + 1));
            std::vector<Vec2> pts(std::size_t(n) + 1);
            std::vector<double> cum(pts.size(), 0.0);
            for (int j = 0; j <= n; ++j) {
                pts[std::size_t(j)] = j == 0 ? b.start() : j == n ? b.end() : evaluate(b, double(j) / n);
                if (j > 0) cum[std::size_t(j)] = cum[std::size_t(j) - 1] + glm::length(pts[std::size_t(j)] - pts[std::size_t(j) - 1]);
            }
            const double total = cum.back();
            const ZProfile* profile = &data.zProfile(l, c);
            for (int j = 0; j < n; ++j) {
                appearance::Segment sg;
                sg.p0 = pts[std::size_t(j)];
                sg.p1 = pts[std::size_t(j) + 1];
                sg.u0 = total > 0.0 ? u0 + (u1 - u0) * cum[std::size_t(j)] / total : u0;
                sg.u1 = total > 0.0 ? u0 + (u1 - u0) * cum[std::size_t(j) + 1] / total : u1;
                segments_.push_back(sg);
                profiles_.push_back(profile);
            }
        }
        std::vector<const appearance::Segment*> candidates;
        const int first = -tile.border, last = tile.resolution + tile.border;
        for (int j0 = first; j0 <= last; j0 += kSampleBlock)
            for (int i0 = first; i0 <= last; i0 += kSampleBlock) {
                const int i1 = std::min(last, i0 + kSampleBlock - 1), j1 = std::min(last, j0 + kSampleBlock - 1);
                appearance::candidatesNear(segments_, Box{tile.position(i0, j0), tile.position(i1, j1)},
                                           std::numeric_limits<double>::infinity(), candidates);
                for (int j = j0; j <= j1; ++j)
                    for (int i = i0; i <= i1; ++i) {
                        const Vec2 q = tile.position(i, j);
                        double best = std::numeric_limits<double>::infinity(), z = 0.0;
                        for (const appearance::Segment* sg : candidates) {
                            const SegmentNearest n = nearestOnSegment(q, sg->p0, sg->p1);
                            if (n.distance2 < best) {
                                best = n.distance2;
                                z = profiles_[std::size_t(sg - segments_.data())]->at(sg->u0 + (sg->u1 - sg->u0) * n.t);
                            }
                        }
                        z_[tile.index(i, j)] = float(z);
                    }
            }
    }

    float operator()(std::size_t k) const { return z_[k]; }

private:
    static constexpr double kMinAxialStep = 0.5;  // metres: the longest flattened segment is max(delta, this)
    static constexpr int kMinAxialSegments = 4;   // per curved piece
    static constexpr int kMaxAxialSegments = 256; // per piece
    static constexpr int kSampleBlock = 8;        // samples per side of the blocks whose candidate segments are found together

    static double boxDistance(const Box& a, const Box& b) {
        const double dx = std::max({0.0, b.min.x - a.max.x, a.min.x - b.max.x});
        const double dy = std::max({0.0, b.min.y - a.max.y, a.min.y - b.max.y});
        return std::sqrt(dx * dx + dy * dy);
    }

    std::vector<appearance::Segment> segments_;
    std::vector<const ZProfile*> profiles_;  // of each segment's curve
    std::vector<float> z_;  // z_e at each sample (ElevationTile::index)
};

// 3x3 Gaussian (1 2 1) x (1 2 1) / 16 of z_m where b > 0, on every sample but the outer ring.
void filterWhereBlended(ElevationTile& t) {
    const std::vector<float> zm = t.zm;
    for (int j = 1 - t.border; j <= t.resolution + t.border - 1; ++j)
        for (int i = 1 - t.border; i <= t.resolution + t.border - 1; ++i) {
            if (t.b[t.index(i, j)] <= 0.0f) continue;
            double sum = 0.0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) sum += double((2 - std::abs(di)) * (2 - std::abs(dj))) * zm[t.index(i + di, j + dj)];
            t.zm[t.index(i, j)] = float(sum / 16.0);
        }
}

// z_c: z_m at the even samples (the parent level's grid), linear in between.
void halfResolution(ElevationTile& t) {
    auto even = [&](int i) { return (i % 2 + 2) % 2 == 0; };
    for (int j = 1 - t.border; j <= t.resolution + t.border - 1; ++j)
        for (int i = 1 - t.border; i <= t.resolution + t.border - 1; ++i) {
            const int i0 = even(i) ? i : i - 1, i1 = even(i) ? i : i + 1;
            const int j0 = even(j) ? j : j - 1, j1 = even(j) ? j : j + 1;
            t.zc[t.index(i, j)] = 0.25f * (t.zm[t.index(i0, j0)] + t.zm[t.index(i1, j0)] + t.zm[t.index(i0, j1)] + t.zm[t.index(i1, j1)]);
        }
}

}  // namespace

AxialRiver axialRiver(const Layer& layer, const Area& area) {
    constexpr std::size_t kMaxCurves = 256;  // a bound on the walk, far above a river area's confluences
    std::vector<ClippedLoop> loops;
    for (const auto& loop : area.loops) loops.push_back({loopVertices(layer, loop), false});
    const Curve& axial = layer.curves[area.axial];
    AxialRiver out;
    std::vector<ElementId>& curves = out.curves;
    curves.push_back(area.axial);
    std::vector<ElementId> pending{axial.start, axial.end}, seen;
    while (!pending.empty() && curves.size() < kMaxCurves) {
        const ElementId n = pending.back();
        pending.pop_back();
        if (n == kNoElement || std::find(seen.begin(), seen.end(), n) != seen.end()) continue;
        seen.push_back(n);
        if (!insideLoops(loops, layer.nodes[n].p)) continue;
        out.nodes.push_back(n);
        for (ElementId c : layer.nodes[n].curves) {
            const Curve& cv = layer.curves[c];
            if (!cv.alive || !cv.areas.empty() || cv.cls != axial.cls || (cv.flags & (kBridge | kTunnel)) ||
                std::find(curves.begin(), curves.end(), c) != curves.end())
                continue;
            curves.push_back(c);
            pending.push_back(cv.start == n ? cv.end : cv.start);
        }
    }
    std::sort(curves.begin(), curves.end());
    std::sort(out.nodes.begin(), out.nodes.end());
    return out;
}


ElevationTile produceElevation(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData,
                               const Dem& dem, const ElevationParams& params, ElevationCounters* counters,
                               const CancelFlag* cancel) {
    throwIfCancelled(cancel);
    const TileGrid& grid = quadtree.params().grid();  // validated by the Quadtree
    const int n = grid.elevationResolution;
    ElevationTile t;
    t.bounds = quad.bounds;
    t.resolution = n;
    t.border = grid.elevationBorder;
    t.delta = quad.bounds.size().x / double(n);
    t.stride = n + 1 + 2 * grid.elevationBorder;
    const std::size_t count = std::size_t(t.stride) * std::size_t(t.stride);
    t.zo.resize(count);
    t.ze.assign(count, 0.0f);
    t.b.assign(count, 0.0f);
    t.zc.assign(count, 0.0f);
    for (int j = -t.border; j <= n + t.border; ++j)
        for (int i = -t.border; i <= n + t.border; ++i) t.zo[t.index(i, j)] = float(dem.sample(t.position(i, j)));

    FootprintCanvas canvas(t);
    const Scene& scene = quadtree.scene();
    for (LayerId l = 0; l < quad.layers.size(); ++l) {
        if (l < params.hiddenLayers.size() && params.hiddenLayers[l]) continue;
        const LayerKind kind = scene.layers[l].kind;
        if (kind == LayerKind::Roads || kind == LayerKind::Rivers) {
            std::size_t k = 0;
            for (const auto& [a, pieces] : quad.layers[l].curves) {
                if ((k++ & 63) == 0) throwIfCancelled(cancel);
                const Curve& c = quadtree.ancestorCurve(l, a);
                if (c.flags & (kBridge | kTunnel)) {  // the terrain under a deck or over a tunnel stays as it is
                    if (counters) ++counters->curvesOnStructures;
                    continue;
                }
                if (double(c.w) < 2.0 * t.delta) {
                    if (counters) ++counters->curvesSkippedThin;
                    continue;
                }
                drawCurve(canvas, t, l, a, pieces, c, curveData);
                if (counters) ++counters->curvesDrawn;
            }
        }
        if (kind == LayerKind::Lakes || kind == LayerKind::Rivers) {
            // Lakes, and river areas without an axial curve: flat at the lowest height of their
            // border. River areas with one: its descending profile at the nearest point.
            for (const auto& [a, pieces] : quad.layers[l].areas) {
                throwIfCancelled(cancel);
                const Area& area = scene.layers[l].areas[a];
                const double wf = double(area.wf);
                if (kind == LayerKind::Rivers && area.axial != kNoElement) {
                    const AxialHeights axial(t, l, scene.layers[l], axialRiver(scene.layers[l], area).curves, curveData);
                    drawAreaFootprint(canvas, t, pieces, wf, axial);
                } else {
                    const float level = float(curveData.lakeLevel(l, a));
                    drawAreaFootprint(canvas, t, pieces, wf, [level](std::size_t) { return level; });
                }
                if (counters && kind == LayerKind::Lakes) ++counters->lakesDrawn;
            }
        }
    }
    t.zm.resize(count);
    for (std::size_t k = 0; k < count; ++k) t.zm[k] = t.b[k] * t.ze[k] + (1.0f - t.b[k]) * t.zo[k];
    filterWhereBlended(t);
    halfResolution(t);
    if (counters) ++counters->tiles;
    return t;
}

}  // namespace lacet
