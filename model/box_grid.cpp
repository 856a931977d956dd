#include "model/box_grid.h"

#include <algorithm>
#include <cmath>

namespace lacet {

BoxGrid::BoxGrid(std::span<const Box> boxes) : stamps_(boxes.size(), 0u) {
    if (boxes.empty()) return;
    bounds_ = boxes.front();
    std::vector<double> sizes;
    sizes.reserve(boxes.size());
    for (const Box& b : boxes) {
        bounds_ = {glm::min(bounds_.min, b.min), glm::max(bounds_.max, b.max)};
        sizes.push_back(std::max(b.size().x, b.size().y));
    }
    std::nth_element(sizes.begin(), sizes.begin() + std::ptrdiff_t(sizes.size() / 2), sizes.end());
    const double side = std::max(bounds_.size().x, bounds_.size().y);
    // About the median item, but no more cells than kCellsPerItem per item (items of very
    // different sizes would otherwise make a grid far larger than the items).
    const double area = std::max(bounds_.size().x, 1e-9 * (1.0 + side)) * std::max(bounds_.size().y, 1e-9 * (1.0 + side));
    const double fewest = std::sqrt(area / (kCellsPerItem * double(boxes.size())));
    cell_ = std::max({sizes[sizes.size() / 2], fewest, side / kMaxCellsPerSide, 1e-9 * (1.0 + side)});
    if (!(cell_ > 0.0) || !std::isfinite(cell_)) cell_ = 1.0;
    nx_ = std::clamp(int(std::ceil(bounds_.size().x / cell_)), 1, kMaxCellsPerSide);
    ny_ = std::clamp(int(std::ceil(bounds_.size().y / cell_)), 1, kMaxCellsPerSide);

    // Counting sort of (cell, item) pairs.
    std::vector<std::uint32_t> counts(std::size_t(nx_) * std::size_t(ny_) + 1, 0u);
    auto forCells = [&](const Box& b, auto&& f) {
        const int i0 = cellX(b.min.x), i1 = cellX(b.max.x), j0 = cellY(b.min.y), j1 = cellY(b.max.y);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) f(std::size_t(j) * std::size_t(nx_) + std::size_t(i));
    };
    for (const Box& b : boxes) forCells(b, [&](std::size_t c) { ++counts[c + 1]; });
    for (std::size_t c = 1; c < counts.size(); ++c) counts[c] += counts[c - 1];
    offsets_ = counts;
    items_.resize(offsets_.back());
    for (std::size_t k = 0; k < boxes.size(); ++k) forCells(boxes[k], [&](std::size_t c) { items_[counts[c]++] = std::uint32_t(k); });
}

// Clamped in double first: a far (or non-finite) point must not overflow the int conversion.
int BoxGrid::cellX(double x) const {
    const double c = std::floor((x - bounds_.min.x) / cell_);
    return c >= double(nx_ - 1) ? nx_ - 1 : c > 0.0 ? int(c) : 0;
}
int BoxGrid::cellY(double y) const {
    const double c = std::floor((y - bounds_.min.y) / cell_);
    return c >= double(ny_ - 1) ? ny_ - 1 : c > 0.0 ? int(c) : 0;
}

}  // namespace lacet
