#pragma once
// Work the live loop leaves to a thread of its own (editor/tile_loop.h: a slow quad's tiles,
// editor/background_subdivision.h: a subdivision of many elements). The thread runs in the idle
// scheduling class (Linux SCHED_IDLE): it takes only the CPU time that the frames and their
// workers leave, so a frame is never slowed by it, even on a machine with as many busy threads as
// cores; its cost is measured on threadCpuClock() (model/work_clock.h), which its waiting does
// not inflate.

#include <future>
#include <type_traits>
#include <utility>

namespace lacet {

// Lowers the calling thread to the idle scheduling class (where the system has one; else nothing).
void lowerToIdlePriority();

// Runs `f` on a new thread at idle priority; its result (or exception) through the future.
template <class F>
auto launchBackground(F&& f) -> std::future<std::invoke_result_t<std::decay_t<F>>> {
    return std::async(std::launch::async, [f = std::forward<F>(f)]() mutable {
        lowerToIdlePriority();
        return f();
    });
}

}  // namespace lacet
