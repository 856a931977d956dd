// libFuzzer target: arbitrary bytes as a mapping file (io/feature_mapping.h) through parseMapping.
// Every input must give a mapping or a MappingError naming the reason, never a crash. Seeds: the
// default mapping and the test mappings. Run: scripts/fuzz.sh.
#include <cstdint>
#include <string>

#include "io/feature_mapping.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        (void)lacet::parseMapping(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
    } catch (const lacet::MappingError&) {
    }
    return 0;
}
