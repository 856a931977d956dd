// Frame-rate-adaptive K (editor/adaptive_quality.h): lowered while frames run over the target,
// raised back to the user's K when there is room and the view is complete, never past its bounds.
#include <stdexcept>

#include <gtest/gtest.h>

#include "editor/adaptive_quality.h"

namespace lacet {
namespace {

TEST(AdaptiveQuality, LowersWhileFramesRunOverThenRaisesBackToTheUsersK) {
    AdaptiveQualityParams p;
    p.targetMs = 10.0;
    p.minK = 1.5;
    p.window = 5;
    AdaptiveQuality a(4.0, p);
    // Slow frames: K falls by `lower` once per window, down to minK and no further.
    double k = a.K();
    for (int f = 0; f < 200; ++f) {
        const double next = a.onFrame(25.0, false);
        EXPECT_LE(next, k);
        k = next;
    }
    EXPECT_DOUBLE_EQ(a.K(), 1.5);
    EXPECT_GT(a.lowered(), 3);
    // Fast frames with work still pending: no raise (it would add work to a busy view).
    for (int f = 0; f < 50; ++f) a.onFrame(1.0, false);
    EXPECT_DOUBLE_EQ(a.K(), 1.5);
    // Fast, complete frames: back up to the user's K, never past it.
    for (int f = 0; f < 500; ++f) a.onFrame(1.0, true);
    EXPECT_DOUBLE_EQ(a.K(), 4.0);
    EXPECT_GT(a.raised(), 3);
}

TEST(AdaptiveQuality, OneSlowFrameInAWindowChangesNothing) {
    AdaptiveQualityParams p;
    p.targetMs = 10.0;
    p.window = 5;
    AdaptiveQuality a(3.0, p);
    for (int f = 0; f < 100; ++f) a.onFrame(f % 5 == 0 ? 500.0 : 8.0, true);  // median 8: between room and target
    EXPECT_DOUBLE_EQ(a.K(), 3.0);
    EXPECT_EQ(a.lowered(), 0);
    EXPECT_EQ(a.raised(), 0);
}

TEST(AdaptiveQuality, TheUsersKIsTheCeilingAndBadKnobsAreRefused) {
    AdaptiveQualityParams p;
    p.window = 1;
    p.targetMs = 10.0;
    AdaptiveQuality a(2.0, p);
    a.onFrame(100.0, false);
    EXPECT_LT(a.K(), 2.0);
    a.setUserK(6.0);
    EXPECT_DOUBLE_EQ(a.K(), 6.0);
    EXPECT_THROW(a.setUserK(0.0), std::invalid_argument);
    p.lower = 1.0;
    EXPECT_THROW(AdaptiveQuality(2.0, p), std::invalid_argument);
    EXPECT_THROW(AdaptiveQuality(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace lacet
