// libFuzzer target: arbitrary bytes as a scene file (SQLite/GeoPackage) through loadScene and
// loadSceneRegion (a region around the extent's centre, through the feature index and R-trees).
// Every input must load or throw SceneFileError, never crash or trip a sanitizer. Seeds: scene files
// written by `lacet synth --out`. Run: scripts/fuzz.sh (README, developer section).
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "io/scene_file.h"
#include "io/scene_region.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string path = "/tmp/lacet_fuzz_scene_" + std::to_string(::getpid()) + ".gpkg";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    }
    try {
        (void)lacet::loadScene(path);
    } catch (const lacet::SceneFileError&) {
    }
    try {
        (void)lacet::loadSceneRegion(path, {{4000.0, 4000.0}, {4500.0, 4500.0}}, {}, 6);
    } catch (const lacet::SceneFileError&) {
    }
    return 0;
}
