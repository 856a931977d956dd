#include "pyramid/quad_digest.h"

// Quad digests (pyramid/quad_digest.h), what `lacet pyramid update` trusts to remake only the
// quads an edit changed: the same scene always gives the same digests; after random edits of every
// kind, every quad whose elevation or appearance tile changed has a new digest (a quad whose tile
// changed under an old digest would keep a stale tile in the pyramid), and the digests of the quads
// away from the edit stay as they were; the elevation scope follows the elevation tile only.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "model/edits.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "raster/dem_source.h"
#include "raster/parallel_producers.h"
#include "synth/random_edits.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

constexpr int kLevel = 3;  // the quads compared: the 64 of level 3 and the 16 of level 2

// The tiles and digests of every quad of levels kLevel - 1 and kLevel, made from `scene` alone.
struct DigestedQuads {
    std::vector<AppearanceTile> appearance;
    std::vector<ElevationTile> elevation;
    std::vector<std::uint64_t> all, elevationOnly;  // QuadDigests::of, each scope
};

void collectDigestQuads(Quadtree& qt, Quad& q, std::vector<const Quad*>& out) {
    if (q.level >= kLevel - 1) out.push_back(&q);
    if (q.level == kLevel) return;
    if (q.isLeaf()) qt.subdivide(q);
    for (auto& c : q.children) collectDigestQuads(qt, *c, out);
}

DigestedQuads digested(const Scene& scene, const Dem& dem) {
    GraphStep step(scene);
    Quadtree qt(scene, {}, &step);
    std::vector<const Quad*> quads;
    collectDigestQuads(qt, qt.root(), quads);
    const InMemoryDem source(dem);
    CurveDataCache data(qt, source.heights());
    DigestedQuads m;
    m.appearance = produceAppearanceTiles(quads, qt, data, source, {});
    m.elevation = produceElevationTiles(quads, qt, data, source, {});
    const QuadDigests digests(qt, data);
    for (const Quad* q : quads) {
        m.all.push_back(digests.of(*q));
        m.elevationOnly.push_back(digests.of(*q, QuadDigestScope::Elevation));
    }
    return m;
}

struct DigestWorld {
    Scene scene;
    Dem dem;
};

DigestWorld digestWorld(std::uint64_t seed) {
    Scene scene = makeSyntheticScene({seed, 400});
    Dem dem = makeSyntheticDem(scene, {seed, 400});
    return {std::move(scene), std::move(dem)};
}

TEST(QuadDigest, TheSameSceneGivesTheSameDigests) {
    const DigestWorld w = digestWorld(3);
    const DigestedQuads a = digested(w.scene, w.dem);
    const Scene copy = w.scene;
    const DigestedQuads b = digested(copy, w.dem);
    ASSERT_EQ(a.all.size(), 64u + 16u);
    EXPECT_EQ(a.all, b.all);
    EXPECT_EQ(a.elevationOnly, b.elevationOnly);
    // Distinct quads of a scene have distinct digests (the digest covers the quad's place).
    std::vector<std::uint64_t> sorted = a.all;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());
}

// The property pyramid update rests on, over random edits of every kind (moves, inserts and
// deletions of vertices, nodes, curves and areas, widths, classes, bridge and tunnel flags,
// roundabouts): a tile that changed has a new digest, in both scopes.
TEST(QuadDigest, EveryQuadWhoseTilesAnEditChangesHasANewDigest) {
    DigestWorld w = digestWorld(26);
    std::mt19937_64 rng(26);
    DigestedQuads before = digested(w.scene, w.dem);
    std::size_t edits = 0, tilesChanged = 0, digestsChanged = 0, compared = 0;
    std::map<EditKind, std::size_t> kinds;
    const int tries = test::sanitizedOr(80, 16);
    for (int i = 0; i < tries; ++i) {
        const RandomEdit e = applyRandomEdit(w.scene, rng, 150.0);
        if (e.changeset.empty()) continue;
        ++edits;
        ++kinds[e.kind];
        const DigestedQuads after = digested(w.scene, w.dem);
        ASSERT_EQ(after.all.size(), before.all.size());
        for (std::size_t q = 0; q < after.all.size(); ++q) {
            const bool elevation = !(after.elevation[q] == before.elevation[q]);
            const bool appearance = !(after.appearance[q] == before.appearance[q]);
            SCOPED_TRACE("edit " + std::to_string(i) + " (" + std::string(toString(e.kind)) + "), quad " + std::to_string(q));
            if (elevation || appearance) {
                EXPECT_NE(after.all[q], before.all[q]) << "a tile changed under an unchanged digest";
            }
            if (elevation) {
                EXPECT_NE(after.elevationOnly[q], before.elevationOnly[q]) << "the elevation tile changed under an unchanged digest";
            }
            tilesChanged += elevation || appearance;
            digestsChanged += after.all[q] != before.all[q];
            ++compared;
        }
        before = after;
    }
    EXPECT_GE(edits, std::size_t(tries) / 2);
    EXPECT_GT(tilesChanged, 0u);
    // Conservative, not everything: the edits left most digests as they were.
    EXPECT_LT(digestsChanged, compared / 2);
    EXPECT_GE(digestsChanged, tilesChanged);
    std::printf("[ figures ] %zu edits of %zu kinds: %zu quad tiles changed, %zu digests changed, of %zu quads compared\n", edits,
                kinds.size(), tilesChanged, digestsChanged, compared);
}

// A field's border moved: the quads holding it get a new digest of their appearance, but their
// elevation scope (which the pyramid's mipmapped levels use) and their elevation tiles stay.
TEST(QuadDigest, TheElevationScopeIgnoresWhatTheElevationProducerDoesNotRead) {
    DigestWorld w = digestWorld(5);
    const DigestedQuads before = digested(w.scene, w.dem);
    LayerId fields = LayerId(w.scene.layers.size());
    for (LayerId l = 0; l < w.scene.layers.size(); ++l)
        if (w.scene.layers[l].kind == LayerKind::Fields) fields = l;
    ASSERT_LT(fields, w.scene.layers.size()) << "the synthetic scene has no fields layer";
    const Layer& layer = w.scene.layers[fields];
    ElementId border = kNoElement;
    for (ElementId c = 0; c < layer.curves.size() && border == kNoElement; ++c)
        if (layer.curves[c].alive && !layer.curves[c].areas.empty() && layer.curves[c].vertices.size() >= 3) border = c;
    ASSERT_NE(border, kNoElement);
    const Vertex& v = layer.curves[border].vertices[1];
    moveVertex(w.scene, fields, border, 1, v.p + Vec2(6.0, -4.0));
    const DigestedQuads after = digested(w.scene, w.dem);
    std::size_t appearanceChanged = 0;
    for (std::size_t q = 0; q < after.all.size(); ++q) {
        EXPECT_TRUE(after.elevation[q] == before.elevation[q]) << "quad " << q;
        EXPECT_EQ(after.elevationOnly[q], before.elevationOnly[q]) << "quad " << q;
        if (!(after.appearance[q] == before.appearance[q])) {
            ++appearanceChanged;
            EXPECT_NE(after.all[q], before.all[q]) << "quad " << q;
        }
    }
    EXPECT_GT(appearanceChanged, 0u);
}

}  // namespace
}  // namespace lacet
