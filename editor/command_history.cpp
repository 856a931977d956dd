#include "editor/command_history.h"

#include <chrono>
#include <utility>
#include <variant>

#include "model/work_clock.h"

namespace lacet {
namespace {

using Clock = std::chrono::steady_clock;

}  // namespace

void CommandHistory::execute(Scene& scene, const Command& command, bool merge, const AfterEdit& after) {
    const auto t0 = Clock::now();
    Applied a = lacet::apply(scene, command);
    const double ms = msSince(t0);
    undone_.clear();
    const Changeset cs = a.changeset;
    if (merge && !done_.empty() && continuesDrag(done_.back().command, command) && done_.back().serial != savedSerial_) {
        // One undo step: the first command's snapshot, both changesets.
        Done& last = done_.back();
        last.command = command;
        last.applied.changeset.append(a.changeset);
        last.applied.changeset.normalize();
        last.serial = ++serial_;
    } else {
        done_.push_back({command, std::move(a), group_, ++serial_});
    }
    after(cs, ms);
}

bool CommandHistory::undo(Scene& scene, const AfterEdit& after) {
    if (done_.empty()) return false;
    const std::uint64_t group = done_.back().group;
    do {
        const auto t0 = Clock::now();
        const Changeset cs = lacet::undo(scene, done_.back().applied);
        const double ms = msSince(t0);
        undone_.push_back(std::move(done_.back()));
        done_.pop_back();
        after(cs, ms);
    } while (group != 0 && !done_.empty() && done_.back().group == group);
    return true;
}

bool CommandHistory::redo(Scene& scene, const AfterEdit& after) {
    if (undone_.empty()) return false;
    const std::uint64_t group = undone_.back().group;
    do {
        Done d = std::move(undone_.back());
        undone_.pop_back();
        const auto t0 = Clock::now();
        d.applied = lacet::apply(scene, d.command);
        const double ms = msSince(t0);
        done_.push_back(std::move(d));
        after(done_.back().applied.changeset, ms);
    } while (group != 0 && !undone_.empty() && undone_.back().group == group);
    return true;
}

}  // namespace lacet
