#include "io/image_file.h"

#include <OpenImageIO/imageio.h>

namespace lacet {

void writeImage8(const std::string& path, int width, int height, int channels, const std::vector<std::uint8_t>& pixels) {
    if (width <= 0 || height <= 0 || channels <= 0 || pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels))
        throw ImageFileError(path + ": image size and pixel buffer do not match");
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw ImageFileError(path + ": no image format for this file name (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (!out->open(path, spec)) throw ImageFileError(path + ": cannot open for writing (" + out->geterror() + ")");
    if (!out->write_image(OIIO::TypeDesc::UINT8, pixels.data()) || !out->close())
        throw ImageFileError(path + ": write failed (" + out->geterror() + ")");
}

}  // namespace lacet
