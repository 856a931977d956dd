#include "editor/background_work.h"

#include <algorithm>

#include <pthread.h>
#include <sched.h>

namespace lacet {

void lowerToIdlePriority() {
#ifdef SCHED_IDLE
    sched_param param{};
    param.sched_priority = 0;
    pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);  // refused: it runs as it is
#endif
}

BackgroundWorkers::BackgroundWorkers(std::size_t threads) {
    for (std::size_t i = 0; i < std::max<std::size_t>(1, threads); ++i) threads_.emplace_back([this] { run(); });
}

BackgroundWorkers::~BackgroundWorkers() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
        queue_.clear();
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void BackgroundWorkers::run() {
    lowerToIdlePriority();
    for (;;) {
        std::function<void()> job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (stop_) return;
            job = std::move(queue_.front());
            queue_.pop_front();
        }
        job();  // a packaged task: its exception goes to its future
    }
}

}  // namespace lacet
