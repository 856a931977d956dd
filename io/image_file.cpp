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

Image8 readImage8(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw ImageFileError(path + ": cannot read (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = in->spec();
    Image8 image{spec.width, spec.height, spec.nchannels, {}};
    image.pixels.resize(std::size_t(spec.width) * std::size_t(spec.height) * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, image.pixels.data()))
        throw ImageFileError(path + ": read failed (" + in->geterror() + ")");
    in->close();
    return image;
}

}  // namespace lacet
