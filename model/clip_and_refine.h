#pragma once
// CLIPANDREFINE (§4.2, Fig. 4): makes the pieces of one element in a quad from its pieces in
// the parent quad.
//
// Clipping is conservative: a Bezier piece is kept when its tight bounds, dilated by the
// element's margin, meet the quad (curves: wf/2; areas: wf, the width of their outside border
// strip; nodes: half the largest wf of their curves). Refinement splits pieces with de Casteljau
// at t = 1/2 until each is flat within the tolerance (every control point within `tolerance` of
// the chord, so the chord polyline is within `tolerance` of the curve), and also while a piece
// larger than the quad, so that parts far outside are dropped; both decisions depend only on the
// piece and the level, so adjacent quads refine the pieces they share identically. Kept pieces
// stay exact Bezier sub-pieces (control points kept), so a child quad refines them further.
//
// A clipped curve is a maximal run of kept pieces. A clipped area keeps its loops, with each run
// of dropped pieces replaced by a closing path along the dilated quad border that turns around
// the quad exactly as the dropped run did (SectorWalk); a loop with no kept piece either
// vanishes (it does not surround the quad) or becomes the quad border. An area that surrounds
// the quad with no piece near it is flagged `coversQuad`.

#include <algorithm>
#include <cstdint>
#include <vector>

#include "model/tile_grid.h"
#include "model/types.h"

namespace lacet {

// What the quadtree clips for: the tile grid (model/tile_grid.h: resolutions, borders and the
// reaches they imply) and the refinement tolerance, an accuracy knob: `toleranceTexels`
// appearance texels of a quad whose texture is `resolution` texels wide. Default: half a texel of
// a 256-texel quad. RefineParams is a TileGrid, so the grid's fields read as before
// (`params.resolution`); build one as RefineParams{{.resolution = 64}}.
struct RefineParams : TileGrid {
    double toleranceTexels = 0.5;  // texels, > 0
    double tolerance(double quadSize) const { return toleranceTexels * quadSize / double(resolution); }  // metres
    const TileGrid& grid() const { return *this; }

    // Clipping keeps elements as far outside the quad as the producers read them (the larger of
    // the elevation footprint reach and the appearance reach), so that adjacent tiles see the same
    // elements at their shared and border samples and texels.
    // A curve's margin must not grow with depth (a child only sees what its parent kept), so a
    // curve too thin for a footprint at this level still gets the reach of the first deeper level
    // where it has one (the largest delta / 2^k <= w / 2).
    double curveMargin(double w, double wf, double quadSize) const {
        double delta = elevationDelta(quadSize);
        if (w <= 0.0) delta = 0.0;
        while (delta > 0.0 && w < 2.0 * delta) delta *= 0.5;
        return 0.5 * wf + std::max(footprintReach() * delta, appearanceReach(quadSize));
    }
    double areaMargin(double wf, double quadSize) const {
        return wf + std::max(footprintReach() * elevationDelta(quadSize), appearanceReach(quadSize));
    }
};

struct ClippedCurve {
    std::vector<Vertex> vertices;
    // Parameter on the ancestor curve of each on-curve vertex, in order: k + t at parameter t of
    // the ancestor's k-th Bezier piece. Exact (dyadic), so the curvilinear coordinate u of any
    // clipped point is computed on the ancestor (§5.1) and is continuous across quads.
    std::vector<double> s;
    std::uint32_t parentIndex = 0;  // index of the piece it was made from in the parent bucket
    bool startsAtNode = false;      // its first vertex is the ancestor's start node
    bool endsAtNode = false;        // its last vertex is the ancestor's end node
    friend bool operator==(const ClippedCurve&, const ClippedCurve&) = default;
};

struct ClippedLoop {
    std::vector<Vertex> vertices;  // closed: the last vertex repeats the first
    bool hole = false;
    friend bool operator==(const ClippedLoop&, const ClippedLoop&) = default;
};

struct ClippedArea {
    std::vector<ClippedLoop> loops;
    std::uint32_t parentIndex = 0;
    bool coversQuad = false;  // the quad, dilated by the area's margin, lies inside the area
    friend bool operator==(const ClippedArea&, const ClippedArea&) = default;
};

// Refinement stops splitting a piece after this many halvings (2^-40 of its parameter range);
// reached only by pieces far below any texel.
constexpr int kMaxRefineDepth = 40;

void clipAndRefineCurve(const ClippedCurve& parent, std::uint32_t parentIndex, const Box& quad, double margin,
                        double tolerance, std::vector<ClippedCurve>& out);

void clipAndRefineArea(const ClippedArea& parent, std::uint32_t parentIndex, const Box& quad, double margin,
                       double tolerance, std::vector<ClippedArea>& out);

inline bool keepNode(Vec2 p, const Box& quad, double margin) { return quad.dilated(margin).contains(p); }

}  // namespace lacet

namespace lacet {

// Bitwise equality (a -0.0 differs from +0.0): what "incremental equals rebuild" compares.
bool identical(const std::vector<Vertex>& a, const std::vector<Vertex>& b);
bool identical(const ClippedCurve& a, const ClippedCurve& b);
bool identical(const ClippedArea& a, const ClippedArea& b);

}  // namespace lacet
