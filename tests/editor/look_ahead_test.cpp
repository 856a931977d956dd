// The live loop's look-ahead (editor/look_ahead.h): the camera's last move continued for the
// frames ahead, none on the first frame or while the camera stands still, the height above the
// ground kept at least 1 m, and the refine budget a share of the frame's.
#include "editor/look_ahead.h"

#include <gtest/gtest.h>

namespace lacet {
namespace {

TEST(LookAhead, ContinuesTheLastMoveForTheFramesAhead) {
    LookAhead la({.framesAhead = 10.0});
    const FrameViewers first = la.next({100.0, 200.0, 500.0}, 80.0);
    EXPECT_EQ(first.viewer, glm::dvec3(100.0, 200.0, 80.0));
    EXPECT_FALSE(first.predicted) << "no move is known on the first frame";
    const FrameViewers second = la.next({103.0, 196.0, 498.0}, 78.0);
    EXPECT_EQ(second.viewer, glm::dvec3(103.0, 196.0, 78.0));
    ASSERT_TRUE(second.predicted);
    EXPECT_EQ(*second.predicted, glm::dvec3(133.0, 156.0, 58.0));  // the height above the ground moves with the eye
}

TEST(LookAhead, NoPredictionWhileStillAndTheHeightStaysAboveTheGround) {
    LookAhead la({.framesAhead = 30.0, .stillFraction = 1e-3});
    la.next({0.0, 0.0, 100.0}, 100.0);
    EXPECT_FALSE(la.next({0.05, 0.0, 100.0}, 100.0).predicted) << "a move under 0.1 m at 100 m is standing still";
    const FrameViewers down = la.next({0.05, 0.0, 90.0}, 5.0);  // diving: 30 frames ahead would be far below the ground
    ASSERT_TRUE(down.predicted);
    EXPECT_EQ(down.predicted->z, 1.0);
    la.reset();
    EXPECT_FALSE(la.next({500.0, 0.0, 90.0}, 5.0).predicted) << "after a jump nothing is predicted from the old place";
}

TEST(LookAhead, TheRefineBudgetIsTheShareOfTheFrames) {
    EXPECT_EQ(LookAhead().refineBudgetMs(12.0), 6.0);
    EXPECT_EQ(LookAhead({.refineShare = 0.25}).refineBudgetMs(12.0), 3.0);
    EXPECT_EQ(LookAhead().refineBudgetMs(0.0), 0.0) << "no frame budget: refine completely";
}

}  // namespace
}  // namespace lacet
