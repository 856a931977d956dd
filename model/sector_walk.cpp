#include "model/sector_walk.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace lacet {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

int orient(Vec2 a, Vec2 b, Vec2 c) {
    return int(CGAL::orientation(Kernel::Point_2(a.x, a.y), Kernel::Point_2(b.x, b.y), Kernel::Point_2(c.x, c.y)));
}

}  // namespace

SectorWalk::SectorWalk(const Box& box)
    : center_(box.center()),
      corners_{box.min, {box.max.x, box.min.y}, box.max, {box.min.x, box.max.y}} {}

int SectorWalk::sector(Vec2 p) const {
    for (int j = 0; j < 4; ++j)
        if (orient(center_, corners_[j], p) >= 0 && orient(center_, corners_[(j + 1) % 4], p) < 0) return j;
    return 0;  // p == centre: not reachable for points outside the box
}

int SectorWalk::steps(Vec2 p, Vec2 q) const {
    const int a = sector(p);
    const int b = sector(q);
    const int o = orient(center_, p, q);
    if (o > 0) return (b - a + 4) % 4;
    if (o < 0) return -((a - b + 4) % 4);
    return 0;  // p, q on one ray from the centre: same sector
}

void SectorWalk::appendCorners(int fromSector, int turn, std::vector<Vec2>& out) const {
    // Going counter-clockwise from sector s to s+1 crosses ray s+1, i.e. passes corner s+1;
    // clockwise from s to s-1 passes corner s.
    for (int k = 1; k <= turn; ++k) out.push_back(corner(fromSector + k));
    for (int k = 0; k < -turn; ++k) out.push_back(corner(fromSector - k));
}

}  // namespace lacet
