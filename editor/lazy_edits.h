#pragma once
// Edits of a scene file read lazily (issue 23: editing a partial scene; §6 over §7's out-of-core
// vector data). Commands (editor/command.h) name the file's ids. Each is applied to what it touches
// read alone: the region of the elements it names, read from the file with the edits before it
// (io/scene_region.h over an io/scene_overlay.h), which holds every curve at a node it moves and
// every area of a curve it changes. What the command changed (the elements of its snapshot and
// changeset) goes into the next overlay, in the file's ids, with the feature boxes the file saved
// would give them. The history keeps, for each step, each changed element before and after:
// undo and redo set the overlay back and forth exactly; a drag of one vertex or node is one step
// (editor/command.h: continuesDrag); groups are undone together.
//
// The session (editor/edit_session.h) reads again, with the new overlay, the parts and the top tree
// that a step touches (LazyStep: the elements and where they were and are).
//
// Adding: a new node or curve gets the id the whole scene would give it, nextId(): the file's next
// id past those it and the edits hold (an id of an element added, saved, then taken back, absent
// in the overlay, is given again, as the whole scene's undo frees the slot). An added element's
// value before is `absent` (io/scene_overlay.h): undone before a save it leaves the overlay,
// after one its row is deleted by the next save. The nodes a command names are read with every
// curve at them (a node without curves is in no feature's box: SceneRegionOptions::nodes).
//
// Saving: io/scene_save_edits.h writes the overlay into the file, then markSaved().

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "editor/command.h"
#include "io/scene_file.h"
#include "io/scene_overlay.h"
#include "model/clip_and_refine.h"

namespace lacet {

// What one execute, undo or redo changed: the elements (the file's ids) and where each lay before
// and lies after (a node's point, a curve's vertices' box, an area's feature box).
struct LazyStep {
    std::vector<ElementRef> refs;
    std::vector<Box> boxes;
    // Each of `refs`' value and feature box before and after (OverlayElement: the file's ids).
    std::vector<OverlayElement> before, after;
    double readMs = 0.0;  // reading what the command touches (execute only)
};

class LazyEdits {
public:
    explicit LazyEdits(std::string path, RefineParams refine = {});

    // Applies `command` (the file's ids) over the edits so far; EditError (naming the element and
    // the reason) leaves everything as it was; SceneFileError when the file cannot give what it
    // touches. Clears the redo steps. `merge`: as CommandHistory::execute.
    LazyStep execute(const Command& command, bool merge = false);
    std::optional<LazyStep> undo();
    std::optional<LazyStep> redo();
    void beginGroup() { group_ = ++nextGroup_; }
    void endGroup() { group_ = 0; }
    std::size_t undoDepth() const { return done_.size(); }
    std::size_t redoDepth() const { return undone_.size(); }
    bool modified() const { return topSerial() != savedSerial_; }
    // The edits now saved into the file (io/scene_save_edits.h): the overlay is empty from now
    // on (a new version()); undo and redo set the values before and after explicitly, since the
    // file's rows are now those of this state; modified() is false until the next step.
    void markSaved();
    void forgetRedo() { undone_.clear(); }
    // Takes back the last execute, undo or redo whole (the history and the overlay as before it,
    // with a new version()), when what follows it could not be done (the session's read of the
    // file after it failed). False when there is none to take back (one rollback per step).
    bool rollback();

    // The id (the file's) the next element of `kind` added to `layer` gets: the file's count of
    // such ids, past those the edits added, less the absent ones at its end. Throws
    // SceneFileError naming the file; std::out_of_range for a layer it has not.
    ElementId nextId(LayerId layer, ElementKind kind) const;

    // The edits now (never null; a new object after each step: reads in flight keep theirs).
    const std::shared_ptr<const SceneOverlay>& overlay() const { return overlay_; }
    // Changes with each step (0: no edit yet).
    std::uint64_t version() const { return version_; }

private:
    struct Change {
        ElementRef ref;
        std::optional<OverlayElement> before;  // its overlay entry before (none: the file's row)
        OverlayElement value;                  // its value and feature box before, from either
        OverlayElement after;
        std::optional<Box> beforeBox, afterBox;  // where it lay and lies
    };
    struct Step {
        Command command;
        std::vector<Change> changes;
        std::uint64_t group = 0, serial = 0;
    };
    std::uint64_t topSerial() const { return done_.empty() ? 0 : done_.back().serial; }
    // Sets each change's after (redo) or before (undo) state into a new overlay.
    LazyStep replay(const std::vector<Change>& changes, bool forward);
    // Replays the last step of `from` (a group whole) and moves it to `to`: undo or redo.
    LazyStep moveSteps(std::vector<Step>& from, std::vector<Step>& to, bool forward);
    // What rollback() restores: the state before the last execute, undo or redo.
    struct Before {
        std::shared_ptr<const SceneOverlay> overlay{};
        std::uint64_t serial = 0;
        std::optional<Step> merged{};  // execute merged into the last step: that step before
        bool pushed = false;           // execute pushed a step
        std::vector<Step> redo{};      // execute: the redo steps it cleared
        std::size_t moved = 0;       // undo or redo: the steps moved
        bool undid = false;          // the move was an undo
    };
    std::optional<Before> before_;

    std::string path_;
    mutable SceneFileConnection connection_;  // the file kept open: an edit reads a few rows
    RefineParams refine_;
    std::shared_ptr<const SceneOverlay> overlay_;
    std::uint64_t version_ = 0;
    std::vector<Step> done_, undone_;
    std::uint64_t serial_ = 0, savedSerial_ = 0, group_ = 0, nextGroup_ = 0;
};

}  // namespace lacet
