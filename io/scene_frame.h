#pragma once
// The scene's projected CRS (io/georeference.h): a transverse Mercator projection of the WGS84
// ellipsoid with scale 1 on its central meridian, centred on the data (GeographicLib's exact
// series, accurate to nanometres within thousands of km of the centre). Scene coordinates are the
// projected metres plus `originShift`, so that the scene's extent starts at (0, 0).

#include <string>

#include <glm/vec2.hpp>

#include "io/georeference.h"

namespace lacet {

class SceneFrame {
public:
    // A frame centred on (lon0, lat0) degrees, with no shift yet.
    SceneFrame(double lon0, double lat0);
    explicit SceneFrame(const Georeference& g);

    // Scene metres of a (lon, lat) point in degrees, and back.
    Vec2 forward(glm::dvec2 lonLat) const;
    glm::dvec2 reverse(Vec2 scene) const;
    // Point scale factor at a scene point (1 on the central meridian, growing away from it).
    double scale(Vec2 scene) const;
    // The largest |scale - 1| over `box` (sampled on a 33 x 33 grid; it grows monotonically with
    // the distance from the central meridian, so the grid's edge columns bound it).
    double largestScaleError(const Box& box) const;

    // Sets the shift and the WKT of the georeference.
    void setOriginShift(Vec2 shift);
    const Georeference& georeference() const { return g_; }

private:
    Georeference g_;
    double y0_ = 0.0;  // northing of lat0 on the central meridian
};

}  // namespace lacet
