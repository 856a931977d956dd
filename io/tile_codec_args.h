#pragma once
// Private to io/: the argument check the tile encoders share (io/tile_codec.cpp, io/float_tiff.cpp).

#include <cstddef>
#include <stdexcept>
#include <string>

#include "io/tile_codec.h"

namespace lacet {

// Throws std::invalid_argument naming `function` unless 1 <= width, height <= kMaxTileSide and
// `size` is width * height * channels.
inline void checkImageArgs(const char* function, std::size_t size, int width, int height, int channels) {
    if (width < 1 || height < 1 || width > kMaxTileSide || height > kMaxTileSide)
        throw std::invalid_argument(std::string(function) + ": width and height must be in 1.." +
                                    std::to_string(kMaxTileSide) + ", got " + std::to_string(width) + " x " +
                                    std::to_string(height));
    if (size != std::size_t(width) * std::size_t(height) * std::size_t(channels))
        throw std::invalid_argument(std::string(function) + ": expected width * height * " + std::to_string(channels) +
                                    " values, got " + std::to_string(size));
}

}  // namespace lacet
