#pragma once
// Edits of the root graph. Each checks its arguments first and throws EditError (naming the
// layer, element and reason) without touching the scene when they are wrong; otherwise it
// applies the change and returns the changeset to give to Quadtree::update().
//
// What an edit reports as modified:
// - a curve whose geometry changes, and every area whose loops use it;
// - a node whose position, adjacency or adjacent curve widths/classes change (node caps,
//   junction markings and the node's clipping margin depend on them).

#include <stdexcept>

#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

class EditError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

// Control points and interior on-curve vertices (index 1 .. size-2). End vertices belong to
// the nodes: use moveNode.
Changeset moveVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index, Vec2 p);
// Inserts `v` before vertex `index` (1 .. size-1); the spline must stay well formed.
Changeset insertVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index, Vertex v);
Changeset deleteVertex(Scene& s, LayerId layer, ElementId curve, std::size_t index);
// Moves a node and the end vertices of its curves.
Changeset moveNode(Scene& s, LayerId layer, ElementId node, Vec2 p);

Changeset addNode(Scene& s, LayerId layer, Vec2 p, ElementId* id = nullptr);
// Only an isolated node (no curves) can be deleted.
Changeset deleteNode(Scene& s, LayerId layer, ElementId node);
// `c.start`/`c.end` must be alive nodes whose positions equal the first/last vertices.
Changeset addCurve(Scene& s, LayerId layer, Curve c, ElementId* id = nullptr);
// A curve used by an area cannot be deleted before the area.
Changeset deleteCurve(Scene& s, LayerId layer, ElementId curve);
// Loops must be closed chains of alive curves.
Changeset addArea(Scene& s, LayerId layer, Area a, ElementId* id = nullptr);
Changeset deleteArea(Scene& s, LayerId layer, ElementId area);

Changeset setCurveWidth(Scene& s, LayerId layer, ElementId curve, float w, float wf);
Changeset setCurveClass(Scene& s, LayerId layer, ElementId curve, std::uint16_t cls);
// CurveFlag bits (a bridge, a tunnel, a ford: no procedural bridge): the curve is modified.
Changeset setCurveFlags(Scene& s, LayerId layer, ElementId curve, std::uint16_t flags);
Changeset setAreaClass(Scene& s, LayerId layer, ElementId area, std::uint16_t cls);
Changeset setAreaFootprint(Scene& s, LayerId layer, ElementId area, float wf);
// Sets the radius (m) of the roundabout at a node of a Roads layer (§4.3, Fig. 5 right; 0 removes
// it). A radius that does not fit (roundaboutRefusal(), model/roundabouts.h) throws EditError with
// the reason. Reports the node and every curve at it as modified: their expansions change.
Changeset setNodeRoundabout(Scene& s, LayerId layer, ElementId node, float radius);

}  // namespace lacet
