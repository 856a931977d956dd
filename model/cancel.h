#pragma once
// Work cancelled from another thread (editor/tile_loop.h: a quad's tiles or children made in the
// background, dropped when an edit changes what they read). The producers and
// Quadtree::makeChildren check the flag between the elements they handle and throw WorkCancelled
// once it is set; what they made is dropped, and their per-thread buffers are left ready for the
// next call.

#include <atomic>
#include <stdexcept>

namespace lacet {

using CancelFlag = std::atomic<bool>;

struct WorkCancelled : std::runtime_error {
    WorkCancelled() : std::runtime_error("cancelled") {}
};

// Throws WorkCancelled when `cancel` (may be null: never) is set.
inline void throwIfCancelled(const CancelFlag* cancel) {
    if (cancel && cancel->load(std::memory_order_relaxed)) throw WorkCancelled();
}

}  // namespace lacet
