#pragma once
// Incremental equals rebuild (§5): random edits of a scene, each followed by Quadtree::update, and
// the updated quadtree compared with one rebuilt from scratch on the same structure
// (compareQuadtrees), the viewer moving now and then so that quads are subdivided and merged.
// One loop for the randomized test (tests/model/incremental_test.cpp) and `lacet check incremental`.
//
// Order of calls: make the scene, then checkIncremental(scene, params); the scene is edited in place.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "model/graph.h"
#include "model/quadtree.h"
#include "synth/random_edits.h"

namespace lacet {

struct IncrementalCheckParams {
    std::uint64_t seed = 1;            // of the one generator drawing the viewers and the edits
    int edits = 100;                   // random edits tried (>= 0); those that find nothing to edit are skipped
    int maxLevel = 12;                 // deepest quadtree level the viewer refines to (ViewParams::maxLevel)
    int viewEvery = 10;                // the viewer moves before every viewEvery-th edit (>= 1)
    double reach = 100.0;              // metres: how far an edit moves points (applyRandomEdit)
    double viewerHeight = 1.0;         // metres above the extent's plane: the lowest viewer...
    double viewerHeightRange = 20.0;   // ...and the range above it (uniform)
    // The quadtree's procedural step at the root: the scene's GraphStep (bridges, roundabouts; the
    // rebuild gets a fresh one, so the step's own index is checked too), or this one when set.
    ProceduralStep* procedural = nullptr;
    // Quads compared after each edit: 0, every quad of the tree (a rebuild of the whole tree);
    // else this many drawn at random, each rebuilt alone along its path from the root
    // (Quadtree::reach), and every quad every `fullEvery` edits (0: never), so that millions of
    // edits run in hours.
    std::size_t sample = 0;
    int fullEvery = 0;
    // Undo and redo (§6): after an edit is compared, it is undone with this probability (the
    // scene's elements restored to their values before it, slots included, and UPDATE given the
    // edit's changeset reversed, as the editor's undo does) and compared again; an undone edit is
    // redone with redoChance (the values after it restored, UPDATE given its changeset) and
    // compared again. Drawn from a generator of their own: the edits are the same with or without.
    double undoChance = 0.0;
    double redoChance = 0.5;
    bool stopAtFirstMismatch = false;  // stop after the first edit whose update differs
    std::size_t detailsPerEdit = 3;    // mismatch descriptions kept per edit (compareQuadtrees)
    std::size_t maxDetails = 20;       // and in all
};

struct IncrementalCheckReport {
    std::size_t edits = 0;          // edits applied
    std::size_t undos = 0, redos = 0;  // of which undone, and undone then redone (each compared too)
    std::size_t quadsCompared = 0;  // over all comparisons
    std::size_t fullComparisons = 0;  // edits after which every quad was compared
    std::size_t mismatches = 0;     // quads that differ, over all comparisons
    std::map<EditKind, std::size_t> byKind;
    std::vector<std::string> details;       // "edit I (kind): what differs"
    std::vector<double> updateMs, rebuildMs;  // milliseconds per applied edit: update, rebuild
    // Edits (undos and redos too) after which the graph step's bridges (kBridge procedural curves) or roundabout arcs
    // (kRoundabout) were more or fewer than before, and the totals at the end.
    std::size_t editsAddingBridges = 0, editsRemovingBridges = 0;
    std::size_t editsAddingRings = 0, editsRemovingRings = 0;
    std::size_t bridgesAtEnd = 0, ringArcsAtEnd = 0;
};

IncrementalCheckReport checkIncremental(Scene& scene, const IncrementalCheckParams& params);

}  // namespace lacet
