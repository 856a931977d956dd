#include "io/scene_frame.h"

#include <cmath>
#include <cstdio>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/TransverseMercator.hpp>

namespace lacet {
namespace {

const GeographicLib::TransverseMercator& projection() {
    static const GeographicLib::TransverseMercator tm(GeographicLib::Constants::WGS84_a(), GeographicLib::Constants::WGS84_f(), 1.0);
    return tm;
}

double northing(double lon0, double lat0) {
    double x = 0.0, y = 0.0;
    projection().Forward(lon0, lat0, lon0, x, y);
    return y;
}

}  // namespace

SceneFrame::SceneFrame(double lon0, double lat0) {
    g_.valid = true;
    g_.lon0 = lon0;
    g_.lat0 = lat0;
    y0_ = northing(lon0, lat0);
}

SceneFrame::SceneFrame(const Georeference& g) : g_(g), y0_(northing(g.lon0, g.lat0)) {}

Vec2 SceneFrame::forward(glm::dvec2 lonLat) const {
    double x = 0.0, y = 0.0;
    projection().Forward(g_.lon0, lonLat.y, lonLat.x, x, y);
    return Vec2(x, y - y0_) + g_.originShift;
}

glm::dvec2 SceneFrame::reverse(Vec2 scene) const {
    const Vec2 p = scene - g_.originShift;
    double lat = 0.0, lon = 0.0;
    projection().Reverse(g_.lon0, p.x, p.y + y0_, lat, lon);
    return {lon, lat};
}

double SceneFrame::scale(Vec2 scene) const {
    const Vec2 p = scene - g_.originShift;
    double lat = 0.0, lon = 0.0, gamma = 0.0, k = 1.0;
    projection().Reverse(g_.lon0, p.x, p.y + y0_, lat, lon, gamma, k);
    return k;
}

double SceneFrame::largestScaleError(const Box& box) const {
    double worst = 0.0;
    for (int j = 0; j <= 32; ++j)
        for (int i = 0; i <= 32; ++i)
            worst = std::max(worst, std::abs(scale(box.min + box.size() * Vec2(i / 32.0, j / 32.0)) - 1.0));
    return worst;
}

// OGC WKT of the frame's CRS: a transverse Mercator whose false easting and northing carry the
// shift (and the northing of the centre), so GIS tools place the scene where it is.
void SceneFrame::setOriginShift(Vec2 shift) {
    g_.originShift = shift;
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "PROJCS[\"Lacet scene (transverse Mercator on WGS84)\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\","
                  "SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
                  "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"latitude_of_origin\",0],PARAMETER[\"central_meridian\",%.17g],"
                  "PARAMETER[\"scale_factor\",1],PARAMETER[\"false_easting\",%.17g],PARAMETER[\"false_northing\",%.17g],"
                  "UNIT[\"metre\",1]]",
                  g_.lon0, shift.x, shift.y - y0_);
    g_.crsWkt = buf;
}

}  // namespace lacet
