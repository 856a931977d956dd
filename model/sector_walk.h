#pragma once
// Paths outside a box, followed around it with exact predicates. Used to close clipped areas
// along the quad border (§4.2, Fig. 4) and to decide whether an area covers a quad.
//
// The plane outside the box is cut into four sectors by the rays from the box centre C through
// its corners B0 = (min.x, min.y), B1 = (max.x, min.y), B2 = (max.x, max.y), B3 = (min.x, max.y):
// sector j lies between ray j (included) and ray j+1, counter-clockwise (0 bottom, 1 right,
// 2 top, 3 left). A Bezier piece whose bounds miss the box lies in a half-plane that excludes C,
// so it turns around C by less than half a turn, exactly as its chord does: the number of
// corner rays it crosses (its signed "steps") is found from the sectors of its end points and
// one orientation test, all with CGAL's exact predicates. Four steps are one turn.

#include <vector>

#include "model/types.h"

namespace lacet {

class SectorWalk {
public:
    explicit SectorWalk(const Box& box);

    int sector(Vec2 p) const;
    // Signed corner-ray crossings of the chord p -> q, which must lie in a half-plane that
    // excludes the box centre (positive counter-clockwise).
    int steps(Vec2 p, Vec2 q) const;
    Vec2 corner(int k) const { return corners_[((k % 4) + 4) % 4]; }
    // The corners a path outside the box passes, leaving sector `fromSector` and turning by
    // `steps`: appended in travel order. With P in sector s0 and Q reached after `steps`, the
    // polyline P, corners..., Q stays outside the box and turns around it like the path.
    void appendCorners(int fromSector, int steps, std::vector<Vec2>& out) const;

private:
    Vec2 center_;
    Vec2 corners_[4];
};

}  // namespace lacet
