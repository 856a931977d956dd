#pragma once
// The tiles of a pyramid in memory, as GIS tools see them: a quad's texels inside its bounds (no
// border), rows from the top (north) down, as GeoPackage tiles are; the conversions from the
// producers' tiles, the mipmap of §7, and back to the editor's tiles.
//
// Appearance: RGB and the water mask in two planes (the mask is its own tile table, skipped
// where there is no water). Elevation: the terrain's z_m at the centre of each of the tile's
// elevationResolution^2 cells (the mean of the cell's four corner samples: the bilinear surface
// the editor draws), as a GeoPackage gridded coverage with grid-value-is-center wants.

#include <array>
#include <cstdint>
#include <vector>

#include "model/types.h"
#include "raster/appearance_tile.h"
#include "raster/elevation_tile.h"

namespace lacet {

struct PyramidImage {
    int size = 0;                     // texels per side
    std::vector<std::uint8_t> rgb;    // size * size * 3, rows top first
    std::vector<std::uint8_t> water;  // size * size, 0..255, rows top first
    bool hasWater() const;
    friend bool operator==(const PyramidImage&, const PyramidImage&) = default;
};

// The interior texels of `tile` (uniform tiles included, through tileTexels()).
PyramidImage pyramidImage(const AppearanceTile& tile);

// §7's mipmap: each texel the rounded mean of the 2 x 2 texels of its child below it. `children`
// in Quad::children order (0 lower-left, 1 lower-right, 2 upper-left, 3 upper-right), all of one
// even size. Throws std::invalid_argument otherwise. It is assemble() of each child's halve().
PyramidImage mipmap(const std::array<const PyramidImage*, 4>& children);
// An image at half its size, each texel the rounded mean of 2 x 2 (an even size is required).
PyramidImage halve(const PyramidImage& image);
// The parent's image from its four children at half size (Quad::children order), each in its
// quadrant: the build passes what it reads back from the stored tiles (io/tile_codec.h's
// decodeImageHalf for a lossy encoding), so that an update gives the same bytes.
PyramidImage assemble(const std::array<const PyramidImage*, 4>& halves);

// An editor's tile of a quad from its pyramid image: the texels inside, the `border` around them
// repeating the edge texels (a pyramid tile holds nothing outside its quad).
AppearanceTile appearanceTile(const PyramidImage& image, const Box& bounds, int border);

struct ElevationCells {
    int size = 0;              // cells per side (the tile's elevation resolution)
    std::vector<float> z;      // size * size, metres, rows top first
    double min = 0.0, max = 0.0, mean = 0.0, stdDev = 0.0;  // of z (the gridded tile ancillary's statistics)
};

ElevationCells elevationCells(const ElevationTile& tile);

}  // namespace lacet
