#include "editor/background_subdivision.h"

#include <chrono>

#include <tbb/task_arena.h>

#include "editor/background_work.h"
#include "model/work_clock.h"

namespace lacet {

std::optional<QuadChildren> BackgroundSubdivision::children(const Quadtree& tree, const Quad& q) {
    if (job_ && job_->quad == &q && job_->tree == &tree) {
        job_->asked = true;
        if (job_->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
        Job job = std::move(*job_);
        job_.reset();
        return job.result.get();  // an error surfaces here, as a subdivision's at once would
    }
    const std::size_t elements = elementCount(q);  // the root's (the scene's) counts none: made at once
    const WorkClock& clock = params_.clock;
    // At once: without the knob, the root (the scene's graph: nothing to show meanwhile), or a leaf
    // within what was measured (a larger one is not trusted to the line's extrapolation) and
    // estimated to be quick.
    if (!(params_.backgroundMs > 0.0) || !q.parent || !estimate_.mayExceed(elements, params_.backgroundMs)) {
        const auto t0 = clock();
        QuadChildren kids = tree.makeChildren(q);
        if (q.parent) estimate_.add(elements, msSince(clock, t0));  // the root's (the scene's) says nothing of the others'
        return kids;
    }
    // One at a time: q waits (children made for a leaf that a whole refinement no longer asks for
    // are dropped by settle(), not here: the leaf may come later in this one).
    if (job_) return std::nullopt;
    Job job;
    job.tree = &tree;
    job.quad = &q;
    job.asked = true;
    job.cancel = std::make_unique<CancelFlag>(false);
    if (!workers_) workers_ = std::make_unique<BackgroundWorkers>(1);
    job.result = workers_->submit([this, &tree, &q, cancel = job.cancel.get(), elements] {
        const WorkClock cpu = threadCpuClock();
        const auto t0 = cpu();
        // An arena of its own: the frame's parallel loops never pick up this subdivision's tasks
        // (nor it theirs) while they wait for their own.
        tbb::task_arena arena(1);
        QuadChildren kids = arena.execute([&] { return tree.makeChildren(q, cancel); });
        estimate_.add(elements, msSince(cpu, t0));
        return kids;
    });
    job_ = std::move(job);
    ++begun_;
    return std::nullopt;
}

std::size_t BackgroundSubdivision::settle() {
    if (!job_) return 0;
    if (job_->asked) {
        job_->asked = false;
        return 0;
    }
    return quiesce();
}

std::size_t BackgroundSubdivision::quiesce() {
    if (!job_) return 0;
    // Made before the flag was seen: freed on the worker, not by the frame (a coarse leaf's
    // children hold all its elements).
    if (std::optional<QuadChildren> made = stopJob(*job_->cancel, job_->result)) {
        auto kids = std::make_shared<QuadChildren>(std::move(*made));
        workers_->submit([kids] {
            for (auto& kid : *kids) kid.reset();
        });
    }
    job_.reset();
    return 1;
}

}  // namespace lacet
