// The projected CRS of the tests' hand-made scenes and DEMs: a transverse Mercator on Andorra
// (latitude 42.5, meridian 1.5), as WKT.
#pragma once

namespace lacet {

inline constexpr const char* kWkt =
    "PROJCS[\"Lacet TM\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Transverse_Mercator\"],"
    "PARAMETER[\"latitude_of_origin\",42.5],PARAMETER[\"central_meridian\",1.5],PARAMETER[\"scale_factor\",1],"
    "PARAMETER[\"false_easting\",0],PARAMETER[\"false_northing\",0],UNIT[\"metre\",1]]";

}  // namespace lacet
