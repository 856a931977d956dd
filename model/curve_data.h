#pragma once
// Curve data on ancestors (§5.1, §5.2): the curvilinear coordinate u and the z-profile of an
// ancestor curve, computed only when a producer asks for them, cached per ancestor, and dropped
// when an edit touches what they were computed from.
//
// u(s): the arc length (metres) from the ancestor's start to its point of parameter s (k + t on
// its k-th piece; ClippedCurve::s gives s for every clipped vertex), so u is continuous across
// every clipped piece of the curve.
//
// z-profile: the height field sampled every `sampleSpacing` metres along the ancestor, smoothed by
// a kernel of half-width `kernelRadius`; then
// - every curve meeting at a node has the node's one height there: the node height is the mean
//   height over a disc of radius `kernelRadius` around it (for a river node: the lowest terrain at
//   it and along the river curves flowing into it, the valley floor), and the profile is pulled to
//   it near the ends (linearly over `kernelRadius`);
// - rivers (LayerKind::Rivers) flow from start to end and never rise: a river node is no higher
//   than any river node upstream of it, and the profile is no higher than the terrain under it,
//   then the running minimum, clamped between its end nodes' heights;
// - lakes (areas of LayerKind::Lakes) are flat at the lowest height of their border;
// - a procedural curve (model/procedural.h) follows the part of its root curve's profile it was
//   cut from, so a road's pieces meet at one height; a road trimmed at a roundabout meets the ring
//   at its node's height, and a ring arc is level with it;
// - a bridge (kBridge) runs straight between its ends, never under the terrain profile it
//   replaces, and rises where it must so that its underside (road surface less the graph step's
//   deckThickness) stands `clearance` above the profile of every curve it spans; when that
//   profile is dropped (an edit upstream of a river), the deck's is dropped with it.
//
// Order of calls: construct over a Quadtree (for ancestor curves) and a HeightField; ask u(),
// zProfile(), nodeHeight(), lakeLevel() from any number of threads; after each edit call
// invalidate(changeset) (before Quadtree::update or after; it only drops cached data).

#include <atomic>
#include <memory>
#include <mutex>
#include <set>
#include <unordered_map>
#include <vector>

#include "model/changeset.h"
#include "model/quadtree.h"

namespace lacet {

// Terrain height (metres) at a point of the scene (metres), e.g. a DEM.
class HeightField {
public:
    virtual ~HeightField() = default;
    virtual double height(Vec2 p) const = 0;
};

// Accuracy knobs of z-profiles.
struct ZProfileParams {
    double sampleSpacing = 10.0;  // metres between height samples along a curve, > 0
    double kernelRadius = 40.0;   // metres, half-width of the triangular smoothing kernel, >= 0
    double arcLengthTolerance = 1e-4;  // metres, accuracy of u
};

struct ZProfile {
    double length = 0.0;    // arc length of the ancestor (m)
    double spacing = 0.0;   // metres between samples (<= sampleSpacing; the last sample is at the end)
    std::vector<double> z;  // heights at u = i * spacing
    double at(double u) const;  // linear interpolation, clamped to the ends
};

struct CurveDataCounters {
    std::atomic<std::size_t> arcLengthTables{0};  // ancestors whose u table was computed
    std::atomic<std::size_t> zProfiles{0};        // z-profiles computed
    std::atomic<std::size_t> nodeHeights{0};
    std::atomic<std::size_t> lakeLevels{0};
};

class CurveDataCache {
public:
    CurveDataCache(const Quadtree& quadtree, const HeightField& heights, ZProfileParams params = {});

    double u(LayerId layer, AncestorId ancestor, double s) const;
    double length(LayerId layer, AncestorId ancestor) const;
    const ZProfile& zProfile(LayerId layer, AncestorId ancestor) const;
    double nodeHeight(LayerId layer, ElementId node) const;
    double lakeLevel(LayerId layer, ElementId area) const;
    // The water a bridge span stands over: the crossed curve's profile at the crossing, the
    // highest within a sample spacing of it (what a deck's lift clears).
    double spanWater(const BridgeSpan& span) const;
    // Where a curve's terrain is sampled for its z-profile: sampleSpacing apart (at most) in arc
    // length along a dense polyline, one point per ZProfile::z entry.
    std::vector<Vec2> samplePoints(LayerId layer, AncestorId ancestor) const;

    // Drops what the changeset touches: its curves, nodes and areas, the procedural curves of its
    // curves, and for rivers everything downstream of a touched river node or curve. Returns the
    // root curves whose computed z-profile, or that of a procedural curve made from them, was
    // dropped: tiles made with it are stale even where the quad's graph did not change (a river
    // downstream of an edit). A root curve's procedural curves are found among the cached ones
    // (by their id range, proceduralId()), not in the quadtree, so this may run before or after
    // Quadtree::update.
    std::vector<ElementRef> invalidate(const Changeset& changeset);

    const CurveDataCounters& counters() const { return counters_; }
    const ZProfileParams& params() const { return params_; }

private:
    struct Key {
        LayerId layer;
        AncestorId id;  // an ancestor curve's, or a root node's or area's ElementId
        friend bool operator==(const Key&, const Key&) = default;
        friend auto operator<=>(const Key&, const Key&) = default;
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            return std::hash<std::uint64_t>()(k.id ^ std::uint64_t(k.layer) * 0x9e3779b97f4a7c15u);
        }
    };
    template <class T>
    using Map = std::unordered_map<Key, std::unique_ptr<T>, KeyHash>;

    struct Arc {
        std::vector<BezierPiece> pieces;
        std::vector<double> start;  // u at each on-curve vertex
    };
    template <class T, class Compute>
    const T& getOrCompute(Map<T>& map, const Key& key, std::atomic<std::size_t>& counter, Compute&& compute) const;
    const Arc& arc(LayerId layer, AncestorId ancestor) const;
    double localNodeHeight(LayerId layer, ElementId node) const;
    std::unique_ptr<ZProfile> computeProfile(LayerId layer, AncestorId ancestor) const;
    // The terrain under the curve, smoothed, pulled to its node heights (rivers never rising).
    std::unique_ptr<ZProfile> terrainProfile(LayerId layer, AncestorId ancestor) const;
    // A procedural curve's: the part of its root's profile it follows (or its ring's height),
    // met by the ring's height at a trimmed end, lifted over its spans for a bridge.
    std::unique_ptr<ZProfile> proceduralProfile(LayerId layer, AncestorId ancestor, const ProceduralCurve& pc) const;
    void liftDeck(LayerId layer, AncestorId ancestor, std::span<const BridgeSpan> spans, ZProfile& prof) const;
    // Drops the arc-length tables (with `arcs`) and z-profiles of root curve `curve` and of the
    // procedural curves made from it.
    void dropCurve(LayerId layer, ElementId curve, bool arcs, std::vector<ElementRef>& dropped);
    void dropDownstream(LayerId layer, ElementId node, std::vector<ElementRef>& dropped);

    const Quadtree& quadtree_;
    const HeightField& heights_;
    ZProfileParams params_;
    mutable std::mutex mutex_;
    mutable Map<Arc> arcs_;
    mutable Map<ZProfile> profiles_;
    mutable Map<double> nodeHeights_;
    mutable Map<double> lakeLevels_;
    mutable std::set<Key> procedural_;  // the procedural curves with an arc or a z-profile cached
    // Crossed curve -> the bridge decks whose profile read its profile (dropped with it).
    mutable std::unordered_map<Key, std::set<Key>, KeyHash> readers_;
    double deckClearance_ = 5.0, deckThickness_ = 1.2;  // from the quadtree's GraphStep, if any
    mutable CurveDataCounters counters_;
};

}  // namespace lacet
