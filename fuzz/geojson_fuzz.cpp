// libFuzzer target: arbitrary bytes as a GeoJSON file through the vector reader (fuzz/vector_fuzz.h).
// Run: scripts/fuzz.sh (README, developer section).
#include "vector_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return lacet::fuzz::readVectorBytes(data, size, ".geojson");
}
