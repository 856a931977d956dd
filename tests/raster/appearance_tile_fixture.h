#pragma once
// A bare appearance tile and its canvas for the reference tests of the drawing passes
// (appearance_segments_test, appearance_curves_test, appearance_areas_test).

#include "raster/appearance_canvas.h"

namespace lacet::test {

// A tile of `resolution` texels over the square [origin, origin + size]^2 (metres), with a border
// of `border` texels, drawn at `samples` x `samples` pixels a texel.
inline AppearanceTile bareTile(Vec2 origin, double size, int resolution, int border, int samples) {
    AppearanceTile t;
    t.bounds = {origin, origin + Vec2(size)};
    t.resolution = resolution;
    t.border = border;
    t.stride = resolution + 2 * border;
    t.samples = samples;
    t.delta = size / double(resolution);
    return t;
}

}  // namespace lacet::test
