// The layout of the DEM LOD tree (io/dem_lod.h): levels, blocks and the inherited samples.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/dem_lod.h"
#include "io/tile_codec.h"

namespace lacet {

DemLodLayout DemLodLayout::make(int width, int height, double cell, Vec2 origin, int blockSide) {
    if (width < 2 || height < 2)
        throw std::invalid_argument("DemLodLayout::make(): a grid of " + std::to_string(width) + " x " +
                                    std::to_string(height) + " samples (at least 2 x 2)");
    if (!(cell > 0.0) || !std::isfinite(cell))
        throw std::invalid_argument("DemLodLayout::make(): cell " + std::to_string(cell) + " m is not finite and > 0");
    if (!std::isfinite(origin.x) || !std::isfinite(origin.y))
        throw std::invalid_argument("DemLodLayout::make(): the origin is not finite");
    if (blockSide < 4 || blockSide % 2 != 0 || blockSide > kMaxTileSide)
        throw std::invalid_argument("DemLodLayout::make(): block side " + std::to_string(blockSide) +
                                    " is not even and in 4.." + std::to_string(kMaxTileSide));
    DemLodLayout l;
    l.width = width;
    l.height = height;
    l.cell = cell;
    l.origin = origin;
    l.blockSide = blockSide;
    const std::int64_t side = std::max(width, height);
    l.levels = 1;
    while ((std::int64_t(blockSide) << (l.levels - 1)) < side) ++l.levels;
    return l;
}

Box DemLodLayout::extent() const {
    return {{origin.x - 0.5 * cell, origin.y - (double(height) - 0.5) * cell},
            {origin.x + (double(width) - 0.5) * cell, origin.y + 0.5 * cell}};
}

int DemLodLayout::levelFor(double spacing) const {
    if (std::isnan(spacing)) throw std::invalid_argument("DemLodLayout::levelFor(): spacing is NaN");
    for (int l = 0; l < levels; ++l)
        if (levelCell(l) <= spacing) return l;
    return levels - 1;
}

std::int64_t DemLodLayout::tileCount() const {
    std::int64_t n = 0;
    for (int l = 0; l < levels; ++l) n += std::int64_t(blockColumns(l)) * std::int64_t(blockRows(l));
    return n;
}

int levelAtMost(const DemLodLayout& layout, int maxSide) {
    if (maxSide < 1) throw std::invalid_argument("levelAtMost(): maxSide " + std::to_string(maxSide) + " < 1");
    for (int l = layout.levels - 1; l > 0; --l)
        if (layout.levelWidth(l) <= maxSide && layout.levelHeight(l) <= maxSide) return l;
    return 0;
}

void inheritFromParent(std::span<float> block, std::span<const float> parent, int col, int row, int blockSide) {
    if (blockSide < 4 || blockSide % 2 != 0)
        throw std::invalid_argument("inheritFromParent(): block side " + std::to_string(blockSide) + " is odd or < 4");
    const std::size_t n = std::size_t(blockSide) * std::size_t(blockSide);
    if (block.size() != n || parent.size() != n)
        throw std::invalid_argument("inheritFromParent(): blocks of " + std::to_string(block.size()) + " and " +
                                    std::to_string(parent.size()) + " samples, " + std::to_string(n) + " expected");
    if (col < 0 || row < 0) throw std::invalid_argument("inheritFromParent(): negative block column or row");
    const std::size_t side = std::size_t(blockSide), half = side / 2;
    const std::size_t ox = std::size_t(col & 1) * half, oy = std::size_t(row & 1) * half;
    for (std::size_t q = 0; q < side; q += 2)
        for (std::size_t m = 0; m < side; m += 2) block[q * side + m] = parent[(oy + q / 2) * side + ox + m / 2];
}

}  // namespace lacet
