#pragma once
// Subdivisions of leaves of many elements made on a background thread (issue 24: no slow frame):
// the ChildMaker (model/quadtree.h) the live loop (editor/tile_loop.h) refines with when
// SessionParams::backgroundMs is set. A leaf whose subdivision is estimated (from its element
// count, editor/production_estimate.h) to take longer than the knob gets its children made by
// Quadtree::makeChildren on a thread of its own, one leaf at a time, and stays a leaf (its
// subdivision deferred) until a refinement finds them made and attaches them; the others are
// subdivided at once, timed into the estimate (a leaf larger than any measured is not trusted to
// it: its children are made there). Children made for a leaf that the next refinement
// no longer subdivides are dropped.
//
// The thread reads the leaf's graph, the scene and the procedural curves: the loop stops it
// (quiesce) before anything changes them (an edit, a new tree) and before a refinement that
// would merge the leaf away (QuadForest::keeps); makeChildren checks its cancel flag between
// elements, so no edit waits for a subdivision.

#include <cstddef>
#include <future>
#include <memory>
#include <optional>

#include "editor/background_work.h"
#include "editor/production_estimate.h"
#include "editor/session_params.h"
#include "model/quadtree.h"

namespace lacet {

class BackgroundSubdivision final : public ChildMaker {
public:
    // `params` (its backgroundMs and clock, read at each call) must outlive this.
    explicit BackgroundSubdivision(const SessionParams& params) : params_(params) {}
    ~BackgroundSubdivision() override { quiesce(); }
    BackgroundSubdivision(const BackgroundSubdivision&) = delete;
    BackgroundSubdivision& operator=(const BackgroundSubdivision&) = delete;

    std::optional<QuadChildren> children(const Quadtree& tree, const Quad& q) override;
    // After each refinement: drops children made for a leaf it did not ask for. Returns how many
    // were dropped (0 or 1).
    std::size_t settle();
    // Stops the thread, dropping what it makes, and waits for it; returns how many were dropped.
    std::size_t quiesce();
    // Waits until the children being made are made (the next refinement that asks takes them).
    void wait() {
        if (job_) job_->result.wait();
    }
    // The leaf whose children are being made or wait, or nullptr.
    const Quad* leaf() const { return job_ ? job_->quad : nullptr; }
    std::size_t begun() const { return begun_; }  // subdivisions begun in the background so far

private:
    struct Job {
        const Quadtree* tree = nullptr;
        const Quad* quad = nullptr;
        std::unique_ptr<CancelFlag> cancel;
        std::future<QuadChildren> result;
        bool asked = false;  // by the refinement since the last settle()
    };
    const SessionParams& params_;
    std::optional<Job> job_;
    ProductionEstimate estimate_;  // a subdivision's time by the leaf's elements
    std::size_t begun_ = 0;
    std::unique_ptr<BackgroundWorkers> workers_;  // one thread, made at the first job
};

}  // namespace lacet
