#pragma once
// The view-dependent refinement knobs (§8), named once: the quadtree's subdivision rule
// (Quadtree::refineForViewer, Quadtree::wantsSubdivision), the editing session that drives it, the
// renderer's geomorphing that hides its level changes, and the benchmarks that report them all
// read one ViewParams.
//
// The rule: a quad of size s (metres, side of its square) at distance d from the viewer
// (Quadtree::viewDistance: to the nearest point of the quad, at the viewer's height) is subdivided
// when d < K * s and its level is below maxLevel. So a leaf of size s is shown for distances in
// [K * s, 2 * K * s): at 2 * K * s its parent (size 2 * s) stops being subdivided and the parent's
// level begins.
//
// Geomorphing: the renderer moves a leaf's heights from its own z_m to the coarser z_c (the
// heights its parent would show) as the distance nears 2 * K * s, so the level change at that
// distance neither pops nor leaves a step. The morph band is given in units of K * s:
// t = clamp((d / (K * s) - morphStart) / morphWidth, 0, 1) blends z_m (t = 0) to z_c (t = 1).
// It must end where the parent's level begins, morphStart + morphWidth = 2 (morphEnd()), and start
// after the leaf's own level begins, morphStart >= 1.

#include <cmath>
#include <stdexcept>

namespace lacet {

struct ViewParams {
    // Subdivide quads closer to the viewer than K times their size (dimensionless, > 0; the paper
    // uses 2.8). Larger K: finer quads at a given distance, more tiles to make.
    double K = 2.8;
    // Deepest quadtree level (the root is level 0; 0 to kMaxLevel). Level 24 is quads of about 6 mm
    // over a 100 km scene, deeper than any view needs.
    int maxLevel = 24;
    // Where the geomorphing band starts, in units of K times the leaf size (in [1, 2)).
    double morphStart = 1.6;
    // Its width in the same units (morphStart + morphWidth = 2: it ends where the parent's level
    // begins).
    double morphWidth = 0.4;

    double morphEnd() const { return morphStart + morphWidth; }

    // Quads are numbered with 32-bit coordinates, and the draw plan (editor/draw_plan.h) orders
    // leaves by 64-bit Z-order codes: 31 levels.
    static constexpr int kMaxLevel = 31;

    // Throws std::invalid_argument naming the knob out of its range.
    void validate() const {
        if (!(K > 0.0)) throw std::invalid_argument("ViewParams: K must be > 0");
        if (maxLevel < 0 || maxLevel > kMaxLevel) throw std::invalid_argument("ViewParams: maxLevel must be in [0, 31]");
        if (!(morphStart >= 1.0 && morphWidth > 0.0 && std::abs(morphEnd() - 2.0) < 1e-12))
            throw std::invalid_argument("ViewParams: the morph band must start at or after 1 and end at 2 (morphStart + morphWidth)");
    }
};

}  // namespace lacet
