// EditSession with a streamed DEM (editor/dem_stream.h): each quad's window, and the tiles remade
// when the finer blocks they wanted arrive.
#include "editor/edit_session.h"

namespace lacet {

DemWindow EditSession::demWindow(const Quad& q, glm::dvec3 viewer) {
    const double size = q.bounds.size().x;
    // The producers read the DEM a little beyond the quad: the elevation tile's border and the
    // footprints' reach, the appearance's border (model/tile_grid.h); a quarter of the side covers both.
    const Box box{q.bounds.min - size / 4.0, q.bounds.max + size / 4.0};
    return demStream_->window(box, size / params_.demSamplesPerQuad, Quadtree::viewDistance(q, viewer) / size);
}

void EditSession::followDemStream(const CacheFit& fit, glm::dvec3 viewer, FrameReport& r) {
    demStream_->beginFrame();
    const bool arrived = !demStream_->takeArrived().empty();
    for (const Quad* q : fit.shown) {
        const auto it = cache_.find(keyOf(*q));
        if (it == cache_.end() || it->second.dirty || it->second.demLevel >= it->second.demWanted) continue;
        const double size = q->bounds.size().x;
        const Box box{q->bounds.min - size / 4.0, q->bounds.max + size / 4.0};
        const double spacing = size / params_.demSamplesPerQuad;
        if (arrived && demStream_->availableLevel(box, spacing) > it->second.demLevel) {
            it->second.dirty = true;
            ++r.demRemade;
        } else {
            demStream_->request(box, spacing, Quadtree::viewDistance(*q, viewer) / size);
        }
    }
}

}  // namespace lacet
