#include "raster/area_triangulation.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace lacet {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_2<Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

}  // namespace

bool insideLoops(const std::vector<std::vector<Vec2>>& loops, Vec2 q) {
    bool inside = false;
    for (const auto& loop : loops) {
        if (loop.size() < 2) continue;
        Vec2 prev = loop.back();
        for (const Vec2& cur : loop) {
            if ((cur.y > q.y) != (prev.y > q.y) && q.x < (prev.x - cur.x) * (q.y - cur.y) / (prev.y - cur.y) + cur.x)
                inside = !inside;
            prev = cur;
        }
    }
    return inside;
}

void triangulateArea(const std::vector<std::vector<Vec2>>& loops, Vec2 origin, std::vector<Triangle>& out) {
    Cdt cdt;
    std::vector<std::vector<Vec2>> local;
    local.reserve(loops.size());
    for (const auto& loop : loops) {
        std::vector<Vec2> l;
        for (const Vec2& p : loop) {
            const Vec2 q = p - origin;
            if (l.empty() || q != l.back()) l.push_back(q);
        }
        while (l.size() > 1 && l.back() == l.front()) l.pop_back();
        if (l.size() < 3) continue;
        std::vector<Kernel::Point_2> points;
        points.reserve(l.size());
        for (const Vec2& q : l) points.emplace_back(q.x, q.y);
        cdt.insert_constraint(points.begin(), points.end(), true);
        local.push_back(std::move(l));
    }
    if (local.empty()) return;
    for (auto f : cdt.finite_face_handles()) {
        Triangle t;
        for (int i = 0; i < 3; ++i) t[std::size_t(i)] = Vec2(f->vertex(i)->point().x(), f->vertex(i)->point().y());
        const Vec2 centroid = (t[0] + t[1] + t[2]) / 3.0;
        if (!insideLoops(local, centroid)) continue;
        for (Vec2& p : t) p += origin;
        out.push_back(t);
    }
}

}  // namespace lacet
