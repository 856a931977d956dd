// libFuzzer target: arbitrary bytes as an OpenStreetMap PBF file through the vector reader
// (fuzz/vector_fuzz.h). Seeds: cuts of the Andorra extract made at run time. Run: scripts/fuzz.sh.
#include "vector_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return lacet::fuzz::readVectorBytes(data, size, ".osm.pbf");
}
