#pragma once
// The synthetic DEM finer than memory (issue 16: `lacet synth --dem-side`), made row by row: the
// in-memory synthetic DEM (synth/synthetic_dem.h, 20 m cells) as the base, sampled bicubically
// (Dem::sample) at each fine sample, plus deterministic fine detail: value noise of wavelengths
// shortestWavelength to longestWavelength metres (octaves halving the wavelength and the amplitude),
// of about `amplitude` metres, faded to 0 near the rivers so that they still run downhill.
//
// Near the rivers. The distance to the river curves (the scene's LayerKind::Rivers layers) is kept
// on a coarse grid of `distanceCell` metres (each cell centre's distance to the curves sampled every
// distanceCell / 2 metres, capped at 2 riverFade + 3.5 distanceCell); at a fine sample it is
// interpolated bilinearly and lowered by 1.75 distanceCell (a lower bound of the true distance: the
// field is 1-Lipschitz and the corners read are within a cell diagonal, the curves' samples at most
// distanceCell / 4 from them). The detail is 0 where that bound is
// within riverFade of a river and full beyond 2 riverFade (smoothstep between). Along a river and
// in its valley floor the fine DEM is then the base sampled, and rises as the base does (its
// tolerance: synth/synthetic_dem.h), up to the Catmull-Rom of fine samples of it.
//
// Grid: side x side samples over the scene's square extent, sample (i, t) (column i from the west,
// row t from the NORTH, the order a DEM LOD tree is written in) at the centre of its cell:
// extent.min.x + (i + 0.5) cell, extent.max.y - (t + 0.5) cell, cell = extent width / side.
// Deterministic: the same scene, base and parameters give bit-identical rows, in any order, on any
// thread (integer hashing, a fixed order of floating-point operations).
//
// Units: metres.

#include <cstdint>
#include <span>
#include <vector>

#include "model/graph.h"
#include "raster/dem.h"

namespace lacet {

struct FineDemParams {
    int side = 20480;                  // samples a side over the extent, >= 2 (20480: 5 m cells over 100 km)
    std::uint64_t seed = 1;            // of the detail
    double amplitude = 2.0;            // metres, > 0: the detail's largest excursion, about
    double shortestWavelength = 20.0;  // metres, > 0
    double longestWavelength = 200.0;  // metres, >= shortestWavelength
    double riverFade = 100.0;          // metres, >= 0: no detail this close to a river, full detail at twice it
    double distanceCell = 50.0;        // metres, > 0: the cell of the distance-to-rivers grid
};

class FineSyntheticDem {
public:
    // Keeps a reference to `base` (which must outlive this). Throws std::invalid_argument naming
    // FineDemParams for a parameter out of range or a non-square extent.
    FineSyntheticDem(const Scene& scene, const Dem& base, const FineDemParams& params);

    int side() const { return params_.side; }
    double cell() const { return cell_; }          // metres
    Vec2 topLeft() const;                          // the centre of sample (0, 0), scene metres
    Vec2 position(int i, int t) const;             // of sample (i, t), scene metres
    // Row t (0 = north) into heights (side() values, metres). Thread-safe.
    void row(int t, std::span<float> heights) const;
    // The detail's weight at p (0 near rivers, 1 away from them), for tests.
    double fade(Vec2 p) const;
    // The detail alone at p (metres, before the fade).
    double detail(Vec2 p) const;

private:
    const Dem& base_;
    FineDemParams params_;
    Box extent_;
    double cell_ = 0.0;
    // Distance to rivers at the coarse grid's cell centres, metres (capped).
    int dw_ = 0, dh_ = 0;
    std::vector<float> distance_;
    std::vector<double> wavelengths_, amplitudes_;
};

}  // namespace lacet
