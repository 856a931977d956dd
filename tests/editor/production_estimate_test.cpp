// The oracle of a tile's production time (editor/production_estimate.h): it learns the line
// through what tiles cost against what their quads hold, follows a change of cost, and stays
// usable before any spread in sizes.
#include "editor/production_estimate.h"

#include <random>

#include <gtest/gtest.h>

namespace lacet {
namespace {

TEST(ProductionEstimate, KnowsNothingBeforeItsFirstTile) { EXPECT_EQ(ProductionEstimate{}.predict(1000), 0.0); }

TEST(ProductionEstimate, LearnsTheCostOfACoarseQuadFromNoisySamples) {
    // Leaves hold a few elements and cost about 1 ms; coarse quads thousands and cost more.
    ProductionEstimate e;
    std::mt19937_64 rng(3);
    std::uniform_int_distribution<int> leaf(0, 40);
    std::normal_distribution<double> noise(0.0, 0.1);
    for (int i = 0; i < 400; ++i) {
        const std::size_t x = i % 50 == 0 ? 3000 + std::size_t(leaf(rng)) * 50 : std::size_t(leaf(rng));
        e.add(x, 1.0 + 0.004 * double(x) + noise(rng));
    }
    EXPECT_NEAR(e.predict(10), 1.04, 0.1);
    EXPECT_NEAR(e.predict(5000), 21.0, 2.0);  // what a frame budget must not start blindly
}

TEST(ProductionEstimate, IsTheMeanWhenEveryQuadHoldsTheSame) {
    ProductionEstimate e;
    for (int i = 0; i < 10; ++i) e.add(7, i % 2 ? 1.0 : 3.0);
    EXPECT_NEAR(e.predict(7), 2.0, 0.15);
    EXPECT_NEAR(e.predict(7000), 2.0, 0.15);  // no slope can be known yet
}

TEST(ProductionEstimate, FollowsACostThatChanges) {
    ProductionEstimate e;
    for (int i = 0; i < 500; ++i) e.add(std::size_t(i % 10), 1.0);
    for (int i = 0; i < 1500; ++i) e.add(std::size_t(i % 10), 4.0);  // a larger texture resolution, say
    EXPECT_NEAR(e.predict(5), 4.0, 0.05);
}

}  // namespace
}  // namespace lacet
