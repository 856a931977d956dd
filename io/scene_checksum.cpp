#include "io/scene_checksum.h"

#include <bit>
#include <cstdio>
#include <string_view>

#include "io/scene_file.h"

namespace lacet {
namespace {

// xxHash64-style rounds over 64-bit words, then a final avalanche. Not cryptographic: it detects
// damage, not tampering.
class Checksum {
public:
    void word(std::uint64_t w) {
        w *= 0xC2B2AE3D27D4EB4FULL;
        w = std::rotl(w, 31) * 0x9E3779B185EBCA87ULL;
        h_ = std::rotl(h_ ^ w, 27) * 0x9E3779B185EBCA87ULL + 0x85EBCA77C2B2AE63ULL;
    }
    void real(double v) { word(std::bit_cast<std::uint64_t>(v)); }
    void real(float v) { word(std::bit_cast<std::uint32_t>(v)); }
    void text(std::string_view t) {
        word(t.size());
        std::uint64_t w = 0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            w |= std::uint64_t(static_cast<unsigned char>(t[k])) << (8 * (k % 8));
            if (k % 8 == 7 || k + 1 == t.size()) {
                word(w);
                w = 0;
            }
        }
    }
    void ids(const std::vector<ElementId>& v) {
        word(v.size());
        for (ElementId id : v) word(id);
    }
    std::uint64_t value() const {
        std::uint64_t h = h_;
        h ^= h >> 33;
        h *= 0xC2B2AE3D27D4EB4FULL;
        h ^= h >> 29;
        return h;
    }

private:
    std::uint64_t h_ = 0x27D4EB2F165667C5ULL;
};

}  // namespace

std::string sceneChecksumText(const SceneDocument& doc) {
    Checksum c;
    const Scene& scene = doc.scene;
    c.word(kSceneFormatVersion);
    for (double v : {scene.extent.min.x, scene.extent.min.y, scene.extent.max.x, scene.extent.max.y}) c.real(v);
    c.word(scene.layers.size());
    for (const Layer& layer : scene.layers) {
        c.text(layer.name);
        c.word(std::uint64_t(layer.kind));
        c.word(layer.nodes.size());
        for (const Node& n : layer.nodes) {
            c.real(n.p.x);
            c.real(n.p.y);
            // The radius's bits above `alive`: a file without roundabouts sums as before they existed.
            const std::uint32_t radius = n.roundabout == 0.0f ? 0u : std::bit_cast<std::uint32_t>(n.roundabout);
            c.word(std::uint64_t(radius) << 1 | std::uint64_t(n.alive));
            c.ids(n.curves);
        }
        c.word(layer.curves.size());
        for (const Curve& cv : layer.curves) {
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
        c.word(layer.areas.size());
        for (const Area& a : layer.areas) {
            c.real(a.wf);
            c.word(std::uint64_t(a.cls) << 33 | std::uint64_t(a.axial) << 1 | std::uint64_t(a.alive));
            c.word(a.loops.size());
            for (const auto& loop : a.loops) {
                c.word(loop.size());
                for (const AreaEdge& e : loop) c.word(std::uint64_t(e.curve) << 1 | std::uint64_t(e.reversed));
            }
        }
    }
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
    c.word(doc.dem.has_value());
    if (doc.dem) {
        const Box& e = doc.dem->extent();
        for (double v : {e.min.x, e.min.y, e.max.x, e.max.y}) c.real(v);
        c.word(std::uint64_t(doc.dem->width()) << 32 | std::uint64_t(doc.dem->height()));
        for (float z : doc.dem->heights()) c.real(z);
    }
    char buf[24];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(c.value()));
    return buf;
}

}  // namespace lacet
