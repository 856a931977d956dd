// libFuzzer target: arbitrary bytes as a pyramid file (GeoPackage) through checkPyramid (every tile
// decoded: the JPEG, PNG and float TIFF decoders) and the editor's PyramidReader. Every input must
// be reported or throw PyramidError, never crash. Seeds: a small pyramid built at run time. Run:
// scripts/fuzz.sh.
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "pyramid/pyramid_check.h"
#include "pyramid/pyramid_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = "/tmp/lacet_fuzz_pyramid_" + std::to_string(::getpid()) + ".gpkg";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    try {
        const lacet::PyramidCheck c = lacet::checkPyramid(path);
        lacet::PyramidReader reader(path, c.info.extent, c.info.crsWkt);
        (void)reader;
    } catch (const lacet::PyramidError&) {
    }
    return 0;
}
