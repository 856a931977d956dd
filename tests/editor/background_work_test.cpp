// Background work of the live loop (issue 24, no slow frame; editor/tile_loop.h,
// editor/background_subdivision.h): tiles and subdivisions left to a thread of their own give
// exactly the tiles the frames make themselves, through edits that stop them and views that
// merge their quads away. The thread's progress is waited for (EditSession::waitForBackground),
// never timed; the budgets run on a stepped clock.
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "editor/edit_session.h"
#include "model/edits.h"
#include "model/work_clock.h"
#include "synth/random_edits.h"
#include "tests/editor/session_checks.h"

namespace lacet {
namespace {

using test::expectTilesEqualFromScratch;
using test::syntheticDocument;

// Small tiles, a 10 ms budget on a stepped clock, and every quad with an estimate left to the
// background (the first tiles and subdivisions, with none, are made in the frames).
SessionParams backgroundParams() {
    SessionParams params;
    params.refine.resolution = 32;
    params.view.maxLevel = 9;
    params.cacheTiles = 1u << 20;
    params.clock = steppedClockMs(0.05);
    params.backgroundMs = 1e-9;
    return params;
}

constexpr double kBudgetMs = 10.0;

struct Totals {
    std::size_t tilesBegun = 0, subdivisionsBegun = 0, dropped = 0, taken = 0;
    void add(const FrameReport& r) {
        tilesBegun += r.backgroundStarted;
        subdivisionsBegun += r.backgroundSubdivisions;
        dropped += r.backgroundDropped;
        taken += r.backgroundTaken;
    }
};

// Frames at `viewer` until the view is complete: nothing pending, deferred or in the background.
void completeView(EditSession& session, glm::dvec3 viewer, Totals& totals) {
    for (int i = 0; i < 100000; ++i) {
        const FrameReport r = session.frame(viewer, kBudgetMs);
        totals.add(r);
        if (r.pending == 0 && !r.refineDeferred && !session.backgroundBusy()) return;
        session.waitForBackground();
    }
    FAIL() << "the view did not complete";
}

// A road or river vertex (or node) moved by up to 30 m.
Command randomMove(const Scene& s, std::mt19937_64& rng) {
    const LayerId layer = uniform01(rng) < 0.7 ? kRoadsLayer : kRiversLayer;
    const Layer& l = s.layers[layer];
    const Vec2 by(uniform01(rng) * 60.0 - 30.0, uniform01(rng) * 60.0 - 30.0);
    for (;;) {
        const ElementId c = ElementId(uniform01(rng) * double(l.curves.size())) % ElementId(l.curves.size());
        const auto& v = l.curves[c].vertices;
        if (!l.curves[c].alive || v.size() < 3) continue;
        if (uniform01(rng) < 0.3 && l.curves[c].start != kNoElement)
            return MoveNodeCmd{layer, l.curves[c].start, l.nodes[l.curves[c].start].p + by};
        const std::size_t i = 1 + std::size_t(uniform01(rng) * double(v.size() - 2)) % (v.size() - 2);
        return MoveVertexCmd{layer, c, i, v[i].p + by};
    }
}

// Edits right after a frame that left work to the background stop it; what the frames and the
// background make in the end equals tiles made from scratch, view after view, edit after edit.
TEST(BackgroundWork, TilesAndSubdivisionsMadeInTheBackgroundEqualTilesMadeFromScratchThroughEdits) {
    const SessionParams params = backgroundParams();
    EditSession session(syntheticDocument(5, 1500), params);
    const Box e = session.document().scene.extent;
    std::mt19937_64 rng(17);
    Totals totals;
    std::size_t edits = 0;
    for (int round = 0; round < 4; ++round) {
        const Vec2 p = e.min + Vec2(uniform01(rng), uniform01(rng)) * e.size();
        const glm::dvec3 viewer(p.x, p.y, 20.0 + 400.0 * uniform01(rng));
        // A few frames, each followed by an edit while their background work may be in flight.
        for (int k = 0; k < 3; ++k) {
            totals.add(session.frame(viewer, kBudgetMs));
            try {
                totals.dropped += session.execute(randomMove(session.document().scene, rng)).backgroundStopped;
                ++edits;
            } catch (const EditError&) {
            }
        }
        completeView(session, viewer, totals);
        expectTilesEqualFromScratch(session, params, "round " + std::to_string(round));
    }
    EXPECT_GE(edits, 8u);
    EXPECT_GT(totals.tilesBegun, 100u);
    EXPECT_GT(totals.subdivisionsBegun, 20u);
    EXPECT_GT(totals.taken, 100u);
    EXPECT_GT(totals.dropped, 0u);  // by the edits
    std::cout << "[ figures  ] " << totals.tilesBegun << " quads' tiles and " << totals.subdivisionsBegun
              << " subdivisions begun in the background, " << totals.taken << " taken, " << totals.dropped << " dropped, "
              << edits << " edits\n";
}

// A viewer that jumps away while a subdivision deep under it is being made merges that quad's
// ancestors: the work is stopped before the merge (it reads the quad), and the new view is exact.
TEST(BackgroundWork, AViewerJumpingAwayStopsTheWorkOnQuadsItMergesAway) {
    const SessionParams params = backgroundParams();
    EditSession session(syntheticDocument(8, 1200), params);
    const Box e = session.document().scene.extent;
    const Vec2 a = e.min + 0.2 * e.size(), b = e.min + 0.85 * e.size();
    Totals totals;
    completeView(session, glm::dvec3(a.x, a.y, 25.0), totals);
    // Nearby, lower: deeper quads wanted near the first view.
    const FrameReport near = session.frame(glm::dvec3(a.x + 60.0, a.y + 40.0, 8.0), kBudgetMs);
    ASSERT_GT(near.backgroundSubdivisions, 0u);
    ASSERT_TRUE(session.backgroundBusy());
    const FrameReport far = session.frame(glm::dvec3(b.x, b.y, 10.0), kBudgetMs);
    EXPECT_GE(far.backgroundDropped, 1u);
    completeView(session, glm::dvec3(b.x, b.y, 10.0), totals);
    expectTilesEqualFromScratch(session, params, "after the jump");
}

// Without a frame budget, or with the knob at 0, nothing is left to the background.
TEST(BackgroundWork, NothingIsLeftToTheBackgroundWithoutABudgetOrTheKnob) {
    SessionParams params = backgroundParams();
    EditSession unbudgeted(syntheticDocument(5, 600), params);
    params.backgroundMs = 0.0;
    EditSession off(syntheticDocument(5, 600), params);
    const Vec2 c = unbudgeted.document().scene.extent.center();
    for (int i = 0; i < 5; ++i) {
        const glm::dvec3 viewer(c.x + 100.0 * i, c.y, 30.0);
        const FrameReport r = unbudgeted.frame(viewer, 0.0);
        EXPECT_EQ(r.backgroundStarted + r.backgroundSubdivisions, 0u);
        EXPECT_EQ(r.pending, 0u);
        const FrameReport s = off.frame(viewer, kBudgetMs);
        EXPECT_EQ(s.backgroundStarted + s.backgroundSubdivisions, 0u);
        EXPECT_FALSE(unbudgeted.backgroundBusy() || off.backgroundBusy());
    }
}

}  // namespace
}  // namespace lacet
