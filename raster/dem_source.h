#pragma once
// The DEM a batch command reads (the pyramid build, render, the checks): the heights the
// z-profiles and point checks sample, and the DEM each quad's producers read. In memory, one DEM
// for both (InMemoryDem); a LOD tree read within a memory budget gives each quad its window at
// the level the quad needs and the profiles one fixed level (io/dem_stream.h: StreamedDem), as
// the editor reads it.

#include <memory>

#include "model/curve_data.h"
#include "model/quadtree.h"
#include "raster/dem.h"
#include "raster/dem_height_field.h"

namespace lacet {

class DemSource {
public:
    virtual ~DemSource() = default;
    virtual const HeightField& heights() const = 0;
    // The DEM quad q's producers read. Any thread may call it; the result stays valid while held.
    virtual std::shared_ptr<const Dem> quadDem(const Quad& q) const = 0;
};

// A DEM in memory (which must outlive it) for every quad.
class InMemoryDem final : public DemSource {
public:
    explicit InMemoryDem(const Dem& dem) : dem_(dem), heights_(dem) {}
    const HeightField& heights() const override { return heights_; }
    std::shared_ptr<const Dem> quadDem(const Quad&) const override { return std::shared_ptr<const Dem>(std::shared_ptr<const Dem>(), &dem_); }

private:
    const Dem& dem_;
    DemHeightField heights_;
};

}  // namespace lacet
