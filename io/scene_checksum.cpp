#include "io/scene_checksum.h"

#include <bit>
#include <cstdio>
#include <string_view>

#include "io/dem_lod.h"
#include "io/digest.h"
#include "io/scene_file.h"

namespace lacet {
SceneChecksum::SceneChecksum(const Scene& scene) {
    c_.word(kSceneFormatVersion);
    for (double v : {scene.extent.min.x, scene.extent.min.y, scene.extent.max.x, scene.extent.max.y}) c_.real(v);
    c_.word(scene.layers.size());
}

void SceneChecksum::layerHead(const Layer& layer) {
    c_.text(layer.name);
    c_.word(std::uint64_t(layer.kind));
}

void SceneChecksum::count(std::size_t n) { c_.word(n); }

void SceneChecksum::node(const Node& n) {
    c_.real(n.p.x);
    c_.real(n.p.y);
    // The radius's bits above `alive`: a file without roundabouts sums as before they existed.
    const std::uint32_t radius = n.roundabout == 0.0f ? 0u : std::bit_cast<std::uint32_t>(n.roundabout);
    c_.word(std::uint64_t(radius) << 1 | std::uint64_t(n.alive));
    c_.ids(n.curves);
}

void SceneChecksum::curve(const Curve& cv) {
    c_.word(cv.start);
    c_.word(cv.end);
    c_.real(cv.w);
    c_.real(cv.wf);
    c_.word(std::uint64_t(cv.cls) << 32 | std::uint64_t(cv.flags) << 1 | std::uint64_t(cv.alive));
    c_.word(cv.vertices.size());
    for (const Vertex& v : cv.vertices) {
        c_.real(v.p.x);
        c_.real(v.p.y);
        c_.word(std::uint64_t(v.onCurve) | std::uint64_t(v.closing) << 1);
    }
    c_.ids(cv.areas);
}

void SceneChecksum::area(const Area& a) {
    c_.real(a.wf);
    c_.word(std::uint64_t(a.cls) << 33 | std::uint64_t(a.axial) << 1 | std::uint64_t(a.alive));
    c_.word(a.loops.size());
    for (const auto& loop : a.loops) {
        c_.word(loop.size());
        for (const AreaEdge& e : loop) c_.word(std::uint64_t(e.curve) << 1 | std::uint64_t(e.reversed));
    }
}

void SceneChecksum::layer(const Layer& layer) {
    layerHead(layer);
    count(layer.nodes.size());
    for (const Node& n : layer.nodes) node(n);
    count(layer.curves.size());
    for (const Curve& cv : layer.curves) curve(cv);
    count(layer.areas.size());
    for (const Area& a : layer.areas) area(a);
}

std::string SceneChecksum::finish(const SceneDocument& doc) {
    Digest& c = c_;
    c.word(doc.attributes.size());
    for (const ElementAttribute& a : doc.attributes) {
        c.word(std::uint64_t(a.layer) << 40 | std::uint64_t(a.kind) << 32 | std::uint64_t(a.id));
        c.text(a.key);
        c.text(a.value);
    }
    const Georeference& g = doc.georeference;
    c.word(g.valid);
    for (double v : {g.lon0, g.lat0, g.originShift.x, g.originShift.y}) c.real(v);
    c.text(g.crsWkt);
    if (doc.demLod) {
        // A streamed DEM: its layout and the digest of its samples; doc.dem is derived from it. The
        // word 2 is neither of the words below (0 no DEM, 1 an in-memory DEM), whose sums are kept.
        const DemLodLayout& l = doc.demLod->layout();
        c.word(2);
        c.word(std::uint64_t(std::uint32_t(l.width)) << 32 | std::uint64_t(std::uint32_t(l.height)));
        c.real(l.cell).real(l.origin.x).real(l.origin.y);
        c.word(std::uint64_t(std::uint32_t(l.blockSide)) << 32 | std::uint64_t(std::uint32_t(l.levels)));
        c.text(doc.demLod->digest());
    } else {
        c.word(doc.dem.has_value());
    }
    if (doc.dem && !doc.demLod) {
        const Box& e = doc.dem->extent();
        for (double v : {e.min.x, e.min.y, e.max.x, e.max.y}) c.real(v);
        c.word(std::uint64_t(doc.dem->width()) << 32 | std::uint64_t(doc.dem->height()));
        for (float z : doc.dem->heights()) c.real(z);
    }
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(c.value()));
    return buf;
}

std::string sceneChecksumText(const SceneDocument& doc) {
    SceneChecksum c(doc.scene);
    for (const Layer& layer : doc.scene.layers) c.layer(layer);
    return c.finish(doc);
}

}  // namespace lacet
