// libFuzzer target: arbitrary bytes as a GeoJSON file through the vector reader (OGR + mapping +
// per-feature checks). Every input must end in a report or a VectorImportError, never a crash or
// a sanitizer report. Run: scripts/fuzz.sh (README, developer section).
#include <cstdint>
#include <string>

#include <cpl_vsi.h>

#include "io/vector_import.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const lacet::FeatureMapping mapping = lacet::defaultMapping();
    const std::string path = "/vsimem/fuzz.geojson";
    VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(data), vsi_l_offset(size), FALSE);
    if (!f) return 0;
    VSIFCloseL(f);
    try {
        lacet::VectorData out;
        lacet::readVectors(path, mapping, out);
    } catch (const lacet::VectorImportError&) {
    }
    VSIUnlink(path.c_str());
    return 0;
}
