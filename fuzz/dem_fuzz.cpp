// libFuzzer target: arbitrary bytes as a DEM raster (GeoTIFF or anything GDAL opens) through the
// DEM import: demSourceInfo (the file checked: CRS, size, nodata) then importDem of a 1 km square
// at its centre (window read, voids filled, resampled). Every input must import or throw
// DemImportError, never crash. Seeds: tiles cut from the Andorra SRTM at run time. Run:
// scripts/fuzz.sh.
#include <cstdint>
#include <string>

#include <cpl_vsi.h>

#include "io/dem_import.h"
#include "io/scene_frame.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = "/vsimem/fuzz_dem.tif";
    VSILFILE* f = VSIFileFromMemBuffer(path.c_str(), const_cast<GByte*>(data), vsi_l_offset(size), FALSE);
    if (!f) return 0;
    VSIFCloseL(f);
    try {
        const lacet::DemSourceInfo info = lacet::demSourceInfo({path});
        const lacet::Vec2 c = info.lonLat.center();
        if (info.lonLat.size().x < 20.0 && info.lonLat.size().y < 20.0 && std::abs(c.y) < 80.0) {
            lacet::SceneFrame frame(c.x, c.y);
            const lacet::Vec2 o = frame.forward(c);
            frame.setOriginShift(-(o - 500.0));
            lacet::DemImportReport report;
            (void)lacet::importDem(info, frame, {{0.0, 0.0}, {1000.0, 1000.0}}, 50.0, report);
        }
    } catch (const lacet::DemImportError&) {
    }
    VSIUnlink(path.c_str());
    return 0;
}
