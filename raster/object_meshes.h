#pragma once
// The object meshes of a quad (§5.3): what stands on the terrain rather than in its textures,
// generated from the vector data when the quad's tiles are made. Two kinds:
//
// Bridges. One mesh per bridge, built from its ANCESTOR curve (a procedural bridge the graph step
// cut from a road, or an imported kBridge curve: model/graph_step.h), never from the clipped
// pieces, so a bridge clipped into many quads is still one bridge: its deck (a slab
// `deckThickness` deep under the road surface, the bridge's z-profile, as wide as the road plus a
// parapet on each side), parapets, pillars every `pillarSpacing` where the deck is higher than
// `minPillarHeight` above the ground, and an abutment (a block from the deck's underside into the
// ground) at each end. Each bridge belongs to exactly one quad of each level: among the quads that
// hold its pieces, the one whose half-open bounds ([min, max), closed on the root's max sides)
// contain its point at half its length. The mesh is a function of the ancestor, its z-profile
// and the DEM only, so every level builds the same bridge.
//
// Trees. Along the curves a TreeRule asks for (alleys beside roads of a class, hedges on the field
// borders), one tree at each u = k * spacing (u: the ancestor's arc length, CurveDataCache::u, so
// trees continue across quad borders), beside the axis at the rule's offset on each of its sides.
// A tree's position is a function of (ancestor, k, side) only; it belongs to the quad whose
// half-open bounds contain it, so trees along a curve clipped into many quads are those of the
// whole curve, each once. Its foot stands on the displayed ground: z_m of the quad's elevation
// tile (bilinear, as EditSession::displayedHeight), or the DEM without a tile. Quads larger than
// a rule's `maxQuadSize` get none of its trees (at the distances where such quads are drawn a tree
// is a pixel, and a coarse quad would hold every tree of its area).
//
// Cost: a quad whose curves hold no bridge and match no tree rule builds nothing (the counters
// stay 0); the per-curve test is one flag and one rule lookup.
//
// Thread safety: produceObjects() may run for many quads at once; it only reads the quadtree, the
// DEM and the tile, and asks the CurveDataCache (thread-safe) for u, lengths and z-profiles.

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "model/curve_data.h"
#include "model/graph.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "raster/dem.h"
#include "raster/elevation_tile.h"

namespace lacet {

// The curves that get trees: those of layers of `kind` and class `cls` (-1: any class), except
// bridges and tunnels.
struct TreeRule {
    LayerKind kind = LayerKind::Roads;
    int cls = -1;                 // the curve's class, or -1 for any
    double spacing = 15.0;        // m along the curve (u) between trees, > 0
    // Distance from the axis as a fraction of the curve's wf / 2 (the edge of its footprint), on
    // both sides when > 0 (an alley), on the axis when 0 (a hedge); in [0, 1]: a tree must lie
    // within its curve's clipping margin (>= wf / 2) to be found in the quad that owns it.
    double offsetFraction = 1.0;
    double endClearance = 12.0;   // m: no tree closer than this to either end of the ancestor (junctions), >= 0
    double height = 9.0;          // m, ground to crown top, > 0
    double crownRadius = 2.5;     // m, > 0
    double trunkRadius = 0.25;    // m, >= 0 (0: no trunk)
    double crownBase = 0.35;      // fraction of the height where the crown begins, in [0, 1)
    double heightJitter = 0.15;   // relative height variation between trees (deterministic per tree), in [0, 1)
    // m: quads larger than this get none of these trees (they are drawn from at least K times
    // their size, where such a tree is a pixel or two, and a coarse quad would hold thousands), > 0
    double maxQuadSize = 1200.0;
    std::array<std::uint8_t, 4> crownColour{58, 102, 46, 255};   // sRGB
    std::array<std::uint8_t, 4> trunkColour{92, 70, 50, 255};
};

// Named knobs of the object meshes (§5.3).
struct ObjectParams {
    bool bridges = true;
    // The deck's depth under its road surface (m, > 0): the z-profile of a bridge is its road
    // surface and the graph step makes its underside clear the water by GraphStepParams::clearance
    // with this thickness, so it must be GraphStepParams::deckThickness (the editing session sets
    // it from its graph step's parameters).
    double deckThickness = GraphStepParams{}.deckThickness;
    double parapetHeight = 1.0;     // m above the road surface, >= 0
    double parapetWidth = 0.4;      // m, each side, beyond the road's width w, >= 0
    double pillarSpacing = 30.0;    // m along the deck between pillars (evenly between the abutments), > 0
    double pillarThickness = 1.6;   // m along the deck, > 0
    double pillarWidthFraction = 0.7;  // of the deck's width across it, in (0, 1]
    double minPillarHeight = 1.5;   // m: no pillar where the deck's underside is lower than this above the ground, >= 0
    double footDepth = 1.0;         // m: pillars and abutments go this far below the ground (and the crossed water), >= 0
    double abutmentLength = 4.0;    // m along the deck from each end: the block under the deck, > 0
    double stationSpacing = 2.0;    // m between the deck's cross-sections along u, > 0
    // Trees (none when empty). Default: alleys beside secondary roads (class 1 of the importer's
    // mapping and of the synthetic scene), hedges on the field borders (every curve of a Fields layer).
    std::vector<TreeRule> trees = defaultTrees();
    // m between the points of a curve piece that trees are placed along (each Bezier piece of the
    // ancestor is flattened into chords this long or shorter, u scaled to the curve data's), > 0
    double treeSampleStep = 1.0;
    std::vector<bool> hiddenLayers;   // layers with no objects (index: LayerId; missing: shown)

    static std::vector<TreeRule> defaultTrees();
    void validate() const;  // throws std::invalid_argument naming the knob
};

// One vertex: position relative to ObjectMesh::origin (metres, float), unit normal, sRGB colour.
struct ObjectVertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    std::array<std::uint8_t, 4> colour{255, 255, 255, 255};
    friend bool operator==(const ObjectVertex&, const ObjectVertex&) = default;
};

// A bridge is its deck (with the parapets) and its abutments and pillars, parts of one ancestor.
enum class ObjectKind : std::uint8_t { Deck, Abutment, Pillar, Tree };

// What a range of the mesh is, and where it stands (scene metres):
// - Deck: index 0, anchor the road surface at half the bridge's length (the owner's point);
// - Abutment: index 0 at the start, 1 at the end; anchor the centre of its foot;
// - Pillar: index i (1, 2, ... from the start); anchor the centre of its foot;
// - Tree: index k (at u = k * spacing), side -1 right, 0 on the axis, 1 left of the curve's
//   direction; anchor its foot on the ground.
struct ObjectPart {
    ObjectKind kind = ObjectKind::Tree;
    LayerId layer = 0;
    AncestorId ancestor = 0;
    std::int64_t index = 0;
    int side = 0;
    glm::dvec3 anchor{0.0};
    std::uint32_t firstVertex = 0, vertexCount = 0, firstIndex = 0, indexCount = 0;
};

struct ObjectMesh {
    glm::dvec3 origin{0.0};                // the quad's bounds min, at z = 0 (metres)
    std::vector<ObjectVertex> vertices;
    std::vector<std::uint32_t> indices;    // triangles, counter-clockwise seen from outside
    std::vector<ObjectPart> parts;
    glm::vec3 lo{0.0f}, hi{0.0f};          // bounds of the vertices, relative to origin (empty mesh: 0)
    bool empty() const { return indices.empty(); }
    glm::dvec3 world(std::size_t vertex) const { return origin + glm::dvec3(vertices[vertex].position); }
};

struct ObjectCounters {
    std::atomic<std::size_t> meshesBuilt{0};  // quads whose mesh holds something
    std::atomic<std::size_t> bridges{0};
    std::atomic<std::size_t> pillars{0};
    std::atomic<std::size_t> trees{0};
    void reset();
};

// The objects that `quad` owns. `elevation`: the quad's elevation tile (trees stand on its z_m),
// or nullptr (the DEM). The root quad (whose graph is the scene) owns none.
ObjectMesh produceObjects(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData, const Dem& dem,
                          const ElevationTile* elevation, const ObjectParams& params, ObjectCounters* counters = nullptr);

// Whether a point belongs to the quad `bounds` of a tree whose root is `root`: half-open on the
// min side ([min, max)), closed on the root's max sides, so exactly one quad of a level owns it.
bool ownsPoint(const Box& bounds, const Box& root, Vec2 p);

}  // namespace lacet
