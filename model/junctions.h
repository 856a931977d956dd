#pragma once
// Junctions of a road network, read on the root graph (the ancestors), so that every quad that
// draws a piece of a road makes the same decision (§4.1, Fig. 3-4).
//
// Stop lines: at a node where 4 or more curves meet, every curve gets a stop line; where 3 meet,
// only the one that meets the other two (the stem of the T: the curve left when the two most
// opposite directions at the node are taken away); where 1 or 2 meet, none.
//
// Junction radius: markings (side lines, centre dashes) stop this far from a junction node, so
// the junction itself is plain asphalt; stop lines are drawn just outside it.

#include "model/graph.h"

namespace lacet {

// Number of curve ends at the node (a closed curve counts twice); 0 for kNoElement or a dead or
// out-of-range node.
int nodeDegree(const Layer& layer, ElementId node);

// Whether curve `curve` gets a stop line where it meets `node` (one of its ends).
bool hasStopLine(const Layer& layer, ElementId node, ElementId curve);

// Metres: half the largest width w of the curves at the node, for nodes of degree >= 3; 0 otherwise.
double junctionRadius(const Layer& layer, ElementId node);

}  // namespace lacet
