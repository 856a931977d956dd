#include "raster/appearance_curves.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>

#include "model/segment.h"
#include "raster/segment4.h"

namespace lacet::appearance {

namespace {

// One pixel of the field, stored as distanceField's callers read it.
void setTexel(Canvas& canvas, std::size_t k, const Segment& nearest, float dist, float v, double t) {
    Scratch& s = canvas.scratch();
    s.dist[k] = dist;
    s.v[k] = v;
    s.u[k] = float(nearest.u0 + (nearest.u1 - nearest.u0) * t);
    const bool cap = (t == 0.0 && nearest.startCap) || (t == 1.0 && nearest.endCap);
    s.flags[k] = std::uint8_t(cap ? (s.flags[k] | kCap) : (s.flags[k] & ~kCap));
    canvas.touch(k);
}

// The canvas pixels a field within `within` metres of the finite segments can reach (none
// without a finite segment: a non-finite one is nobody's candidate).
std::optional<Canvas::Rect> fieldRect(const Canvas& canvas, const std::vector<Segment>& segments, double within) {
    Vec2 lo(kInf), hi(-kInf);
    for (const Segment& sg : segments)
        if (finite(sg.p0) && finite(sg.p1)) lo = glm::min(lo, glm::min(sg.p0, sg.p1)), hi = glm::max(hi, glm::max(sg.p0, sg.p1));
    if (!finite(lo)) return std::nullopt;
    return canvas.around(lo, hi, within / canvas.pixelSize() + 2.0);
}

constexpr int kLanes = kBlock / 4;  // Float4 vectors in a block row

// One row of a block of the field (forEachFieldRow): pixels k0 .. k0 + count - 1 of the canvas,
// four to a vector. Per pixel: the distance (infinite where no segment is a candidate), the
// parameter on the nearest segment and its index in `local` and `candidates` (-1: none); the
// pixel centres (qx, qy) and the segments in the block's local frame.
struct FieldRow {
    std::size_t k0 = 0;
    int count = 0;
    Float4 dist[kLanes], t[kLanes];
    Int4 index[kLanes];
    const Float4* qx = nullptr;
    float qy = 0.0f;
    const LocalSegment* local = nullptr;
    const Segment* const* candidates = nullptr;
    std::size_t candidateCount = 0;
    std::size_t block = 0;  // counts the blocks visited: what a pass derives from the candidates holds while it is the same
    float at(const Float4* v, int i) const { return v[i / 4][i % 4]; }
    // Signed v of pixel i (> 0 on the left of its nearest segment), from the local frame.
    float signedV(int i) const {
        const LocalSegment& ls = local[std::size_t(index[i / 4][i % 4])];
        const float rx = qx[i / 4][i % 4] - ls.x0, ry = qy - ls.y0;
        const float d = at(dist, i);
        return ls.dx * ry - ls.dy * rx >= 0.0f ? d : -d;
    }
};

// The field of distanceField, a block row at a time: visit(row) for every row of every block
// with a candidate segment within `reach` and a pixel of the polyline. Block by block (kBlock
// pixels), only the candidate segments (candidatesNear) are measured, four pixels of a row
// against one at once in float, in the block's local frame (segment4.h): per lane the least
// squared distance, its segment and parameter.
template <class Visit>
void forEachFieldRow(Canvas& canvas, const std::vector<Segment>& segments, double reach, Visit&& visit) {
    Scratch& s = canvas.scratch();
    const double px = canvas.pixelSize();
    const double within = reach + px;
    const std::optional<Canvas::Rect> rect = fieldRect(canvas, segments, within);
    if (!rect) return;
    const auto [x0, y0, x1, y1] = *rect;
    const int side = canvas.side();
    std::vector<const Segment*>& candidates = s.candidates;
    std::vector<LocalSegment>& local = s.local;
    Float4 qx[kLanes];  // pixel centres of a block row, metres from the block's first one
    for (int i = 0; i < kBlock; ++i) qx[i / 4][i % 4] = float(double(i) * px);
    FieldRow row;
    row.qx = qx;
    for (int by = y0; by < y1; by += kBlock)
        for (int bx = x0; bx < x1; bx += kBlock) {
            const int ex = std::min(bx + kBlock, x1), ey = std::min(by + kBlock, y1);
            if (candidatesNear(segments, {canvas.world(bx, by), canvas.world(ex - 1, ey - 1)}, within, candidates) > within) continue;
            const Vec2 origin = canvas.world(bx, by);
            local.clear();
            for (const Segment* sg : candidates) local.push_back(localSegment(sg->p0, sg->p1, origin));
            row.local = local.data();
            row.candidates = candidates.data();
            row.candidateCount = candidates.size();
            row.count = ex - bx;
            ++row.block;
            for (int y = by; y < ey; ++y) {
                const float qy = float(double(y - by) * px);
                Float4* const best = row.dist;
                for (int l = 0; l < kLanes; ++l) best[l] = splat(kInf), row.t[l] = splat(0.0f), row.index[l] = splatInt(-1);
                for (std::size_t c = 0; c < local.size(); ++c) {
                    const LocalSegment& ls = local[c];
                    const Int4 ci = splatInt(int(c));
                    const float ry = qy - ls.y0;
                    for (int l = 0; l < kLanes; ++l) {
                        const Float4 rx = qx[l] - ls.x0;
                        const Float4 t = clamp4((rx * ls.dx + ry * ls.dy) * ls.invLen2, splat(0.0f), splat(1.0f));
                        const Float4 ex2 = rx - ls.dx * t, ey2 = ry - ls.dy * t;
                        const Float4 d2 = ex2 * ex2 + ey2 * ey2;
                        const Int4 nearer = d2 < best[l];  // the first among equally near ones stays
                        best[l] = nearer ? d2 : best[l];
                        row.t[l] = nearer ? t : row.t[l];
                        row.index[l] = nearer ? ci : row.index[l];
                    }
                }
                for (int l = 0; l < kLanes; ++l) best[l] = sqrt4(best[l]);
                row.qy = qy;
                row.k0 = std::size_t(y) * std::size_t(side) + std::size_t(bx);
                visit(row);
            }
        }
}

// The same pixel by pixel: visit(k, dist, v, nearest, t) for each pixel within `reach` and a
// pixel of the polyline, in block order.
template <class Visit>
void forEachFieldPixel(Canvas& canvas, const std::vector<Segment>& segments, double reach, Visit&& visit) {
    const double within = reach + canvas.pixelSize();
    forEachFieldRow(canvas, segments, reach, [&](const FieldRow& row) {
        for (int i = 0; i < row.count; ++i) {
            const int index = row.index[i / 4][i % 4];
            const float dist = row.at(row.dist, i);
            if (index < 0 || double(dist) > within) continue;
            visit(row.k0 + std::size_t(i), dist, row.signedV(i), *row.candidates[std::size_t(index)], double(row.at(row.t, i)));
        }
    });
}

}  // namespace

void distanceFieldReference(Canvas& canvas, const std::vector<Segment>& segments, double reach) {
    const double within = reach + canvas.pixelSize();
    const std::optional<Canvas::Rect> rect = fieldRect(canvas, segments, within);
    if (!rect) return;
    const auto [x0, y0, x1, y1] = *rect;
    const int side = canvas.side();
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
                        const double t = nearestParameter(q, sg->p0, sg->p1);
                        const float d = float(glm::length(r - seg * t));
                        if (d < best) best = d, nearest = sg, bestT = t, bestR = r;
                    }
                    if (!nearest || double(best) > within) continue;
                    const Vec2 seg = nearest->p1 - nearest->p0;
                    const float v = float(seg.x * bestR.y - seg.y * bestR.x >= 0.0 ? double(best) : -double(best));
                    setTexel(canvas, std::size_t(y) * std::size_t(side) + std::size_t(x), *nearest, best, v, bestT);
                }
        }
}

void distanceField(Canvas& canvas, const std::vector<Segment>& segments, double reach) {
    forEachFieldPixel(canvas, segments, reach, [&](std::size_t k, float dist, float v, const Segment& nearest, double t) {
        setTexel(canvas, k, nearest, dist, v, t);
    });
}

namespace {

// The band within hw metres of the polyline, in one colour and water mask, by coverage: drawn as
// the field is measured (each pixel is visited once). With `markings`, the coverage of the road's
// markings at each pixel of the band is appended to `marks` where it is not 0.
void drawBand(Canvas& canvas, const std::vector<Segment>& segments, double hw, glm::vec3 rgb, float mask,
              const RoadMarkings* markings = nullptr, std::vector<MarkingTexel>* marks = nullptr) {
    const float px = float(canvas.pixelSize()), hwPixels = float(hw) / px;
    const Rgbm colour(rgb, mask);
    Rgbm* const out = canvas.scratch().colour.data();
    std::size_t endLinesBlock = 0;  // the block endLines was found for (blocks count from 1)
    bool endLines = true;
    forEachFieldRow(canvas, segments, hw, [&](const FieldRow& row) {
        // bandCoverage four pixels at a time (0 where no segment is near: an infinite distance).
        Float4 alpha[kLanes];
        for (int l = 0; l < kLanes; ++l) {
            const Float4 x = row.dist[l] / px, zero = splat(0.0f), one = splat(1.0f);
            alpha[l] = clamp4(hwPixels - x + 0.5f, zero, one) + clamp4(hwPixels + x + 0.5f, zero, one) - 1.0f;
        }
        for (int i = 0; i < row.count; ++i) {
            const float a = row.at(alpha, i);
            if (a > 0.0f) blend(out[row.k0 + std::size_t(i)], colour, a);
        }
        if (!markings) return;
        // Without a stop or yield line in reach of the block's segments (their u), a pixel has
        // markings only within the side and centre lines' bands across the road (|v| = d): the
        // others are skipped four at a time, with a margin over beyondLines' bound.
        if (row.block != endLinesBlock) {
            double uLo = kInf, uHi = -kInf;
            for (std::size_t c = 0; c < row.candidateCount; ++c)
                uLo = std::min({uLo, row.candidates[c]->u0, row.candidates[c]->u1}),
                uHi = std::max({uHi, row.candidates[c]->u0, row.candidates[c]->u1});
            const double slack = 1e-6 * std::max(std::abs(uLo), std::abs(uHi));  // u is rounded to float
            endLines = markings->endLinesWithin(uLo - slack, uHi + slack);
            endLinesBlock = row.block;
        }
        std::uint32_t lanes = 0;  // bit i: pixel i may have markings
        if (endLines) {
            lanes = (1u << row.count) - 1u;
        } else {
            const float reachPixels = float(markings->lineReach) + 0.01f, axis = markings->sideAxis;
            for (int l = 0; l < kLanes; ++l) {
                const Float4 x = row.dist[l] / px, side = x - axis;
                const Int4 near = ((side < 0.0f ? -side : side) < reachPixels) | (x < reachPixels);
                for (int j = 0; j < 4; ++j) lanes |= near[j] ? 1u << (4 * l + j) : 0u;
            }
            lanes &= (1u << row.count) - 1u;
        }
        for (; lanes; lanes &= lanes - 1) {
            const int i = std::countr_zero(lanes);
            const int index = row.index[i / 4][i % 4];
            const double d = row.at(row.dist, i);
            if (index < 0 || d > markings->hw) continue;  // hw: the band's reach, within the field's
            // As drawMarkings reads them from distanceField: u along the nearest segment, the cap beyond a capped end.
            const Segment& nearest = *row.candidates[std::size_t(index)];
            const double t = row.at(row.t, i);
            if ((t == 0.0 && nearest.startCap) || (t == 1.0 && nearest.endCap)) continue;  // no side line around the round end caps
            const double v = row.signedV(i), u = float(nearest.u0 + (nearest.u1 - nearest.u0) * t);
            if (markings->beyondLines(d, v, u)) continue;  // most of the lanes: no coverage
            const float m = markings->coverage(d, v, u);
            if (m > 0.0f) marks->push_back({std::uint32_t(row.k0 + std::size_t(i)), m});
        }
    });
}

}  // namespace

void drawRiverBanks(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c) {
    const double hw = 0.5 * double(c.w), hwf = std::max(hw, 0.5 * double(c.wf));
    const float px = float(canvas.pixelSize());
    forEachFieldPixel(canvas, segments, hwf, [&](std::size_t k, float d, float, const Segment&, double) {
        const float cov = bandCoverage(d / px, float(hw) / px);
        canvas.over(k, riverBankColour(), 0.0f, (1.0f - cov) * smoothFall(double(d) - hw, hwf - hw));
    });
}

void drawRiverWater(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c) {
    drawBand(canvas, segments, 0.5 * double(c.w), glm::vec3(surfaceColour({Surface::Water, 0, 0}, Vec2(0.0), 1.0)), 1.0f);
}

void drawRoadSurface(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, const RoadMarkings* markings,
                     std::vector<MarkingTexel>* marks) {
    drawBand(canvas, segments, 0.5 * double(c.w), roadColour(c.cls), 0.0f, markings, marks);
}

void drawTunnelPortals(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, double length,
                       double portalLength) {
    // The parts of the polyline within portalLength of either end, cut at that u.
    std::vector<Segment> mouths;
    for (const Segment& sg : segments)
        for (const auto& [lo, hi] : {std::pair{0.0, portalLength}, std::pair{length - portalLength, length}}) {
            const double a = std::max(sg.u0, lo), b = std::min(sg.u1, hi);
            if (!(a < b) || !(sg.u1 > sg.u0)) continue;
            Segment m = sg;
            m.p0 = sg.p0 + (sg.p1 - sg.p0) * ((a - sg.u0) / (sg.u1 - sg.u0));
            m.p1 = sg.p0 + (sg.p1 - sg.p0) * ((b - sg.u0) / (sg.u1 - sg.u0));
            m.u0 = a;
            m.u1 = b;
            mouths.push_back(m);
        }
    if (mouths.empty()) return;
    drawBand(canvas, mouths, 0.5 * double(c.w) + 1.0, tunnelPortalColour(), 0.0f);
    drawBand(canvas, mouths, 0.5 * double(c.w), roadColour(c.cls) * 0.35f, 0.0f);
}

RoadMarkings::RoadMarkings(const Curve& c, const RoadEnds& e, double pixel)
    : ends(e),
      px(pixel),
      hw(0.5 * double(c.w)),
      halfLine(float(0.5 * g.lineWidth / px)),
      sideAxis(float((hw - g.sideInset - 0.5 * g.lineWidth) / px)),
      laneHalf(0.5 * (hw - g.sideInset)),
      lineReach(double(halfLine) + 1.5) {}

bool RoadMarkings::endLinesWithin(double uLo, double uHi) const {
    // The stop and yield lines' reach along the road (as beyondLines), from either end.
    const auto overlaps = [&](bool line, double radius, double gap, double width, bool fromEnd) {
        if (!line) return false;
        const double centre = radius + gap + 0.5 * width, reach = 0.5 * width + 2.0 * px;
        const double lo = fromEnd ? ends.length - centre - reach : centre - reach;
        const double hi = fromEnd ? ends.length - centre + reach : centre + reach;
        return !(uHi < lo || uLo > hi);
    };
    return !(uLo <= uHi) ||  // none, or NaN: the careful way
           overlaps(ends.startStop, ends.startRadius, g.stopLineGap, g.stopLineWidth, false) ||
           overlaps(ends.endStop, ends.endRadius, g.stopLineGap, g.stopLineWidth, true) ||
           overlaps(ends.startYield, ends.startRadius, yield.gap, yield.width, false) ||
           overlaps(ends.endYield, ends.endRadius, yield.gap, yield.width, true);
}

bool RoadMarkings::beyondLines(double d, double v, double u) const {
    // Side and centre lines: beyond their bands across the road, or cut off by a junction (its
    // edgeCoverage is 0 a pixel inside the junction's radius).
    const bool acrossLines = std::abs(d / px - double(sideAxis)) < lineReach || std::abs(v / px) < lineReach;
    const bool cut = (ends.startRadius > 0.0 && u - ends.startRadius <= -px) ||
                     (ends.endRadius > 0.0 && ends.length - ends.endRadius - u <= -px);
    if (acrossLines && !cut) return false;
    // Stop and yield lines: within their width (and two pixels) of their centre along the road.
    const auto near = [&](double fromNode, double radius, double gap, double width) {
        return std::abs(fromNode - (radius + gap + 0.5 * width)) < 0.5 * width + 2.0 * px;
    };
    if (ends.startStop && near(u, ends.startRadius, g.stopLineGap, g.stopLineWidth)) return false;
    if (ends.endStop && near(ends.length - u, ends.endRadius, g.stopLineGap, g.stopLineWidth)) return false;
    if (ends.startYield && near(u, ends.startRadius, yield.gap, yield.width)) return false;
    if (ends.endYield && near(ends.length - u, ends.endRadius, yield.gap, yield.width)) return false;
    return true;
}

float RoadMarkings::coverage(double d, double v, double u) const {
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
    // Yield lines: the same place across the entering lane, in dashes counted from the centre line.
    const auto yieldLine = [&](double fromNode, double radius, double laneSide) {
        const double centre = radius + yield.gap + 0.5 * yield.width;
        const double across = laneSide * v;
        const double phaseAcross = across - yield.dashPeriod * std::floor(across / yield.dashPeriod);
        return bandCoverage(float((fromNode - centre) / px), float(0.5 * yield.width / px)) *
               bandCoverage(float((across - laneHalf) / px), float(laneHalf / px)) *
               bandCoverage(float((phaseAcross - 0.5 * yield.dashPeriod) / px), float(0.5 * yield.dashLength / px));
    };
    if (ends.startYield) m = std::max(m, yieldLine(u, ends.startRadius, 1.0));
    if (ends.endYield) m = std::max(m, yieldLine(ends.length - u, ends.endRadius, -1.0));
    return m;
}

void drawMarkings(Canvas& canvas, std::span<const MarkingTexel> marks) {
    for (const MarkingTexel& m : marks) canvas.over(m.k, markingColour(), 0.0f, m.alpha);
}

void drawMarkings(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, const RoadEnds& ends) {
    const RoadMarkings markings(c, ends, canvas.pixelSize());
    distanceField(canvas, segments, markings.hw);
    Scratch& s = canvas.scratch();
    for (std::uint32_t k : s.touched) {
        const double d = s.dist[k], v = s.v[k], u = s.u[k];
        if (d > markings.hw || (s.flags[k] & kCap)) continue;  // no side line around the round end caps
        if (markings.beyondLines(d, v, u)) continue;
        canvas.over(k, markingColour(), 0.0f, markings.coverage(d, v, u));
    }
    canvas.clearTouched();
}

}  // namespace lacet::appearance
