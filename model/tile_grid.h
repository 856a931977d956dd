#pragma once
// The tile grid, named once: how many texels and elevation samples the producers make per quad,
// how far their tiles extend beyond the quad (the borders), and from these how far beyond a quad
// its clipped elements must reach so that every border texel and sample sees the elements that
// touch it (adjacent tiles then agree on what they share).
//
// The quadtree clips with these reaches (RefineParams, model/clip_and_refine.h, is a TileGrid
// plus the refinement tolerance) and the producers (raster/appearance_producer.h,
// raster/elevation_producer.h) size their tiles from the quadtree's grid, not from a copy of
// their own: a tile border wider than what the quadtree clips for cannot be built.
//
// validate() is called by the Quadtree constructor.

#include <cmath>
#include <stdexcept>

namespace lacet {

struct TileGrid {
    // Appearance texels per quad side (> 0); the refinement tolerance is measured in them.
    int resolution = 256;
    // Appearance texels drawn outside the quad on each side (>= 0).
    int appearanceBorder = 2;
    // Elevation sample intervals per quad side (even, > 0: z_c is made at half resolution); the
    // tile has elevationResolution + 1 samples per side inside the quad, delta = size / this.
    int elevationResolution = 24;
    // Elevation samples outside the quad on each side (>= 2: the 3x3 filter reads one more).
    int elevationBorder = 2;

    // The widening of an elevation footprint beyond its element (elevation samples): sqrt(2) delta
    // for the bilinear interpolation of the samples and as much again for the 3x3 filter
    // (raster/elevation_producer.h).
    static constexpr double kFootprintWidening = 2.8284271247461903;  // 2 sqrt(2)

    double elevationDelta(double quadSize) const { return quadSize / double(elevationResolution); }  // metres
    // How far beyond an element's footprint the elevation producer reads it, in elevation samples:
    // the footprint widening plus the tile border, rounded up to whole samples (5 for the default
    // border of 2).
    double footprintReach() const { return std::ceil(kFootprintWidening + double(elevationBorder)); }
    // How far beyond the quad the appearance producer draws (metres): its border, and one texel
    // more for the anti-aliasing ramp.
    double appearanceReach(double quadSize) const { return double(appearanceBorder + 1) * quadSize / double(resolution); }

    // Throws std::invalid_argument when a field is out of its range.
    void validate() const {
        if (resolution <= 0 || appearanceBorder < 0 || elevationResolution <= 0 || elevationResolution % 2 != 0 ||
            elevationBorder < 2)
            throw std::invalid_argument(
                "TileGrid: resolution > 0, appearanceBorder >= 0, elevationResolution even and > 0, elevationBorder >= 2 required");
    }
};

}  // namespace lacet
