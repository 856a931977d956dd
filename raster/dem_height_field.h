#pragma once
// A Dem seen as the HeightField the curve data (z-profiles) samples.

#include "model/curve_data.h"
#include "raster/dem.h"

namespace lacet {

class DemHeightField : public HeightField {
public:
    explicit DemHeightField(const Dem& dem) : dem_(dem) {}
    double height(Vec2 p) const override { return dem_.sample(p); }

private:
    const Dem& dem_;
};

}  // namespace lacet
