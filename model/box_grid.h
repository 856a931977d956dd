#pragma once
// A uniform grid over the boxes of items (segments, Bezier pieces) for nearest-item searches: the
// distance from a point to a polyline of a million segments, or to a layer's curves, visiting
// only the items whose cells are nearer than the best distance found so far.
//
// Order of calls: BoxGrid grid(boxes); then, per query point, grid.visitNear(q, best, f): f(i)
// is called for items in rings of cells around q, nearest rings first, and may lower `best`; the
// walk stops once a ring's cells are all farther than `best`. Items whose boxes are farther than
// `best` may be visited too (f prunes them); no item that could be nearer is skipped.
//
// Units: metres. Not thread-safe (a visit stamp per item); make one grid per thread.

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "model/types.h"

namespace lacet {

class BoxGrid {
public:
    // Cells of about the median item size, at most kMaxCellsPerSide a side and kCellsPerItem
    // times as many cells as items in all (an item spanning many cells is listed in each).
    // Boxes must be finite.
    explicit BoxGrid(std::span<const Box> boxes);

    template <class Visit>
    void visitNear(Vec2 q, const double& best, Visit&& visit) const;

    std::size_t size() const { return stamps_.size(); }

private:
    static constexpr int kMaxCellsPerSide = 2048;
    static constexpr double kCellsPerItem = 4.0;

    int cellX(double x) const;
    int cellY(double y) const;

    Box bounds_{};
    double cell_ = 1.0;
    int nx_ = 1, ny_ = 1;
    std::vector<std::uint32_t> offsets_;  // per cell, into items_ (nx * ny + 1)
    std::vector<std::uint32_t> items_;
    mutable std::vector<std::uint32_t> stamps_;
    mutable std::uint32_t stamp_ = 0;
};

template <class Visit>
void BoxGrid::visitNear(Vec2 q, const double& best, Visit&& visit) const {
    if (stamps_.empty()) return;
    if (++stamp_ == 0) {  // wrapped: forget every old stamp
        std::fill(stamps_.begin(), stamps_.end(), 0u);
        stamp_ = 1;
    }
    const int ci = cellX(q.x), cj = cellY(q.y);
    const int maxRing = std::max({ci, nx_ - 1 - ci, cj, ny_ - 1 - cj});
    for (int r = 0; r <= maxRing; ++r) {
        // Every cell of ring r is at least (r - 1) cells from q along one axis.
        if (r >= 1 && double(r - 1) * cell_ >= best) return;
        for (int j = cj - r; j <= cj + r; ++j) {
            if (j < 0 || j >= ny_) continue;
            const bool edgeRow = j == cj - r || j == cj + r;
            for (int i = ci - r; i <= ci + r; i += edgeRow ? 1 : 2 * r) {
                if (i >= 0 && i < nx_) {
                    const std::size_t c = std::size_t(j) * std::size_t(nx_) + std::size_t(i);
                    for (std::uint32_t k = offsets_[c]; k < offsets_[c + 1]; ++k) {
                        const std::uint32_t item = items_[k];
                        if (stamps_[item] == stamp_) continue;
                        stamps_[item] = stamp_;
                        visit(std::size_t(item));
                    }
                }
                if (r == 0) break;
            }
        }
    }
}

}  // namespace lacet
