#pragma once
// Edits of a scene read lazily equal edits of the whole scene (issue 23: `lacet check incremental
// --lazy`, and tests/editor/lazy_forest_test.cpp): random commands of every kind a lazy session
// takes (drags of vertices and nodes, widths, bridge flags, roundabouts, deleted curves, new nodes
// and curves drawn from a curve's end, whose ids must agree), with undo
// and redo, made in the same order on a session of the whole scene and on one reading the same
// file lazily (editor/lazy_edits.h); after each, both make the tiles of a viewer at the edit (and,
// now and then, elsewhere: parts held, read again, dropped and read anew), and every tile both made
// since is compared, bit for bit: appearance texels, elevation, object meshes' sizes. Then
// everything is undone and compared again (the file as it is).
//
// With a pyramid (editor/tile_loop.h), the quads of its levels an edit touched are made live, the
// others read from it; the whole session marks more of them touched (every quad with a river area
// after a river's edit) than the lazy one (the part level's quads where the edit was and is), so
// their appearance is compared from `appearanceFrom`, the pyramid's first vector level, down. With
// `topElevationOnly` (the lazy session's top tree reads what elevation needs only:
// editor/lazy_forest.h), the quads drawn from the top tree (above the part level, and at it where
// the part is not held) keep the pyramid's appearance until it is updated and have the objects of
// what the top tree reads: only their elevation is compared.
//
// With saveEvery, the lazy edits are saved into the file now and then (io/scene_save_edits.h), and
// the file's rows must then sum to the whole session's document; the parts read after a save read
// the file saved, its rows and R-trees. (Tiles rarely show a stale R-tree box, which the reads'
// margins hide: tests/editor/lazy_save_test.cpp compares the feature tables themselves.)

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "editor/edit_session.h"

namespace lacet {

struct LazyEditCheckParams {
    std::uint64_t seed = 1;
    int edits = 30;             // random edits tried (a drag counts once)
    int dragSteps = 3;          // commands of a drag (one undo step)
    double reach = 120.0;       // m: how far a move goes, each way
    double undoChance = 0.2;    // each edit is undone with this chance, then redone with one in two
    int appearanceFrom = 0;         // the first level whose appearance is compared (a pyramid's first vector level)
    bool topElevationOnly = false;  // the lazy session's top tree reads what elevation needs only
    std::size_t maxDetails = 20;
    // > 0: the lazy session's edits saved into its file (EditSession::saveEdits) after every
    // saveEvery edits and once more when all is undone; each time the file's rows must sum to the
    // whole session's document (its checksum), and undo and redo go on over the file saved.
    int saveEvery = 0;
};

struct LazyEditCheckReport {
    std::size_t edits = 0, commands = 0;  // applied (refused ones not counted)
    std::size_t refused = 0;              // refused by both sessions alike (a ring that does not fit...)
    std::size_t refusedDifferently = 0;   // refused by one session only (a failure)
    std::size_t undos = 0, redos = 0;
    std::size_t tilesCompared = 0, mismatches = 0;
    std::size_t topReads = 0, partsRenewed = 0;
    std::size_t saves = 0;
    std::vector<double> saveMs;
    std::vector<double> lazyMs, wholeMs;  // per command: execute (lazily: reading what it touches and the parts again)
    std::vector<std::string> details;     // "edit I: what differs"
};

// Both sessions must be of the same file (the whole one loaded with loadScene; its ids are the
// file's) with the same session parameters.
LazyEditCheckReport checkLazyEdits(EditSession& lazy, EditSession& whole, const LazyEditCheckParams& params);

}  // namespace lacet
