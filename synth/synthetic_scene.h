#pragma once
// Deterministic, seeded synthetic scenes with the density of the paper's test dataset (§9: a
// 100 x 100 km^2 area with about 600k curves, 190k areas and 940k nodes and control points,
// most of them fields). Used by tests, benchmarks and the sample app when no real GIS data is
// at hand.
//
// Units: metres, in a square extent with min = (0, 0) and side syntheticExtentSide(curves).
// Generated layers, always in this order (some empty for very small targets):
//   roads   - a network over a jittered grid of junctions (~1.5 km apart), cubic Bezier curves
//             (some made of two pieces), 3-way and 4-way junctions, classes 0 primary, 1
//             secondary, 2 track;
//   rivers  - a few tree-shaped systems flowing out of the extent, curves oriented downstream
//             (start = upstream node), tributaries joining at nodes, widths 2..20 m growing
//             downstream;
//   lakes   - smooth areas bounded by 3..6 curves, at least one with an island (hole);
//   fields  - patches of 2x2 (mostly) or 3x3 parcels whose neighbours share border curves,
//             placed in the road-free blocks away from rivers, lakes and forests; cls = crop;
//   forests - smooth areas bounded by 2..4 curves, a few with a clearing (hole).
// Fields take whatever is left of the curve budget, so the total number of curves is the
// target within a few curves. The same seed always gives a bit-identical scene.

#include <cstdint>
#include <functional>
#include <memory>

#include "model/graph.h"

namespace lacet {

struct SyntheticParams {
    std::uint64_t seed = 1;
    std::size_t curves = 600000;  // target number of curves; the extent scales so that density stays that of the paper's dataset
    // Fraction of the road junctions of degree 3 or more made roundabouts (of radius 10 to 18 m,
    // where roundaboutRefusal() lets them fit), as in Fig. 14 middle. Rivers grow across roads,
    // so the graph step finds crossings (about 1,500 bridges at 600k curves).
    double roundaboutFraction = 0.03;
};

// Side (metres) of the square extent for a given curve count: 100 km at 600k curves, scaled by
// sqrt(curves/600k). A count of 0 is treated as 1 (the extent is never empty).
double syntheticExtentSide(std::size_t curves);

Scene makeSyntheticScene(const SyntheticParams& params);

// The same scene made a part at a time, for scenes larger than memory (lacet synth --out): the
// constructor makes every layer but the fields' elements (roads, rivers, lakes, forests, the
// roundabouts); fields() then hands the fields layer (kFieldsLayer) to `sink` in parts (model/graph.h:
// whole patches, about `partCurves` curves each), in id order. The scene with its parts appended
// (appendLayerPart) is makeSyntheticScene(params), bit for bit. Memory: the other layers (a few
// percent of the curves), the fields' slot plan and one part.
class SyntheticSceneParts {
public:
    explicit SyntheticSceneParts(const SyntheticParams& params);
    ~SyntheticSceneParts();
    // The scene made by the constructor (its fields layer empty), moved out.
    Scene takeScene();
    // Once (std::logic_error after); may follow takeScene().
    void fields(const std::function<void(Layer&& part)>& sink, std::size_t partCurves);

private:
    struct State;
    std::unique_ptr<State> state_;
};

// Fixed layer order of synthetic scenes:
constexpr LayerId kRoadsLayer = 0, kRiversLayer = 1, kLakesLayer = 2, kFieldsLayer = 3, kForestsLayer = 4;

}  // namespace lacet
