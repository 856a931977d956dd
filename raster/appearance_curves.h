#pragma once
// Internal to the appearance producer: roads (surface, markings) and rivers (banks, water),
// drawn from the distance to their polylines (§5.1).

#include <span>
#include <vector>

#include "model/graph.h"
#include "raster/appearance_canvas.h"
#include "raster/appearance_segments.h"

namespace lacet::appearance {

// The distance field the passes below draw from: fills dist (distance to the polyline, metres),
// v (signed: > 0 on the left of the direction of travel), u of the nearest segment and the kCap
// flag (nearest to a capped end, beyond it), for the pixels within `reach` metres and a pixel of
// the polyline, and lists them as touched (the caller clears them). Among segments at the same
// distance the first one wins. The passes below draw from the same field, pixel by pixel, without
// storing it.
//
// distanceFieldReference is the plain one, in double, one pixel and one segment at a time.
// distanceField, the one the passes use, measures four pixels against a segment at once in
// float (segment4.h, in each block's local frame): the same pixels and values up to float
// rounding of the local coordinates (about 1e-6 of the block's reach), and where two segments are
// that near to equally near it may take the other one. tests/raster/appearance_curves_test.cpp
// holds the reference to every segment measured at every pixel, and the two to each other within
// those bounds.
void distanceFieldReference(Canvas& canvas, const std::vector<Segment>& segments, double reach);
void distanceField(Canvas& canvas, const std::vector<Segment>& segments, double reach);

// Rivers in two passes over all the rivers of a layer, so no bank is drawn over water where
// rivers meet: banks (between w/2 and wf/2), then water (mask 1) within w/2.
void drawRiverBanks(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c);
void drawRiverWater(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c);

// What a road's markings need to know about its ends, from the ancestor graph.
struct RoadEnds {
    double length = 0.0;
    double startRadius = 0.0, endRadius = 0.0;  // junction radius, 0 if not a junction
    bool startStop = false, endStop = false;
    // A yield line (dashed, across the entering lane) where the road enters a roundabout's ring
    // (kYieldAtStart / kYieldAtEnd); the radius at that end is then the ring's half width.
    bool startYield = false, endYield = false;
};

// The dashes of a yield line, in metres.
struct YieldLineGeometry {
    double width = 0.3;       // along the road
    double gap = 0.5;         // between the ring's edge and the line
    double dashLength = 0.5;  // across the lane: dashes of dashLength every dashPeriod
    double dashPeriod = 1.0;
};

// A tunnel's portals: its road, darkened, within portalLength metres (u) of either end, framed by
// a 1 m border of the portal's stone (the rest of a tunnel is not drawn: it is under the ground).
void drawTunnelPortals(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, double length,
                       double portalLength);

// Side lines, the dashed centre line, stop lines and yield lines, from the curvilinear coordinate u of the
// segments (segmentsOf with curve data).
// A road's markings (side lines, dashed centre line, stop and yield lines) at a point at distance
// d >= 0 (m) from its polyline, signed v (> 0 on the left), u (m) along it, for pixels of `pixel`
// metres: their coverage of the pixel (0..1). beyondLines(): the point is beyond every line's
// reach, where the coverage is exactly 0 (drawMarkings skips such texels; the test holds the two
// to each other).
struct RoadMarkings {
    RoadMarkings(const Curve& c, const RoadEnds& ends, double pixel);
    float coverage(double d, double v, double u) const;
    bool beyondLines(double d, double v, double u) const;
    // Whether a stop or yield line reaches some u in [uLo, uHi] (where it does not, beyondLines
    // depends on d alone: |d / px - sideAxis| >= lineReach and d / px >= lineReach).
    bool endLinesWithin(double uLo, double uHi) const;

    const MarkingGeometry g{};
    const YieldLineGeometry yield{};
    const RoadEnds ends;
    const double px, hw;
    const float halfLine, sideAxis;  // pixels
    const double laneHalf;
    const double lineReach;  // pixels from a line's axis beyond which its band covers nothing
};

// A road's surface (asphalt within w/2). With `markings`, the segments carry u (segmentsOf with
// curve data) and the caps of its markings (capRingEnds), and the coverage of its markings is
// found at each pixel of the surface and appended to `marks`, to be drawn once the layer's other
// surfaces are down (drawMarkings of those marks).
void drawRoadSurface(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c,
                     const RoadMarkings* markings = nullptr, std::vector<MarkingTexel>* marks = nullptr);

// The road's markings from its distance field to `segments` (the reference), or the marks its
// surface found (drawRoadSurface): the same pixels, bit for bit, when the surface was drawn from
// the same segments.
void drawMarkings(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, const RoadEnds& ends);
void drawMarkings(Canvas& canvas, std::span<const MarkingTexel> marks);

}  // namespace lacet::appearance
