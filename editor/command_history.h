#pragma once
// The editing session's undo/redo history (§6; the commands and their exact inverses are
// editor/command.h): the commands applied to a scene, newest last, and those undone, kept for
// redo until the next command. It applies, undoes and redoes commands on the scene it is given
// and hands each resulting changeset to the caller (the session updates its quadtree and tiles
// from it); it knows no quadtree and no tile.
//
// Undo granularity: with `merge`, a command that continues a drag of the same vertex or node as
// the last one joins its undo step (undo goes back to where the drag began), unless that step was
// saved (a save between two moves splits the drag, so that modified() tells the truth). Commands
// run between beginGroup() and endGroup() are undone and redone together (a new road: its nodes,
// then its curve).
//
// Saved state: every step has a serial; the history is modified() when its newest step's serial
// is not the one markSaved() recorded.

#include <cstdint>
#include <functional>
#include <vector>

#include "editor/command.h"
#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

class CommandHistory {
public:
    // Called with each changeset the history applies to the scene, in order, and the time the
    // edit took (ms).
    using AfterEdit = std::function<void(const Changeset& changeset, double applyMs)>;

    // Applies `command` to `scene` (EditError leaves both as they were), clears the redo stack,
    // records the step and calls `after` with its changeset.
    void execute(Scene& scene, const Command& command, bool merge, const AfterEdit& after);
    void beginGroup() { group_ = ++nextGroup_; }
    void endGroup() { group_ = 0; }
    // Undoes the last step (a group whole) / redoes the last undone one, calling `after` for each
    // command; false when there is none.
    bool undo(Scene& scene, const AfterEdit& after);
    bool redo(Scene& scene, const AfterEdit& after);
    std::size_t undoDepth() const { return done_.size(); }
    std::size_t redoDepth() const { return undone_.size(); }
    // Forgets the redo history (a group taken back because it was refused is no step to redo).
    void forgetRedo() { undone_.clear(); }

    bool modified() const { return savedSerial_ != topSerial(); }
    void markSaved() { savedSerial_ = topSerial(); }

private:
    struct Done {
        Command command;
        Applied applied;
        std::uint64_t group = 0;   // 0: alone
        std::uint64_t serial = 0;  // identifies the scene state after it (for modified())
    };
    std::uint64_t topSerial() const { return done_.empty() ? 0 : done_.back().serial; }

    std::vector<Done> done_;
    std::vector<Done> undone_;  // command, group and serial kept for redo
    std::uint64_t serial_ = 0, savedSerial_ = 0;
    std::uint64_t group_ = 0, nextGroup_ = 0;
};

}  // namespace lacet
