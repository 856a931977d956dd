#pragma once
// What the editing session's tests share: a synthetic document, and the check that every leaf of
// a session's tree has a clean tile equal to one made from scratch (incremental equals rebuild
// through the live loop).
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "editor/edit_session.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"

namespace lacet::test {

// A synthetic scene of `curves` curves and its DEM (1000 x 1000 samples).
inline SceneDocument syntheticDocument(std::uint64_t seed, std::size_t curves) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({seed, curves});
    doc.dem = makeSyntheticDem(doc.scene, {seed, 1000});
    return doc;
}

// Every leaf of the session's tree has a clean tile equal to one made from scratch (more than 50).
inline void expectTilesEqualFromScratch(const EditSession& session, const SessionParams& params, const std::string& when) {
    GraphStep step(session.document().scene, params.graph);
    Quadtree fresh(session.document().scene, params.refine, &step);
    fresh.copyStructureOf(session.quadtree());
    DemHeightField heights(*session.document().dem);
    CurveDataCache data(fresh, heights, params.profiles);
    std::size_t compared = 0;
    fresh.forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        const CachedTile* t = session.tile(keyOf(q));
        ASSERT_NE(t, nullptr) << when;
        EXPECT_FALSE(t->dirty) << when;
        EXPECT_TRUE(t->appearance == produceAppearance(q, fresh, data, *session.document().dem, params.appearance)) << when;
        EXPECT_TRUE(t->elevation == produceElevation(q, fresh, data, *session.document().dem, params.elevation)) << when;
        ++compared;
    });
    EXPECT_GT(compared, 50u) << when;
}

}  // namespace lacet::test
