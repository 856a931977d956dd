#pragma once
// The procedural step of SUBDIVIDE (Alg. 4.1, §4.3): the interface the quadtree calls at the root,
// and the procedural curves it makes. A root curve may be replaced by procedural curves (a road
// cut into road, bridge and road pieces where it crosses a river, trimmed at a roundabout's ring
// and carrying the ring's arcs); each is an ancestor in its own right (AncestorId with
// kProceduralBit, proceduralId() in model/quadtree.h).
//
// Besides its geometry, a procedural curve says what the curve data (model/curve_data.h) and the
// object meshes need to know of it: the part of its root curve it follows (its z-profile is that
// part of the root's, so the pieces of a road meet at one height), the crossings a bridge spans
// (its deck clears their water), and the roundabout node at either end.

#include <cmath>
#include <limits>
#include <vector>

#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

// A crossing a bridge spans: the crossed ancestor curve (a river, or a road under a road bridge).
struct BridgeSpan {
    LayerId layer = 0;
    AncestorId over = 0;    // the crossed curve
    double overS = 0.0;     // the crossing's parameter s on the crossed curve
    double u = 0.0;         // the crossing's arc length along the bridge (m)
    double halfLength = 0.0;  // m along the bridge on either side of u that must clear the crossed footprint
    friend bool operator==(const BridgeSpan&, const BridgeSpan&) = default;
};

struct ProceduralCurve {
    Curve curve;  // geometry and attributes; kBridge on a bridge, kRoundabout on a ring arc, kYieldAt*
    // The part of the root curve it follows, as root parameters (on-curve vertex k at s = k), so
    // that rootS0 <= rootS1; NaN for a curve that follows no part of it (a ring arc).
    double rootS0 = std::numeric_limits<double>::quiet_NaN();
    double rootS1 = std::numeric_limits<double>::quiet_NaN();
    std::vector<BridgeSpan> spans{};  // a bridge's crossings, by u
    ElementId ringAtStart = kNoElement;  // the roundabout node whose ring the curve starts on
    ElementId ringAtEnd = kNoElement;    // ... ends on (both for a ring arc)
    bool followsRoot() const { return !std::isnan(rootS0); }
    friend bool operator==(const ProceduralCurve&, const ProceduralCurve&) = default;
};

// A graph transformation applied when the root is subdivided (§4.3). Its expansion of a root
// curve must be a pure function of the scene (the same scene always gives the same curves), and
// update() must tell UPDATE every other root curve whose expansion an edit changed.
class ProceduralStep {
public:
    virtual ~ProceduralStep() = default;
    // Fills `out` with the curves replacing root curve `id` and returns true, or returns false to
    // keep the curve as it is. Fewer than kMaxProceduralCurves curves per root curve. Called from
    // one thread at a time.
    virtual bool expand(const Scene& scene, LayerId layer, ElementId id, std::vector<ProceduralCurve>& out) const = 0;
    // Called by UPDATE with each changeset, after the scene was edited and before any expansion:
    // appends the root curves (ElementKind::Curve refs) whose expansion reads an element the
    // changeset changed besides themselves (a road's bridges read the rivers it crosses), so that
    // UPDATE expands them again; a step that indexes the scene updates its index here.
    virtual void update(const Scene& scene, const Changeset& changeset, std::vector<ElementRef>& out) {
        (void)scene, (void)changeset, (void)out;
    }
};

}  // namespace lacet
