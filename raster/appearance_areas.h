#pragma once
// Internal to the appearance producer: areas (lakes, fields, forests; §5.1), their surface
// inside and the border strip of width wf outside.

#include "raster/appearance_canvas.h"
#include "raster/appearance_producer.h"
#include "raster/appearance_shading.h"

namespace lacet::appearance {

// Every texel of the canvas at coverage 1 (an area covering the quad), block by block; also how a
// uniform tile's texels are made (tileTexels), so the two agree bit for bit.
void shadeWhole(Canvas& canvas, SurfaceShader& shader);

// Draws a piece of an area over the canvas: its triangles (area_triangulation.h) flag the
// pixels inside; block by block, a pixel farther than a pixel from the real border takes the
// surface's colour, a nearer one blends it by coverage over the border strip.
void drawArea(Canvas& canvas, const AppearanceTile& t, const ClippedArea& area, const SurfaceShade& shade, double wf,
              AppearanceCounters* counters);

}  // namespace lacet::appearance
