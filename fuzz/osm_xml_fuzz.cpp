// libFuzzer target: arbitrary bytes as an OpenStreetMap XML file through the vector reader
// (fuzz/vector_fuzz.h: GDAL's OSM driver, the mapping's OSM rules). Seeds: a small extract made at
// run time; dictionary fuzz/osm_xml.dict. Run: scripts/fuzz.sh.
#include "vector_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return lacet::fuzz::readVectorBytes(data, size, ".osm");
}
