#pragma once
// The body of the vector readers' libFuzzer targets: arbitrary bytes as a file of the given
// extension (the driver OGR picks by it) through readVectors (OGR, the mapping, the per-feature
// checks). Every input must end in a report or a VectorImportError, never a crash or a sanitizer
// report.
#include <cstdint>
#include <string>

#include <cpl_vsi.h>

#include "io/vector_import.h"

namespace lacet::fuzz {

inline int readVectorBytes(const std::uint8_t* data, std::size_t size, const std::string& extension) {
    static const FeatureMapping mapping = defaultMapping();
    const std::string path = "/vsimem/fuzz" + extension;
    VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(data), vsi_l_offset(size), FALSE);
    if (!f) return 0;
    VSIFCloseL(f);
    try {
        VectorData out;
        readVectors(path, mapping, out);
    } catch (const VectorImportError&) {
    }
    VSIUnlink(path.c_str());
    return 0;
}

}  // namespace lacet::fuzz
