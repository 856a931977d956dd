#pragma once
// Work the live loop leaves to threads of their own (editor/tile_loop.h: slow quads' tiles,
// editor/background_subdivision.h: subdivisions of many elements). The threads are made once and
// kept (a new thread per job would be joined by the frame that takes its result, after the
// thread's exit, which at idle priority may wait behind busy workers for many milliseconds, and
// would allocate the producers' per-thread buffers again). They run in the idle scheduling class
// (Linux SCHED_IDLE): they take only the CPU time that the frames and their workers leave, so a
// frame is never slowed by them, even with as many busy threads as cores. A job's cost is
// measured on threadCpuClock() (model/work_clock.h), which its waiting does not inflate.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <type_traits>
#include <vector>

namespace lacet {

// Lowers the calling thread to the idle scheduling class (where the system has one; else nothing).
void lowerToIdlePriority();

// Stops a job that checks `cancel` and waits for it: what it made (nullopt when it saw the flag,
// or failed: dropped either way; whoever wants the work does it again).
template <class T>
std::optional<T> stopJob(std::atomic<bool>& cancel, std::future<T>& result) {
    cancel.store(true);
    try {
        return result.get();
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

class BackgroundWorkers {
public:
    // `threads` (>= 1) kept at idle priority.
    explicit BackgroundWorkers(std::size_t threads);
    ~BackgroundWorkers();  // jobs not begun are dropped (their futures report a broken promise)
    BackgroundWorkers(const BackgroundWorkers&) = delete;
    BackgroundWorkers& operator=(const BackgroundWorkers&) = delete;

    // Runs `f` on one of the threads, in the order submitted; its result (or exception) through
    // the future, whose wait never joins a thread.
    template <class F>
    auto submit(F&& f) -> std::future<std::invoke_result_t<std::decay_t<F>>> {
        using R = std::invoke_result_t<std::decay_t<F>>;
        auto task = std::make_shared<std::packaged_task<R()>>(std::forward<F>(f));
        std::future<R> result = task->get_future();
        {
            const std::lock_guard lock(mutex_);
            queue_.emplace_back([task] { (*task)(); });
        }
        wake_.notify_one();
        return result;
    }
    std::size_t threads() const { return threads_.size(); }

private:
    void run();
    std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<std::function<void()>> queue_;
    bool stop_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace lacet
