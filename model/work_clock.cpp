#include "model/work_clock.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include <time.h>

namespace lacet {

using Clock = std::chrono::steady_clock;

namespace {
constexpr double kMaxStepMs = 3.6e6;  // an hour: far beyond any budget, far below the clock's range
}  // namespace

WorkClock realClock() { return &Clock::now; }

WorkClock threadCpuClock() {
    return [] {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return Clock::time_point(std::chrono::duration_cast<Clock::duration>(std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec)));
    };
}

WorkClock steppedClock(std::chrono::nanoseconds step) {
    if (step.count() <= 0) throw std::invalid_argument("steppedClock(): the step must be > 0 ns, not " + std::to_string(step.count()));
    auto ticks = std::make_shared<std::atomic<std::int64_t>>(0);
    const std::int64_t by = step.count();
    return [ticks, by] {
        const std::int64_t t = ticks->fetch_add(by, std::memory_order_relaxed) + by;
        return Clock::time_point(std::chrono::duration_cast<Clock::duration>(std::chrono::nanoseconds(t)));
    };
}

WorkClock steppedClockMs(double stepMs) {
    if (!std::isfinite(stepMs) || stepMs <= 0.0 || stepMs > kMaxStepMs)
        throw std::invalid_argument("steppedClockMs(): the step must be a number of ms in (0, " + std::to_string(kMaxStepMs) + "], not " +
                                    std::to_string(stepMs));
    return steppedClock(std::chrono::nanoseconds(std::max<std::int64_t>(1, std::llround(stepMs * 1e6))));
}

Deadline Deadline::after(Clock::time_point t0, double ms, WorkClock clock) {
    return {std::move(clock), t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double, std::milli>(std::max(0.0, ms)))};
}

}  // namespace lacet
