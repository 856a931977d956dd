#include "model/work_clock.h"

#include <chrono>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace lacet {
namespace {

using namespace std::chrono_literals;

TEST(WorkClock, ASteppedClockAdvancesOneStepAtEachReadingAndItsCopiesShareIt) {
    const WorkClock clock = steppedClock(250us);
    const auto t1 = clock();
    const WorkClock copy = clock;
    const auto t2 = copy();
    const auto t3 = clock();
    EXPECT_EQ(t2 - t1, 250us);
    EXPECT_EQ(t3 - t2, 250us);
    EXPECT_EQ(msBetween(t1, t3), 0.5);
    EXPECT_EQ(steppedClockMs(0.25)() - steppedClockMs(0.25)(), 0ns);  // two clocks: each its own time
}

TEST(WorkClock, ReadingsFromSeveralThreadsEachAdvanceItOnce) {
    const WorkClock clock = steppedClock(1ns);
    constexpr int kThreads = 4, kReadings = 10000;
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&] {
            for (int i = 0; i < kReadings; ++i) clock();
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(clock().time_since_epoch(), std::chrono::nanoseconds(std::int64_t(kThreads) * kReadings + 1));
}

TEST(WorkClock, ADeadlinePassesAfterItsStepsOnASteppedClockAndAtOnceForZero) {
    const WorkClock clock = steppedClockMs(1.0);
    const Deadline d = Deadline::after(clock(), 3.0, clock);
    EXPECT_FALSE(d.passed());  // +1 ms
    EXPECT_FALSE(d.passed());  // +2 ms
    EXPECT_TRUE(d.passed());   // +3 ms
    EXPECT_TRUE(Deadline::after(clock(), 0.0, clock).passed());
    EXPECT_TRUE(Deadline::after(clock(), -5.0, clock).passed());  // taken as 0
    const Deadline real = Deadline::after(realClock()(), 0.0, realClock());
    EXPECT_TRUE(real.passed());
}

TEST(WorkClock, StepsThatAreNotPositiveAreRefused) {
    EXPECT_THROW(steppedClock(0ns), std::invalid_argument);
    EXPECT_THROW(steppedClock(-1ns), std::invalid_argument);
    EXPECT_THROW(steppedClockMs(0.0), std::invalid_argument);
    EXPECT_THROW(steppedClockMs(-1.0), std::invalid_argument);
    EXPECT_THROW(steppedClockMs(1e300), std::invalid_argument);
    EXPECT_THROW(steppedClockMs(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(steppedClockMs(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

}  // namespace
}  // namespace lacet
