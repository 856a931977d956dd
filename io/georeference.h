#pragma once
// Where a scene lies on the Earth: its projected CRS and extent. Scene coordinates are metres in a
// transverse Mercator projection (WGS84 ellipsoid, scale 1 on the central meridian) centred on
// (lon0, lat0): the scene point (x, y) is originShift + the projection of (lon, lat), so that
// the scene's extent starts at (0, 0). Synthetic scenes have no georeference (`valid` false).

#include <string>

#include "model/types.h"

namespace lacet {

struct Georeference {
    bool valid = false;
    double lon0 = 0.0, lat0 = 0.0;  // degrees: the projection's centre
    Vec2 originShift{0.0};          // metres added to projected coordinates to get scene coordinates
    std::string crsWkt;             // the same CRS as OGC WKT (for the scene file and GIS tools)
    friend bool operator==(const Georeference&, const Georeference&) = default;
};

}  // namespace lacet
