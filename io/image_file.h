#pragma once
// Reading and writing images with OpenImageIO (PNG, TIFF, EXR...: the format follows the file name).

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace lacet {

class ImageFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Writes `pixels` (width x height x channels bytes, rows from the top) to `path`. Throws
// ImageFileError naming the file and OpenImageIO's reason.
void writeImage8(const std::string& path, int width, int height, int channels, const std::vector<std::uint8_t>& pixels);

struct Image8 {
    int width = 0, height = 0, channels = 0;
    std::vector<std::uint8_t> pixels;  // rows from the top
};

// Reads an 8-bit image (other formats are converted). Throws ImageFileError naming the file and
// OpenImageIO's reason.
Image8 readImage8(const std::string& path);

}  // namespace lacet
