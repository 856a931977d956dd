#pragma once
// Roundabouts (§4.3, Fig. 5 right): a node of a Roads layer whose `roundabout` radius is > 0 is
// replaced, in the graph step (model/graph_step.h), by a ring of arc curves between the roads
// that meet there. Each road ending at the node is trimmed where it enters the ring (its first
// crossing of the circle of that radius around the node) and carries the ring's arc from its
// entry counter-clockwise to the next road's entry, so that every arc has exactly one root curve
// and the ring moves with the node.
//
// A radius that does not fit is refused by roundaboutRefusal() (and by the edit that sets it):
// a connected road that does not leave the circle, or two roads entering within the same arc
// (closer than `minEntrySeparation` along the ring).

#include <optional>
#include <string>
#include <vector>

#include "model/procedural.h"

namespace lacet {

struct RoundaboutParams {
    double minEntrySeparation = 4.0;  // m along the ring between two roads' entries, > 0
    double maxRadius = 500.0;         // m, the largest ring radius accepted (larger is a typing error), > 0
};

// What the graph step does to one road curve at its end nodes' rings.
struct RoundaboutCut {
    double s0 = 0.0, s1 = 0.0;  // the kept part of the root curve (root parameter s)
    bool trimmedStart = false, trimmedEnd = false;
    // The ring arcs this curve carries (flags kRoundabout, ringAtStart == ringAtEnd == the node,
    // rootS0/rootS1 NaN, w/wf/cls of the ring: those of the widest road at the node).
    std::vector<ProceduralCurve> arcs;
};

// nullopt when neither end node of road curve `curve` is a roundabout that fits.
std::optional<RoundaboutCut> roundaboutCut(const Scene& scene, LayerId layer, ElementId curve,
                                           const RoundaboutParams& params = {});
// Width w (m) of the ring at `node`: that of the widest road there (0 for a dead or out-of-range
// node, or one without roads). The appearance stops a road's markings half of it from the ring's
// centre line, where its yield line begins.
float roundaboutRingWidth(const Layer& layer, ElementId node);
// Why a roundabout of `radius` metres cannot be made at `node` (nullopt when it can; radius 0
// always can: it removes the roundabout).
std::optional<std::string> roundaboutRefusal(const Scene& scene, LayerId layer, ElementId node, float radius,
                                             const RoundaboutParams& params = {});

}  // namespace lacet
