#pragma once
// Pictures of elevation tiles, for looking at them: a hillshade of z_m and the footprint b.
// Each tile gives resolution x resolution pixels (elevation: its samples 0 .. resolution-1 on
// both axes, the last row and column belonging to the next tile; appearance: its texels), RGB, rows from north (top) to south.

#include <cstdint>
#include <vector>

#include "raster/appearance_tile.h"
#include "raster/elevation_tile.h"

namespace lacet {

// Lambert shading of z_m lit from the north-west, 45 degrees up, tinted by altitude.
void hillshade(const ElevationTile& t, std::vector<std::uint8_t>& rgb);
// The footprint: b in red over a dimmed hillshade, so roads, rivers and lakes show where they
// flatten the terrain.
void footprintImage(const ElevationTile& t, std::vector<std::uint8_t>& rgb);
// The appearance colour (uniform tiles expanded), without the border texels.
void appearanceImage(const AppearanceTile& t, std::vector<std::uint8_t>& rgb);

}  // namespace lacet
