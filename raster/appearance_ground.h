#pragma once
// Internal to the appearance producer: the ground under everything (§5.1), its colour by
// altitude and slope.

#include "raster/appearance_canvas.h"
#include "raster/dem.h"

namespace lacet::appearance {

// Fills the whole canvas with the ground's colour, bilinear between the nodes of a grid of
// `cells` x `cells` cells over the quad (DEM height and slope at each node); nodes beyond the
// DEM's extent take kNoDataGround (raster/appearance_shading.h).
void drawGround(Canvas& canvas, const AppearanceTile& t, const Dem& dem, int cells);

}  // namespace lacet::appearance
