#pragma once
// The quadtree of clipped graphs (§4.2) with CREATEDFROM and incremental UPDATE (§6).
//
// The root quad is the scene's extent and its graph is the Scene itself. Every other quad holds,
// per layer, the pieces of each element made from its parent's pieces by CLIPANDREFINE, grouped
// by ancestor: `curves[a]` is the list of clipped curves whose ancestor is `a`, in order, each
// recording the index of the parent piece it was made from (`parentIndex`). So
//   CREATEDFROM(q)[parent piece (a, i)] = the pieces of q.curves[a] with parentIndex == i,
// a contiguous range (createdFrom() below). Since clipping and refinement keep the ancestor, the
// pieces of ancestor `a` in a quad are made only from the pieces of `a` in its parent.
//
// The procedural step (Alg. 4.1) runs when the root is subdivided: it may replace a root curve by
// procedural curves, which are ancestors in their own right (AncestorId with kProceduralBit,
// proceduralId() below).
//
// Order of calls: build a Quadtree over a Scene (it keeps a reference); subdivide()/merge() or
// refineForViewer(); after each edit of the Scene (model/edits.h), update(changeset).

#include <array>
#include <optional>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "model/cancel.h"
#include "model/changeset.h"
#include "model/clip_and_refine.h"
#include "model/graph.h"
#include "model/procedural.h"
#include "model/view_params.h"
#include "model/work_clock.h"

namespace lacet {

struct QuadLayer {
    std::unordered_map<ElementId, Vec2> nodes;  // ancestor node -> its (unclipped) position
    std::unordered_map<AncestorId, std::vector<ClippedCurve>> curves;  // a root or procedural curve
    std::unordered_map<ElementId, std::vector<ClippedArea>> areas;
    bool empty() const { return nodes.empty() && curves.empty() && areas.empty(); }
};

struct Quad {
    int level = 0;
    std::uint32_t tx = 0, ty = 0;  // position in the grid of its level
    Box bounds;
    Quad* parent = nullptr;
    // children[k] covers (tx*2 + (k & 1), ty*2 + (k >> 1)): 0 lower-left, 1 lower-right,
    // 2 upper-left, 3 upper-right.
    std::array<std::unique_ptr<Quad>, 4> children;
    std::vector<QuadLayer> layers;  // one per scene layer; empty for the root
    bool isLeaf() const { return !children[0]; }
};

// The curves and areas of q's graph (what the time of its tiles and subdivision grows with).
inline std::size_t elementCount(const Quad& q) {
    std::size_t n = 0;
    for (const QuadLayer& l : q.layers) n += l.curves.size() + l.areas.size();
    return n;
}

// Id of the k-th procedural curve made from root curve `root`: kProceduralBit, then the root's id
// (32 bits), then k (the low kProceduralIndexBits). A pure function of (root, k), so an UPDATE and
// a rebuild give a curve the same id, for every root id; the ids of one root form the contiguous
// range [proceduralId(root, 0), proceduralId(root, kMaxProceduralCurves - 1)] and sort by root,
// then k. Throws std::length_error when k >= kMaxProceduralCurves.
constexpr int kProceduralIndexBits = 31;
constexpr std::size_t kMaxProceduralCurves = std::size_t(1) << kProceduralIndexBits;
AncestorId proceduralId(ElementId root, std::size_t k);
// The root curve an ancestor curve is, or was made from.
constexpr ElementId rootCurveOf(AncestorId a) {
    return (a & kProceduralBit) ? ElementId(a >> kProceduralIndexBits) : ElementId(a);
}
// k of the procedural curve proceduralId(root, k); 0 for a root curve.
constexpr std::size_t proceduralIndex(AncestorId a) {
    return (a & kProceduralBit) ? std::size_t(a & (kMaxProceduralCurves - 1)) : 0;
}
// The id ancestor `a` of `layer` has in the whole scene file (model/graph.h: Layer::sceneIds): its
// root curve's file id, with the same k.
inline AncestorId sceneAncestorId(const Layer& layer, AncestorId a) {
    if (!layer.isPart()) return a;
    return (a & kProceduralBit) ? proceduralId(layer.sceneCurveId(rootCurveOf(a)), proceduralIndex(a)) : layer.sceneCurveId(ElementId(a));
}

struct UpdateStats {
    std::size_t quadsVisited = 0;
    std::vector<const Quad*> changedQuads;  // quads whose graph changed: their textures are dirty
    // Root curves the procedural step expanded again besides the changeset's (roads crossing a
    // moved river, the roads of a changed roundabout): what was computed on their procedural
    // curves (CurveDataCache) is stale too.
    std::vector<ElementRef> reexpanded;
};

using QuadChildren = std::array<std::unique_ptr<Quad>, 4>;
class Quadtree;

// Where a refinement gets the children of a leaf it subdivides (editor/background_subdivision.h:
// those of a leaf of many elements made on another thread over several frames): the children
// made by tree.makeChildren(q), or none yet (q stays a leaf for now: the subdivision is deferred).
class ChildMaker {
public:
    virtual ~ChildMaker() = default;
    virtual std::optional<QuadChildren> children(const Quadtree& tree, const Quad& q) = 0;
};

class Quadtree {
public:
    // Validates the scene first (throws ValidationError).
    // `procedural` (may be null) must outlive the tree; UPDATE calls its update().
    explicit Quadtree(const Scene& scene, RefineParams params = {}, ProceduralStep* procedural = nullptr);
    Quadtree(const Quadtree&) = delete;
    Quadtree& operator=(const Quadtree&) = delete;

    const Scene& scene() const { return scene_; }
    const RefineParams& params() const { return params_; }
    Quad& root() { return root_; }
    const Quad& root() const { return root_; }

    // Makes the 4 children of a leaf from its graph (Alg. 4.1).
    void subdivide(Quad& q);
    // The same in two steps: the children of q made from its graph, not attached (it reads only
    // q's graph, the scene and the procedural curves: another thread may run it while q and the
    // scene stay unchanged; `cancel` is checked between elements, model/cancel.h), then attached
    // to q (nothing when q is no longer a leaf).
    QuadChildren makeChildren(const Quad& q, const CancelFlag* cancel = nullptr) const;
    void attach(Quad& q, QuadChildren children);
    // Deletes the descendants of q.
    void merge(Quad& q);
    // Subdivides every quad closer to the viewer than view.K times its size, down to
    // view.maxLevel, and merges the others. `viewer` is (x, y, height above the ground plane
    // z = 0), metres.
    void refineForViewer(glm::dvec3 viewer, const ViewParams& view);
    // The same for several viewers at once: a quad is subdivided when any of them wants it. The
    // tree is first merged where no viewer wants it; then the wanted leaves are subdivided, and
    // their wanted children in turn, most wanted first: those the first viewer wants before those
    // only the others do, then the nearest for their size (distance over size). With a deadline,
    // the first subdivision of the call is always made and each other one only while the deadline
    // has not passed (an already passed deadline makes exactly one), so that every call makes
    // progress whatever the budget, and what is deferred is what matters least. Returns false
    // when a subdivision was deferred, to be done by a later call; the tree the calls reach is the
    // tree refineForViewer makes. Throws std::invalid_argument when `viewers` is empty. With a
    // `maker`, the children of each leaf subdivided come from it (a leaf it has none for yet is
    // deferred, and does not count as the call's first subdivision).
    bool refineForViewers(std::span<const glm::dvec3> viewers, const ViewParams& view,
                          std::optional<Deadline> deadline = std::nullopt, ChildMaker* maker = nullptr);
    // The same within the subtree of `top` (a quad of this tree): only its descendants are merged
    // or subdivided (§7: a part of the scene read for one quad, whose tree is refined below it).
    bool refineSubtree(Quad& top, std::span<const glm::dvec3> viewers, const ViewParams& view,
                       std::optional<Deadline> deadline = std::nullopt, ChildMaker* maker = nullptr);
    // The quad (level, tx, ty), subdividing the leaves on the path from the root to it; throws
    // std::out_of_range when the level's grid has no such quad.
    Quad& reach(int level, std::uint32_t tx, std::uint32_t ty);
    // The rule of refineForViewer: q is below view.maxLevel and closer to `viewer` than view.K
    // times its size.
    static bool wantsSubdivision(const Quad& q, glm::dvec3 viewer, const ViewParams& view);
    // Whether any of `viewers` wants q subdivided: refineForViewers merges a quad that none wants.
    static bool wantedByAny(const Quad& q, std::span<const glm::dvec3> viewers, const ViewParams& view);
    // The distance from `viewer` (x, y, height above the ground) to q: to the nearest point of its
    // bounds, at the viewer's height above them (metres).
    static double viewDistance(const Quad& q, glm::dvec3 viewer);
    // Subdivides this tree exactly where `other` is subdivided (and merges elsewhere).
    void copyStructureOf(const Quadtree& other);

    // UPDATE (Alg. 6.1) after the scene was edited as `changeset` says. One pruning beyond the
    // paper: an area of a Fields, Forests or Other layer whose geometry changed but not its
    // attributes (wf, class, axial curve), re-clipped into a quad into exactly the pieces it had,
    // leaves that quad unchanged and is not carried into its children (their pieces are made
    // from those, with the same margin): a moved field corner changes only the quads near the
    // moved borders, not every quad of the field. (Lakes and river areas are not pruned: their
    // level depends on the whole border.)
    UpdateStats update(const Changeset& changeset);

    // The ancestor curve: a root curve, or a procedural one.
    const Curve& ancestorCurve(LayerId layer, AncestorId id) const;
    // What the procedural step made for procedural curve `id` (null for a root curve's id).
    const ProceduralCurve* proceduralCurve(LayerId layer, AncestorId id) const;
    // The procedural curves root curve `id` expands to now (empty when it is kept as it is).
    std::span<const AncestorId> expansionOf(LayerId layer, ElementId id) const;
    const ProceduralStep* procedural() const { return procedural_; }
    // Procedural curves of the tree with any of `flags` (e.g. kBridge), over all layers.
    std::size_t proceduralCount(std::uint16_t flags) const;
    // Clipping margins (metres) of an ancestor element in a quad of the given size.
    double curveMargin(LayerId layer, AncestorId id, double quadSize) const {
        const Curve& c = ancestorCurve(layer, id);
        return params_.curveMargin(double(c.w), double(c.wf), quadSize);
    }
    double areaMargin(LayerId layer, ElementId id, double quadSize) const {
        return params_.areaMargin(double(scene_.layers[layer].areas[id].wf), quadSize);
    }
    double nodeMargin(LayerId layer, ElementId id, double quadSize) const;

    // CREATEDFROM(q)[(ancestor, parentIndex)]: the curves of q made from that parent piece.
    static std::span<const ClippedCurve> createdFrom(const Quad& q, LayerId layer, AncestorId ancestor,
                                                     std::uint32_t parentIndex);

    template <class F>
    void forEachQuad(F&& f) const { visit(root_, f); }
    std::size_t quadCount() const;
    int depth() const;

private:
    struct Ancestors;  // per-layer sets of ancestor ids of nodes, curves, areas

    template <class F>
    static void visit(const Quad& q, F& f) {
        f(q);
        if (!q.isLeaf())
            for (const auto& c : q.children) visit(*c, f);
    }
    static Box childBounds(const Quad& q, int k);
    void expandRoot(LayerId layer, ElementId id);
    template <class F>
    void forEachRootCurveAncestor(LayerId layer, ElementId id, F&& f) const;
    ClippedCurve rootCurve(LayerId layer, AncestorId ancestor) const;
    ClippedArea rootArea(LayerId layer, ElementId id) const;
    void clipCurveInto(LayerId layer, AncestorId ancestor, std::span<const ClippedCurve> parent, const Quad& child,
                       std::vector<ClippedCurve>& out) const;
    void clipAreaInto(LayerId layer, ElementId id, std::span<const ClippedArea> parent, const Quad& child,
                      std::vector<ClippedArea>& out) const;
    void updateQuad(Quad& q, const Ancestors& removed, const Ancestors& added, UpdateStats& stats);
    bool refine(Quad& top, std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                ChildMaker* maker);
    void copyQuad(Quad& q, const Quad& like);

    const Scene& scene_;
    RefineParams params_;
    ProceduralStep* procedural_;
    Quad root_;
    // Per layer: root curve -> the procedural curves made from it, and their geometry.
    std::vector<std::unordered_map<ElementId, std::vector<AncestorId>>> expandedFrom_;
    // Per layer, the attributes of each area when it was last clipped into the tree, and during
    // an update the modified areas whose attributes did not change (see update()).
    struct AreaAttributes {
        float wf = 0.0f;
        std::uint16_t cls = 0;
        ElementId axial = kNoElement;
        friend bool operator==(const AreaAttributes&, const AreaAttributes&) = default;
    };
    std::vector<std::unordered_map<ElementId, AreaAttributes>> areaAttributes_;
    std::vector<std::vector<ElementId>> geometryOnlyAreas_;
    std::vector<std::unordered_map<AncestorId, ProceduralCurve>> proceduralCurves_;
};

}  // namespace lacet
