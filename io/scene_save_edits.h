#pragma once
// A scene file's edits saved into it, in place (issue 23: saving a scene edited lazily, §7): the
// elements a lazy session changed (io/scene_overlay.h, in the file's ids) written over their rows,
// without reading or writing the rest of the scene, which may be larger than memory.
//
// One SQLite transaction (BEGIN IMMEDIATE: one writer at a time; SQLite's journal makes it atomic,
// so a crash or an error at any point leaves the file as it was):
//   - each element's row in lacet_nodes, lacet_curves or lacet_areas, replaced; an element the
//     edits added (an id past the file's) gets its row, one `absent` loses it (the ids of each
//     layer and kind must stay 0, 1, 2...: else the save is refused);
//   - the features of the curves and areas changed, and of the curves of the loops of an area
//     changed (io/scene_features.h: FeatureTablesEditor), the same geometry and columns saveScene
//     would write for them (a table the save empties stays, empty: a whole save writes none);
//   - lacet_meta's checksum (io/scene_checksum.h, format 2) updated by the digests of the rows
//     replaced, before and after; where elements were added or taken away, the head's digest
//     (it holds each layer's counts) is summed again: a read of the attributes and of the DEM
//     (a streamed DEM's layout and stored digest; an in-memory DEM's samples), not of the rows.
//     A file of format 1, or whose stored parts do not give its checksum, is summed again whole
//     in format 2 (a read of every row of the element tables: the one cost that grows with the
//     scene) and becomes format 2.
// The file must be the one the edits were made over: its stored checksum is `expected` (else the
// save is refused, the file unchanged). Throws SceneFileError naming the file and the reason.

#include <cstddef>
#include <string>

#include "io/scene_features.h"
#include "io/scene_overlay.h"

namespace lacet {

struct SceneEditsSaved {
    std::string checksum;                  // the file's stored checksum now
    std::size_t nodes = 0, curves = 0, areas = 0;  // rows written (added ones included)
    std::size_t added = 0, removed = 0;            // rows of elements added, of absent ones deleted
    bool headSummed = false;  // the head's digest summed again (elements added or taken away)
    FeatureTablesEditor::Counts features;
    double writeMs = 0.0;     // from the start to the rows and features written (the file's head read first)
    double checksumMs = 0.0;  // the checksum: updated, or summed again whole
    bool summedWhole = false; // summed again whole (a format-1 file, made format 2)
    double totalMs = 0.0;
};

SceneEditsSaved saveSceneEdits(const std::string& path, const SceneOverlay& overlay, const std::string& expected);

}  // namespace lacet
