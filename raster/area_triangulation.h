#pragma once
// Area interiors as triangles (§5.1): the loops of a clipped area (outer ring, holes, closing
// paths along the quad border) are inserted as constraints of a CGAL constrained Delaunay
// triangulation, and the faces inside the area are kept.
//
// Inside is decided by the even-odd rule at each face's centroid, against all the loops at once,
// not by counting constrained edges crossed from the infinite face: a hole touching its ring, or
// a hole's closing path lying on the ring's closing path (both run along the same quad border),
// makes coincident constraints that a crossing count would see once instead of twice.
// Constraints that cross (a closing path may cut a kept piece that reaches beyond the dilated
// quad) are split at their intersection (Exact_predicates_tag).
//
// Coordinates: the triangulation works relative to `origin` (the quad's centre), so areas far
// from the scene origin keep their precision. Loops are polylines, first point repeated at the
// end or not; consecutive repeated points are dropped; a loop of fewer than 3 distinct points
// encloses nothing.

#include <array>
#include <vector>

#include "model/types.h"

namespace lacet {

using Triangle = std::array<Vec2, 3>;

// Appends the triangles inside the loops (scene coordinates) to `out`.
void triangulateArea(const std::vector<std::vector<Vec2>>& loops, Vec2 origin, std::vector<Triangle>& out);

// Even-odd rule: whether q is inside an odd number of the loops.
bool insideLoops(const std::vector<std::vector<Vec2>>& loops, Vec2 q);

}  // namespace lacet
