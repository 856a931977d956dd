#pragma once
// Editing commands with exact inverses (issue: the 3D editor, §6). A command applies one edit of
// model/edits.h; before it does, it keeps a snapshot of every element the edit can change (the
// element values themselves, adjacency lists included) and the layer's slot counts, so undo
// restores the scene bit for bit, ids included: an undone add removes its slot again, which is
// the last one (undo is last in, first out), so a redo gives the same ids.

#include <cstdint>
#include <variant>
#include <vector>

#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

struct MoveVertexCmd { LayerId layer; ElementId curve; std::size_t index; Vec2 p; };
struct InsertVertexCmd { LayerId layer; ElementId curve; std::size_t index; Vertex v; };
struct DeleteVertexCmd { LayerId layer; ElementId curve; std::size_t index; };
struct MoveNodeCmd { LayerId layer; ElementId node; Vec2 p; };
struct AddNodeCmd { LayerId layer; Vec2 p; };
struct AddCurveCmd { LayerId layer; Curve curve; };  // start/end: existing nodes
struct DeleteCurveCmd { LayerId layer; ElementId curve; };
struct SetCurveWidthCmd { LayerId layer; ElementId curve; float w, wf; };
struct SetCurveClassCmd { LayerId layer; ElementId curve; std::uint16_t cls; };
struct SetCurveFlagsCmd { LayerId layer; ElementId curve; std::uint16_t flags; };  // CurveFlag bits
struct SetRoundaboutCmd { LayerId layer; ElementId node; float radius; };  // m, 0 removes (model/roundabouts.h)

using Command = std::variant<MoveVertexCmd, InsertVertexCmd, DeleteVertexCmd, MoveNodeCmd, AddNodeCmd, AddCurveCmd,
                             DeleteCurveCmd, SetCurveWidthCmd, SetCurveClassCmd, SetCurveFlagsCmd, SetRoundaboutCmd>;

// What undo needs: the touched elements' values before the command, and the slot counts.
struct Snapshot {
    LayerId layer = 0;
    std::size_t nodeSlots = 0, curveSlots = 0, areaSlots = 0;
    std::vector<std::pair<ElementId, Node>> nodes;
    std::vector<std::pair<ElementId, Curve>> curves;
};

struct Applied {
    Changeset changeset;  // for Quadtree::update and CurveDataCache::invalidate
    Snapshot before;
};

// Applies the command (throws EditError, leaving the scene untouched, when it is invalid).
Applied apply(Scene& scene, const Command& command);
// Restores the scene as it was before `applied` (which must be the last command applied) and
// returns the changeset of that restoration.
Changeset undo(Scene& scene, const Applied& applied);
// Whether `next` continues `last` as a drag of the same vertex or node (one undo step).
bool continuesDrag(const Command& last, const Command& next);

}  // namespace lacet
