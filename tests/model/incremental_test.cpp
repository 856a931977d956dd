// Invariant: after every edit, the incrementally updated quadtree equals a rebuild from scratch
// (elements, geometry bit for bit, ancestors, CREATEDFROM). Randomized with fixed seeds.
#include <map>

#include <gtest/gtest.h>

#include "model/quadtree_compare.h"
#include "model/validate.h"
#include "synth/incremental_check.h"
#include "synth/random_edits.h"
#include "synth/synthetic_scene.h"
#include "tests/model/small_scene.h"
#include "tests/sanitized.h"
#include "tests/model/split_roads.h"

namespace lacet {
namespace {

struct EditRun {
    std::size_t edits = 0;
    std::map<EditKind, std::size_t> byKind;
};

// Applies `edits` random edits; after each, updates the quadtree, and every `viewEvery` edits moves
// the viewer (subdividing and merging quads). Compares with a rebuild after every edit
// (synth/incremental_check.h), stopping at the first mismatch.
EditRun checkIncremental(Scene& s, std::uint64_t seed, int edits, int maxLevel, double reach, int viewEvery,
                         ProceduralStep* procedural = nullptr) {
    const IncrementalCheckReport r = checkIncremental(s, {.seed = seed, .edits = edits, .maxLevel = maxLevel, .viewEvery = viewEvery,
                                                          .reach = reach, .procedural = procedural,
                                                          .stopAtFirstMismatch = true});
    EXPECT_EQ(r.mismatches, 0u) << "seed " << seed << " " << (r.details.empty() ? "" : r.details[0]);
    EXPECT_TRUE(validate(s).empty());
    return {r.edits, r.byKind};
}

TEST(Incremental, RandomEditsOfEveryKindOnASmallSceneEqualRebuild) {
    EditRun total;
    const int seeds = test::sanitizedOr(4, 2);
    for (std::uint64_t seed = 1; seed <= std::uint64_t(seeds); ++seed) {
        Scene s = test::smallScene();
        const EditRun r = checkIncremental(s, seed, 400, 7, 150.0, 25);
        total.edits += r.edits;
        for (auto [k, n] : r.byKind) total.byKind[k] += n;
    }
    EXPECT_GT(total.edits, 250u * std::size_t(seeds));
    for (int k = 0; k < int(EditKind::Count); ++k) EXPECT_GT(total.byKind[EditKind(k)], 10u) << toString(EditKind(k));
}

TEST(Incremental, RandomEditsWithAProceduralStepEqualRebuild) {
    test::SplitRoadsInTwo step;
    std::size_t edits = 0;
    for (std::uint64_t seed = 20; seed <= 21; ++seed) {
        Scene s = test::smallScene();
        edits += checkIncremental(s, seed, 300, 7, 150.0, 25, &step).edits;
    }
    EXPECT_GT(edits, 400u);
}

TEST(Incremental, RandomEditsOnSyntheticScenesEqualRebuild) {
    std::size_t edits = 0;
    const int perScene = test::sanitizedOr(300, 100);
    for (std::uint64_t seed = 10; seed <= 12; ++seed) {
        Scene s = makeSyntheticScene({seed, 400});
        edits += checkIncremental(s, seed, perScene, 8, 0.05 * s.extent.size().x, 30).edits;
    }
    EXPECT_GT(edits, std::size_t(2 * perScene));
}

// The sampled check (lacet check incremental --sample): random quads, each rebuilt alone along its
// path, and every quad every fullEvery edits; it finds no mismatch where the full check finds none,
// compares what it says, and a quad of a tree built from another scene does differ.
TEST(Incremental, TheSampledCheckComparesRandomQuadsAndEveryQuadNowAndThen) {
    Scene s = makeSyntheticScene({21, 400});
    const IncrementalCheckReport r = checkIncremental(s, {.seed = 21, .edits = 200, .maxLevel = 8, .viewEvery = 20,
                                                          .reach = 0.05 * s.extent.size().x, .sample = 6, .fullEvery = 25});
    EXPECT_EQ(r.mismatches, 0u) << (r.details.empty() ? "" : r.details[0]);
    ASSERT_GT(r.edits, 100u);
    EXPECT_EQ(r.fullComparisons, r.edits / 25);
    EXPECT_GT(r.quadsCompared, (r.edits - r.fullComparisons) * 6);  // and the full comparisons' quads
    // A quad of the same place in a tree of another scene: a difference the sampled compare sees.
    Scene other = makeSyntheticScene({22, 400});
    Quadtree a(s, {}), b(other, {});
    const Quad& qa = a.reach(3, 2, 5);
    EXPECT_GT(compareQuads(qa, b.reach(3, 2, 5)).mismatches, 0u);
    Quadtree same(s, {});
    const QuadtreeDiff d = compareQuads(qa, same.reach(3, 2, 5));
    EXPECT_EQ(d.mismatches, 0u) << (d.details.empty() ? "" : d.details[0]);
}

// Undo and redo (§6) in the check: after every undo (the edit's changeset reversed) and every redo
// the updated quadtree equals a rebuild. With every edit undone and none redone, the check's own
// restoration leaves the scene it started from, element for element, slots included.
TEST(Incremental, UndoneAndRedoneEditsEqualRebuildAndUndoingAllRestoresTheScene) {
    std::size_t undos = 0, redos = 0;
    for (std::uint64_t seed = 31; seed <= 32; ++seed) {
        Scene s = test::smallScene();
        const IncrementalCheckReport r = checkIncremental(s, {.seed = seed, .edits = test::sanitizedOr(300, 60), .maxLevel = 7,
                                                              .viewEvery = 25, .reach = 150.0, .undoChance = 0.5,
                                                              .stopAtFirstMismatch = true});
        EXPECT_EQ(r.mismatches, 0u) << "seed " << seed << " " << (r.details.empty() ? "" : r.details[0]);
        EXPECT_TRUE(validate(s).empty());
        undos += r.undos;
        redos += r.redos;
    }
    EXPECT_GT(undos, test::sanitizedOr(100, 20));
    EXPECT_GT(redos, test::sanitizedOr(40, 6));
    EXPECT_LT(redos, undos);

    Scene s = makeSyntheticScene({33, 400});
    const Scene start = s;
    const IncrementalCheckReport r = checkIncremental(s, {.seed = 33, .edits = test::sanitizedOr(200, 30), .maxLevel = 8, .viewEvery = 20,
                                                          .reach = 0.05 * s.extent.size().x, .undoChance = 1.0, .redoChance = 0.0,
                                                          .stopAtFirstMismatch = true});
    EXPECT_EQ(r.mismatches, 0u) << (r.details.empty() ? "" : r.details[0]);
    EXPECT_EQ(r.undos, r.edits);
    EXPECT_EQ(r.redos, 0u);
    ASSERT_EQ(s.layers.size(), start.layers.size());
    for (std::size_t l = 0; l < s.layers.size(); ++l) {
        EXPECT_EQ(s.layers[l].nodes, start.layers[l].nodes) << "layer " << l;
        EXPECT_EQ(s.layers[l].curves, start.layers[l].curves) << "layer " << l;
        EXPECT_EQ(s.layers[l].areas, start.layers[l].areas) << "layer " << l;
    }
}

}  // namespace
}  // namespace lacet
