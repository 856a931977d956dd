#pragma once
// Writing images with OpenImageIO (PNG, TIFF, EXR...: the format follows the file name).

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

}  // namespace lacet
