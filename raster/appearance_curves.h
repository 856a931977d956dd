#pragma once
// Internal to the appearance producer: roads (surface, markings) and rivers (banks, water),
// drawn from the distance to their polylines (§5.1).

#include <vector>

#include "model/graph.h"
#include "raster/appearance_canvas.h"
#include "raster/appearance_segments.h"

namespace lacet::appearance {

// The distance field the passes below draw from: fills dist (distance to the polyline, metres),
// v (signed: > 0 on the left of the direction of travel), u of the nearest segment and the kCap
// flag (nearest to a capped end, beyond it), for the pixels within `reach` metres and a pixel of
// the polyline, and lists them as touched (the caller clears them). Among segments at the same
// distance the first one wins. tests/raster/appearance_curves_test.cpp holds it to every
// segment measured at every pixel.
void distanceField(Canvas& canvas, const std::vector<Segment>& segments, double reach);

// Rivers in two passes over all the rivers of a layer, so no bank is drawn over water where
// rivers meet: banks (between w/2 and wf/2), then water (mask 1) within w/2.
void drawRiverBanks(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c);
void drawRiverWater(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c);

void drawRoadSurface(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c);

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
void drawMarkings(Canvas& canvas, const std::vector<Segment>& segments, const Curve& c, const RoadEnds& ends);

}  // namespace lacet::appearance
