#include "raster/appearance_producer.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "model/junctions.h"
#include "model/roundabouts.h"
#include "model/segment.h"
#include "raster/appearance_areas.h"
#include "raster/appearance_canvas.h"
#include "raster/appearance_curves.h"
#include "raster/appearance_ground.h"
#include "raster/appearance_segments.h"
#include "raster/appearance_shading.h"

namespace lacet {
namespace {

using namespace appearance;

struct DrawItem {
    LayerId layer;
    bool area;
    AncestorId id;  // an ancestor curve's, or an area's (areas have no procedural ancestors)
    ElementId areaId() const { return ElementId(id); }
};

int rank(LayerKind kind) {
    switch (kind) {
        case LayerKind::Lakes: return 1;
        case LayerKind::Rivers: return 2;
        case LayerKind::Roads: return 3;
        default: return 0;
    }
}

template <class Map>
std::vector<typename Map::key_type> sortedKeys(const Map& m) {
    std::vector<typename Map::key_type> ids;
    ids.reserve(m.size());
    for (const auto& [id, pieces] : m) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    return ids;
}

std::vector<DrawItem> drawList(const Quad& quad, const Quadtree& qt, const std::vector<bool>& hidden) {
    const Scene& scene = qt.scene();
    std::vector<LayerId> layers(quad.layers.size());
    for (LayerId l = 0; l < layers.size(); ++l) layers[l] = l;
    std::stable_sort(layers.begin(), layers.end(),
                     [&](LayerId a, LayerId b) { return rank(scene.layers[a].kind) < rank(scene.layers[b].kind); });
    std::vector<DrawItem> items;
    for (LayerId l : layers) {
        if (l < hidden.size() && hidden[l]) continue;
        const LayerKind kind = scene.layers[l].kind;
        // A river layer's areas come after its curves: drawn over their banks, under their water.
        const bool areasAfterCurves = kind == LayerKind::Rivers;
        if (surfaceOf(kind) != Surface::None && !areasAfterCurves)
            for (ElementId id : sortedKeys(quad.layers[l].areas)) items.push_back({l, true, id});
        if (kind == LayerKind::Roads || kind == LayerKind::Rivers)
            for (AncestorId id : sortedKeys(quad.layers[l].curves))
                if (!(qt.ancestorCurve(l, id).flags & kBridge)  // a deck: the object meshes draw it, the river shows under it
                    && qt.ancestorCurve(l, id).areas.empty())   // an area's border (a river area's): drawn with the area
                    items.push_back({l, false, id});
        if (surfaceOf(kind) != Surface::None && areasAfterCurves)
            for (ElementId id : sortedKeys(quad.layers[l].areas)) items.push_back({l, true, id});
    }
    return items;
}

// The shade of the last item when it covers the whole tile (border texels included).
std::optional<SurfaceShade> coveringShade(const Quad& quad, const Quadtree& qt, const AppearanceTile& t, const DrawItem& last) {
    const Scene& scene = qt.scene();
    const LayerKind kind = scene.layers[last.layer].kind;
    if (last.area) {
        const auto& pieces = quad.layers[last.layer].areas.at(last.areaId());
        if (pieces.size() == 1 && pieces.front().coversQuad)
            return SurfaceShade{surfaceOf(kind), scene.layers[last.layer].areas[last.areaId()].cls,
                                scene.layers[last.layer].sceneAreaId(last.areaId())};
        return std::nullopt;
    }
    if (kind != LayerKind::Rivers) return std::nullopt;
    const Curve& c = qt.ancestorCurve(last.layer, last.id);
    const double limit = 0.5 * double(c.w) - t.delta / double(t.samples);
    if (limit <= 0.0) return std::nullopt;
    const Box box = t.bounds.dilated(double(t.border) * t.delta);
    const Vec2 corners[4] = {box.min, {box.max.x, box.min.y}, {box.min.x, box.max.y}, box.max};
    for (const Segment& sg : segmentsOf(quad.layers[last.layer].curves.at(last.id), nullptr, last.layer, last.id)) {
        const bool holds = std::all_of(std::begin(corners), std::end(corners), [&](Vec2 q) {
            return distanceToSegment(q, sg.p0, sg.p1) <= limit;  // a capsule is convex
        });
        if (holds) return SurfaceShade{Surface::Water, 0, scene.layers[last.layer].sceneCurveId(rootCurveOf(last.id))};
    }
    return std::nullopt;
}

// Where a ring arc or a road trimmed at a ring ends on the ring, or a road piece at its bridge, the
// pieces meet at one point with no node there: its markings stop at that end as at a node's cap, instead of drawing their side
// lines around it (the segments of `runs`, as segmentsOf made them).
void capRingEnds(std::vector<Segment>& segments, const std::vector<ClippedCurve>& runs, const Curve& c,
                 const ProceduralCurve& pc) {
    // A ring's end, or a cut where a road meets its bridge (the deck's mesh takes over there).
    const bool atStart = pc.ringAtStart != kNoElement || (pc.followsRoot() && c.start == kNoElement);
    const bool atEnd = pc.ringAtEnd != kNoElement || (pc.followsRoot() && c.end == kNoElement);
    if (!atStart && !atEnd) return;
    double sEnd = -1.0;
    for (const Vertex& v : c.vertices) sEnd += v.onCurve ? 1.0 : 0.0;
    std::size_t next = 0;
    for (const ClippedCurve& run : runs) {
        const std::size_t n = run.s.size() > 1 ? run.s.size() - 1 : 0;
        if (n == 0 || next + n > segments.size()) continue;
        if (atStart && run.s.front() == 0.0) segments[next].startCap = true;
        if (atEnd && run.s.back() == sEnd) segments[next + n - 1].endCap = true;
        next += n;
    }
}

// What a road's markings need to know about its ends (junctions, stop and yield lines), from
// the ancestor graph.
RoadEnds roadEnds(const Quadtree& quadtree, const CurveDataCache& curveData, LayerId l, AncestorId id, const Curve& c) {
    const Layer& layer = quadtree.scene().layers[l];
    RoadEnds ends;
    ends.length = curveData.length(l, id);
    ends.startRadius = junctionRadius(layer, c.start);
    ends.endRadius = junctionRadius(layer, c.end);
    ends.startStop = hasStopLine(layer, c.start, rootCurveOf(id));
    ends.endStop = hasStopLine(layer, c.end, rootCurveOf(id));
    // A road trimmed at a roundabout's ring yields there; its markings stop at the ring's edge.
    ends.startYield = (c.flags & kYieldAtStart) != 0;
    ends.endYield = (c.flags & kYieldAtEnd) != 0;
    if (ends.startYield || ends.endYield)
        if (const ProceduralCurve* pc = quadtree.proceduralCurve(l, id)) {
            if (ends.startYield) ends.startRadius = 0.5 * double(roundaboutRingWidth(layer, pc->ringAtStart));
            if (ends.endYield) ends.endRadius = 0.5 * double(roundaboutRingWidth(layer, pc->ringAtEnd));
        }
    return ends;
}

}  // namespace

AppearanceTile produceAppearance(const Quad& quad, const Quadtree& quadtree, const CurveDataCache& curveData,
                                 const Dem& dem, const AppearanceParams& params, AppearanceCounters* counters,
                                 const CancelFlag* cancel) {
    throwIfCancelled(cancel);
    const TileGrid& grid = quadtree.params().grid();  // validated by the Quadtree
    const int n = grid.resolution;
    if (params.samples < 1 || params.samples > 8 || params.groundCells < 1 || !(params.groundCellMin >= 0.0))
        throw std::invalid_argument("produceAppearance(): 1 <= samples <= 8, groundCells >= 1 and groundCellMin >= 0 required");
    AppearanceTile t;
    t.bounds = quad.bounds;
    t.resolution = n;
    t.border = grid.appearanceBorder;
    t.stride = n + 2 * grid.appearanceBorder;
    t.samples = params.samples;
    t.delta = quad.bounds.size().x / double(n);
    if (counters) ++counters->tiles;

    const Scene& scene = quadtree.scene();
    const std::vector<DrawItem> items = drawList(quad, quadtree, params.hiddenLayers);
    if (params.detectUniform && !items.empty())
        if (const auto shade = coveringShade(quad, quadtree, t, items.back())) {
            t.uniform = true;
            t.shade = *shade;
            if (counters) {
                ++counters->uniformTiles;
                if (shade->surface == Surface::Water) counters->waterTexels += std::size_t(t.stride) * std::size_t(t.stride);
            }
            return t;
        }

    Canvas canvas(t, threadScratch());
    // Cells of groundCellMin at least, from the level's nominal size (the root's halved `level`
    // times, exact), so quads of a level agree on their grid and share its nodes.
    const double size = std::ldexp(quadtree.root().bounds.size().x, -quad.level);
    const double fit = std::ceil(size / std::max(params.groundCellMin, 1e-9) - 1e-9);
    const int cells = int(std::clamp(fit, 1.0, double(params.groundCells)));
    drawGround(canvas, t, dem, cells);
    const MarkingGeometry marking;
    const bool markingsShow = marking.lineWidth >= params.markingMinTexels * t.delta;
    auto drawAreaItem = [&](const DrawItem& it) {
        const Layer& layer = scene.layers[it.layer];
        const Area& a = layer.areas[it.areaId()];
        const SurfaceShade shade{surfaceOf(layer.kind), a.cls, layer.sceneAreaId(it.areaId())};
        for (const ClippedArea& piece : quad.layers[it.layer].areas.at(it.areaId())) {
            drawArea(canvas, t, piece, shade, double(a.wf), counters);
            if (counters) ++counters->areaPieces;
        }
    };
    for (std::size_t i = 0; i < items.size(); ++i) {
        throwIfCancelled(cancel);
        const DrawItem& it = items[i];
        const Layer& layer = scene.layers[it.layer];
        if (it.area) {
            drawAreaItem(it);
            continue;
        }
        // The curves of one layer are consecutive items: draw them together, in two passes.
        std::size_t last = i;
        while (last + 1 < items.size() && !items[last + 1].area && items[last + 1].layer == it.layer) ++last;
        const auto& curves = quad.layers[it.layer].curves;
        if (counters) counters->curvesDrawn += last - i + 1;
        // A road's markings are found as its surface is drawn (the same distance field) and
        // drawn once every surface of the layer is down.
        Scratch& scratch = canvas.scratch();
        scratch.marks.clear();
        for (std::size_t r = i; r <= last; ++r) {
            if ((r & 63) == 0) throwIfCancelled(cancel);
            const AncestorId id = items[r].id;
            const Curve& c = quadtree.ancestorCurve(it.layer, id);
            if (c.flags & kTunnel) {  // under the ground but for its portals
                drawTunnelPortals(canvas, segmentsOf(curves.at(id), &curveData, it.layer, id), c,
                                  curveData.length(it.layer, id), params.tunnelPortalLength);
            } else if (layer.kind == LayerKind::Rivers) {
                drawRiverBanks(canvas, segmentsOf(curves.at(id), nullptr, it.layer, id), c);
            } else if (!roadHasMarkings(c.cls) || !markingsShow) {
                drawRoadSurface(canvas, segmentsOf(curves.at(id), nullptr, it.layer, id), c);
                if (counters && roadHasMarkings(c.cls)) ++counters->markingsBelowTexel;
            } else {
                std::vector<Segment> segments = segmentsOf(curves.at(id), &curveData, it.layer, id);
                if (const ProceduralCurve* pc = quadtree.proceduralCurve(it.layer, id)) capRingEnds(segments, curves.at(id), c, *pc);
                const RoadMarkings markings(c, roadEnds(quadtree, curveData, it.layer, id, c), canvas.pixelSize());
                drawRoadSurface(canvas, segments, c, &markings, &scratch.marks);
                if (counters) ++counters->curvesWithMarkings;
            }
        }
        // The layer's areas that follow its curves (a river layer's): over the banks, under the water.
        std::size_t lastArea = last;
        while (lastArea + 1 < items.size() && items[lastArea + 1].area && items[lastArea + 1].layer == it.layer) ++lastArea;
        for (std::size_t r = last + 1; r <= lastArea; ++r) drawAreaItem(items[r]);
        if (layer.kind == LayerKind::Rivers) {
            for (std::size_t r = i; r <= last; ++r) {
                if ((r & 63) == 0) throwIfCancelled(cancel);
                const AncestorId id = items[r].id;
                const Curve& c = quadtree.ancestorCurve(it.layer, id);
                drawRiverWater(canvas, segmentsOf(curves.at(id), nullptr, it.layer, id), c);
            }
        }
        drawMarkings(canvas, scratch.marks);
        i = lastArea;
    }
    canvas.scratch().clean = true;
    resolve(canvas, canvas.scratch(), t, t.rgbm);
    if (counters) {
        std::size_t water = 0;
        for (std::size_t k = 3; k < t.rgbm.size(); k += 4) water += t.rgbm[k] > 0;
        counters->waterTexels += water;
    }
    return t;
}

std::vector<std::uint8_t> tileTexels(const AppearanceTile& tile) {
    if (!tile.uniform) return tile.rgbm;
    Canvas canvas(tile, threadScratch());
    std::fill(canvas.scratch().colour.begin(), canvas.scratch().colour.end(), Rgbm(0.0f));
    SurfaceShader shader(tile.shade, tile.delta);
    shader.prepare(canvas.box());
    shadeWhole(canvas, shader);
    canvas.scratch().clean = true;  // shadeWhole sets neither dist nor flags
    std::vector<std::uint8_t> out;
    resolve(canvas, canvas.scratch(), tile, out);
    return out;
}

}  // namespace lacet
