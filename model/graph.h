#pragma once
// The spline network (§4.1): a scene is a list of layers; each layer is a graph of nodes,
// curves and areas. This is the root graph of the quadtree; clipped copies live in quads.
//
// Element ids are slot indices in the layer's arrays: stable across edits and save/load, never
// reused. A deleted element keeps its slot with `alive == false`.
//
// Invariants (checked by validate()): a curve's first and last vertices are on-curve and equal
// to its start and end nodes' positions; between two on-curve vertices lie 0..2 controls;
// node.curves lists exactly the alive curves that start or end there (a closed curve twice);
// area loops are closed chains of alive curves; curve.areas lists the areas using the curve.

#include <span>
#include <string>
#include <vector>

#include "model/bezier.h"
#include "model/types.h"

namespace lacet {

// What a layer holds; decides the default shading and footprint rules of its elements.
enum class LayerKind : std::uint8_t { Roads, Rivers, Lakes, Fields, Forests, Other };

std::string_view toString(LayerKind kind);

// Curve flags. From the source data or the user: kBridge (the curve is a bridge: no footprint,
// not drawn on the terrain, a deck mesh), kTunnel (no footprint, not drawn between its portals),
// kNoBridge (the graph step makes no bridge on this curve where it crosses a river: a ford),
// kRoundabout (a roundabout's ring, imported as such), kAlwaysBridge (no culvert: the graph step
// bridges even the narrowest river this road crosses). Set by the graph step on the curves it makes
// (model/procedural.h): kYieldAtStart / kYieldAtEnd (a yield line where the curve enters a ring).
enum CurveFlag : std::uint16_t {
    kBridge = 1u << 0,
    kTunnel = 1u << 1,
    kNoBridge = 1u << 2,
    kRoundabout = 1u << 3,
    kYieldAtStart = 1u << 4,
    kYieldAtEnd = 1u << 5,
    kAlwaysBridge = 1u << 6,  // bridge every river this road crosses, however narrow (no culvert)
};

struct Node {
    Vec2 p{0.0};
    std::vector<ElementId> curves;  // adjacent curves
    // Radius (m) of the roundabout the graph step makes at this junction (§4.3, Fig. 5 right); 0
    // for none.
    float roundabout = 0.0f;
    bool alive = true;
    friend bool operator==(const Node&, const Node&) = default;
};

struct Curve {
    std::vector<Vertex> vertices;  // Bezier spline, first and last on-curve
    ElementId start = kNoElement;
    ElementId end = kNoElement;
    float w = 0.0f;    // width (m)
    float wf = 0.0f;   // footprint width (m), >= w
    std::uint16_t cls = 0;    // class within the layer (e.g. road class)
    std::uint16_t flags = 0;  // CurveFlag bits
    std::vector<ElementId> areas;  // areas whose loops use this curve
    bool alive = true;
    friend bool operator==(const Curve&, const Curve&) = default;
};

struct AreaEdge {
    ElementId curve = kNoElement;
    bool reversed = false;  // walk the curve from its end node to its start node
    friend bool operator==(const AreaEdge&, const AreaEdge&) = default;
};

struct Area {
    // loops[0] is the outer ring, the others holes. Each loop is a closed chain of curves.
    std::vector<std::vector<AreaEdge>> loops;
    float wf = 0.0f;   // footprint width outside the surface (m)
    std::uint16_t cls = 0;
    ElementId axial = kNoElement;  // optional axial curve (elevation profile), same layer
    bool alive = true;
    friend bool operator==(const Area&, const Area&) = default;
};

struct Layer {
    std::string name;
    LayerKind kind = LayerKind::Other;
    std::vector<Node> nodes;
    std::vector<Curve> curves;
    std::vector<Area> areas;

    // Where the layer holds a part of a scene file's layer (a region read by io/scene_region.h):
    // each element's id in the file, ascending, one per element. Empty where the layer is whole
    // (its ids are the file's). What is computed from an id's value (a quad's digest, a field's
    // tint) takes the file's id, so that a part gives what the whole scene gives; the order of the
    // ids is the file's either way. A part takes a new element only once the element's file id is
    // named (pushed onto its kind's ids first: editor/lazy_edits.h gives the file's next id; add*
    // throw std::logic_error otherwise), and is never saved (io/scene_file.h refuses it: the rest
    // of the layer would be lost).
    struct SceneIds {
        bool part = false;  // the layer is a part; the ids below are its elements' in the file
        std::vector<ElementId> nodes, curves, areas;
    } sceneIds;
    bool isPart() const { return sceneIds.part; }
    ElementId sceneNodeId(ElementId id) const { return fileId(sceneIds.nodes, id); }
    ElementId sceneCurveId(ElementId id) const { return fileId(sceneIds.curves, id); }
    ElementId sceneAreaId(ElementId id) const { return fileId(sceneIds.areas, id); }
    // `id` names a node of the layer that is alive (kNoElement and ids past the end do not).
    bool aliveNode(ElementId id) const { return id != kNoElement && id < nodes.size() && nodes[id].alive; }

    ElementId addNode(Vec2 p);
    // Adds a curve whose vertices run from node `start` to node `end`; updates adjacency.
    ElementId addCurve(Curve c);
    // Adds an area from loops of existing curves; updates curve.areas.
    ElementId addArea(Area a);

private:
    static ElementId fileId(const std::vector<ElementId>& ids, ElementId id) {
        return id < ids.size() ? ids[id] : id;  // a whole layer's ids are empty; kNoElement stays
    }
    void refuseIfPart(const std::vector<ElementId>& fileIds, std::size_t count) const;
};

// A layer part: a layer whose elements refer only to each other, by ids from 0 (a patch of fields,
// a chunk of an import), made apart and appended to a layer later (appendLayerPart) or written
// straight to a scene file (io/scene_file.h: saveSceneStreamed), so that a scene larger than memory
// is made one part at a time.
struct ElementOffsets {
    ElementId nodes = 0, curves = 0, areas = 0;
};
// Adds `o` to every id `part`'s elements refer to (node.curves, curve.start/end/areas, area loops
// and axial; kNoElement stays), as if its elements sat after `o` elements of each kind.
void offsetElementIds(Layer& part, const ElementOffsets& o);
// Appends `part`'s elements after `into`'s, their references shifted by into's counts; name and
// kind of `part` are ignored.
void appendLayerPart(Layer& into, Layer&& part);

struct Scene {
    Box extent;  // the root quad (square), in scene CRS metres
    std::vector<Layer> layers;
};

// Iterates the Bezier pieces of a vertex chain (on-curve, 0..2 controls, on-curve, ...).
// `f(const BezierPiece&, size_t firstVertexIndex)`.
template <class F>
void forEachPiece(std::span<const Vertex> v, F&& f) {
    std::size_t i = 0;
    while (i + 1 < v.size()) {
        BezierPiece b;
        std::size_t j = i + 1;
        b.p[0] = v[i].p;
        int n = 1;
        while (j < v.size() && !v[j].onCurve && n < 3) b.p[n++] = v[j++].p;
        if (j >= v.size()) return;  // malformed tail; validate() reports it
        b.p[n] = v[j].p;
        b.degree = n;
        f(b, i);
        i = j;
    }
}

// The closed vertex chain of an area loop, first vertex repeated at the end.
std::vector<Vertex> loopVertices(const Layer& layer, const std::vector<AreaEdge>& loop);

// Counts of alive elements (and of vertices, on-curve and control) over all layers.
struct SceneCounts {
    std::size_t nodes = 0, curves = 0, areas = 0, vertices = 0, controlPoints = 0;
};
SceneCounts count(const Scene& scene);

// Bytes an element holds in memory: its struct and the vectors it owns, at their capacity. What a
// memory budget of vector data counts (io/scene_region.h: SceneRegionOptions::budgetMiB).
std::size_t memoryBytes(const Node& n);
std::size_t memoryBytes(const Curve& c);
// The box of a curve's vertices, control points included (it holds the spline); empty (min above
// max) without vertices.
Box hullBox(const Curve& c);
std::size_t memoryBytes(const Area& a);
// A layer's elements, each vector's unused capacity and a part's file ids included; a scene's layers.
std::size_t memoryBytes(const Layer& layer);
std::size_t memoryBytes(const Scene& scene);
// Bytes in MiB (2^20 bytes), the unit of Lacet's memory budgets.
inline double toMiB(std::size_t bytes) { return double(bytes) / 1048576.0; }

}  // namespace lacet
