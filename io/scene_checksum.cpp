#include "io/scene_checksum.h"

#include <bit>
#include <cstdio>
#include <stdexcept>
#include <string_view>

#include "io/dem_lod.h"
#include "io/digest.h"

namespace lacet {
namespace {

// Each element's fields, into `c` (both formats).
void nodeFields(Digest& c, const Node& n) {
    c.real(n.p.x);
    c.real(n.p.y);
    // The radius's bits above `alive`: a file without roundabouts sums as before they existed.
    const std::uint32_t radius = n.roundabout == 0.0f ? 0u : std::bit_cast<std::uint32_t>(n.roundabout);
    c.word(std::uint64_t(radius) << 1 | std::uint64_t(n.alive));
    c.ids(n.curves);
}

void curveFields(Digest& c, const Curve& cv) {
    c.word(cv.start);
    c.word(cv.end);
    c.real(cv.w);
    c.real(cv.wf);
    c.word(std::uint64_t(cv.cls) << 32 | std::uint64_t(cv.flags) << 1 | std::uint64_t(cv.alive));
    c.word(cv.vertices.size());
    for (const Vertex& v : cv.vertices) {
        c.real(v.p.x);
        c.real(v.p.y);
        c.word(std::uint64_t(v.onCurve) | std::uint64_t(v.closing) << 1);
    }
    c.ids(cv.areas);
}

void areaFields(Digest& c, const Area& a) {
    c.real(a.wf);
    c.word(std::uint64_t(a.cls) << 33 | std::uint64_t(a.axial) << 1 | std::uint64_t(a.alive));
    c.word(a.loops.size());
    for (const auto& loop : a.loops) {
        c.word(loop.size());
        for (const AreaEdge& e : loop) c.word(std::uint64_t(e.curve) << 1 | std::uint64_t(e.reversed));
    }
}

// Format 2: an element's digest starts with where it is.
Digest elementStart(LayerId layer, ElementKind kind, ElementId id) {
    Digest d;
    d.word(std::uint64_t(layer) << 34 | std::uint64_t(kind) << 32 | std::uint64_t(id));
    return d;
}

}  // namespace

SceneChecksum::SceneChecksum(const Scene& scene, int version) : version_(version) {
    if (version != 1 && version != 2) throw std::invalid_argument("SceneChecksum: no format " + std::to_string(version));
    c_.word(std::uint64_t(version));
    for (double v : {scene.extent.min.x, scene.extent.min.y, scene.extent.max.x, scene.extent.max.y}) c_.real(v);
    c_.word(scene.layers.size());
}

void SceneChecksum::layerHead(const Layer& layer) {
    c_.text(layer.name);
    c_.word(std::uint64_t(layer.kind));
    ++layer_;
}

void SceneChecksum::count(std::size_t n) {
    c_.word(n);
    next_ = 0;
}

void SceneChecksum::node(const Node& n) {
    if (version_ == 1) return nodeFields(c_, n);
    sum_ += elementDigest(LayerId(layer_), next_++, n);
}

void SceneChecksum::curve(const Curve& cv) {
    if (version_ == 1) return curveFields(c_, cv);
    sum_ += elementDigest(LayerId(layer_), next_++, cv);
}

void SceneChecksum::area(const Area& a) {
    if (version_ == 1) return areaFields(c_, a);
    sum_ += elementDigest(LayerId(layer_), next_++, a);
}

std::uint64_t SceneChecksum::elementDigest(LayerId layer, ElementId id, const Node& n) {
    Digest d = elementStart(layer, ElementKind::Node, id);
    nodeFields(d, n);
    return d.value();
}

std::uint64_t SceneChecksum::elementDigest(LayerId layer, ElementId id, const Curve& c) {
    Digest d = elementStart(layer, ElementKind::Curve, id);
    curveFields(d, c);
    return d.value();
}

std::uint64_t SceneChecksum::elementDigest(LayerId layer, ElementId id, const Area& a) {
    Digest d = elementStart(layer, ElementKind::Area, id);
    areaFields(d, a);
    return d.value();
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

std::string SceneChecksum::hex(std::uint64_t v) {
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

std::string SceneChecksum::combine(std::uint64_t head, std::uint64_t elements) {
    Digest d;
    d.word(head).word(elements);
    return hex(d.value());
}

SceneChecksumParts SceneChecksum::finish(const SceneDocument& doc) {
    attributeCount(doc.attributes.size());
    for (const ElementAttribute& a : doc.attributes) attribute(a);
    return finishAfterAttributes(doc);
}

void SceneChecksum::attributeCount(std::size_t n) { c_.word(n); }

void SceneChecksum::attribute(const ElementAttribute& a) {
    c_.word(std::uint64_t(a.layer) << 40 | std::uint64_t(a.kind) << 32 | std::uint64_t(a.id));
    c_.text(a.key);
    c_.text(a.value);
}

SceneChecksumParts SceneChecksum::finishAfterAttributes(const SceneDocument& doc) {
    Digest& c = c_;
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
    if (version_ == 1) return {hex(c.value()), 0, 0};
    return {combine(c.value(), sum_), c.value(), sum_};
}

SceneChecksumParts sceneChecksumParts(const SceneDocument& doc, int version) {
    SceneChecksum c(doc.scene, version);
    for (const Layer& layer : doc.scene.layers) c.layer(layer);
    return c.finish(doc);
}

std::string sceneChecksumText(const SceneDocument& doc, int version) { return sceneChecksumParts(doc, version).text; }

}  // namespace lacet
