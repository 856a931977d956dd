// The live loop with a streamed DEM (io/dem_stream.h): each quad's window, and the tiles remade
// when the finer blocks they wanted arrive.
#include "editor/tile_loop.h"

namespace lacet {

namespace {

// The K rule's ratio: the priority of quad `q`'s DEM requests (lower is more important).
double demPriority(const Quad& q, glm::dvec3 viewer) { return Quadtree::viewDistance(q, viewer) / q.bounds.size().x; }

}  // namespace

DemWindow TileLoop::demWindow(const Quad& q, glm::dvec3 viewer) {
    const DemNeed n = quadDemNeed(q.bounds, params_.demSamplesPerQuad);
    return stream_->window(n.box, n.spacing, demPriority(q, viewer));
}

DemWindow TileLoop::objectWindow(const Quad& q, glm::dvec3 viewer, const DemWindow& quadWindow) {
    // A bridge is made whole in the quad holding its middle (raster/object_meshes.h), its pillars
    // standing on the DEM anywhere along it: the window covers its ancestor curves too.
    DemNeed n = quadDemNeed(q.bounds, params_.demSamplesPerQuad);
    Box& box = n.box;
    bool wider = false;
    for (std::size_t l = 0; l < q.layers.size(); ++l)
        for (const auto& [a, pieces] : q.layers[l].curves) {
            const Curve& c = forest_->treeOf(q).ancestorCurve(LayerId(l), a);
            if (!(c.flags & kBridge)) continue;
            const double reach = double(c.w) + double(c.wf) + 10.0;  // the deck's and the pillars' half-widths, and more
            for (const Vertex& v : c.vertices) {
                const Box around{v.p - reach, v.p + reach};
                if (around.min.x < box.min.x || around.min.y < box.min.y || around.max.x > box.max.x || around.max.y > box.max.y) {
                    box.min = glm::min(box.min, around.min);
                    box.max = glm::max(box.max, around.max);
                    wider = true;
                }
            }
        }
    if (!wider) return quadWindow;
    return stream_->window(n.box, n.spacing, demPriority(q, viewer));
}

void TileLoop::followDemStream(const CacheFit& fit, glm::dvec3 viewer, FrameReport& r) {
    stream_->beginFrame();
    for (const Quad* q : fit.shown) {
        const auto it = cache_.find(keyOf(*q));
        if (it == cache_.end() || it->second.dirty || it->second.demLevel >= it->second.demWanted) continue;
        const DemNeed n = quadDemNeed(q->bounds, params_.demSamplesPerQuad);
        if (stream_->availableLevel(n.box, n.spacing) > it->second.demLevel) {
            it->second.dirty = true;
            ++r.demRemade;
        } else {
            stream_->request(n.box, n.spacing, demPriority(*q, viewer));
        }
    }
}

}  // namespace lacet
