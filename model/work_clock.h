#pragma once
// The clock that time budgets are read on: a frame's tile production budget, the refinement's
// deadline. By default the machine's monotonic clock; a test or a script gives a stepped clock,
// which advances a fixed step each time it is read, so that what a budget lets through depends on
// the work done (how many times the clock was read), not on how fast the machine runs it: a
// sanitized build on a loaded machine then decides exactly as a fast one does.
//
// Work sliced across calls under a Deadline always does its first unit, whatever the deadline
// (see Quadtree::refineForViewers): a budget shorter than one unit slows the work down, it never
// stops it.

#include <chrono>
#include <functional>

namespace lacet {

using WorkClock = std::function<std::chrono::steady_clock::time_point()>;

// std::chrono::steady_clock::now.
WorkClock realClock();
// A clock that starts at the steady clock's epoch and advances by `step` (> 0) at each reading.
// Its copies share one time; reading it from several threads is safe (each reading advances it
// once). Throws std::invalid_argument when step <= 0.
WorkClock steppedClock(std::chrono::nanoseconds step);
// The same with the step in milliseconds (a script's or a command line's unit), at most an hour;
// a step under a nanosecond is one nanosecond.
WorkClock steppedClockMs(double stepMs);
// The CPU time of the thread that reads it (on its own time line: compare readings of one thread
// only): what work on a thread that others preempt costs (editor/background_work.h).
WorkClock threadCpuClock();

// Milliseconds between two readings.
inline double msBetween(std::chrono::steady_clock::time_point t0, std::chrono::steady_clock::time_point t1) {
    return std::chrono::duration<double, std::milli>(t1 - t0).count();
}
// Milliseconds from `t0`, a reading of `clock`, to its reading now.
inline double msSince(const WorkClock& clock, std::chrono::steady_clock::time_point t0) { return msBetween(t0, clock()); }
// Milliseconds from `t0` to now on the steady clock (what a report states as time taken).
inline double msSince(std::chrono::steady_clock::time_point t0) { return msBetween(t0, std::chrono::steady_clock::now()); }

// A point on a work clock past which sliced work starts no new unit but its first.
struct Deadline {
    WorkClock clock;
    std::chrono::steady_clock::time_point at;
    // `ms` (>= 0; less is taken as 0) after `t0`, a reading of `clock`.
    static Deadline after(std::chrono::steady_clock::time_point t0, double ms, WorkClock clock);
    bool passed() const { return clock() >= at; }
};

}  // namespace lacet
