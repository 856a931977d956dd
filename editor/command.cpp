#include "editor/command.h"

#include "model/edits.h"

namespace lacet {
namespace {

template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

Snapshot snapshot(const Scene& s, LayerId layer, std::vector<ElementId> nodes, std::vector<ElementId> curves) {
    Snapshot snap;
    snap.layer = layer;
    if (layer >= s.layers.size()) return snap;  // the edit will refuse it
    const Layer& l = s.layers[layer];
    snap.nodeSlots = l.nodes.size();
    snap.curveSlots = l.curves.size();
    snap.areaSlots = l.areas.size();
    for (ElementId n : nodes)
        if (n < l.nodes.size()) snap.nodes.push_back({n, l.nodes[n]});
    for (ElementId c : curves)
        if (c < l.curves.size()) snap.curves.push_back({c, l.curves[c]});
    return snap;
}

std::vector<ElementId> endsOf(const Scene& s, LayerId layer, ElementId curve) {
    if (layer >= s.layers.size() || curve >= s.layers[layer].curves.size()) return {};
    const Curve& c = s.layers[layer].curves[curve];
    return {c.start, c.end};
}

}  // namespace

Applied apply(Scene& s, const Command& command) {
    Applied a;
    a.changeset = std::visit(
        Overloaded{
            [&](const MoveVertexCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return moveVertex(s, c.layer, c.curve, c.index, c.p);
            },
            [&](const InsertVertexCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return insertVertex(s, c.layer, c.curve, c.index, c.v);
            },
            [&](const DeleteVertexCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return deleteVertex(s, c.layer, c.curve, c.index);
            },
            [&](const MoveNodeCmd& c) {
                std::vector<ElementId> curves;
                if (c.layer < s.layers.size() && c.node < s.layers[c.layer].nodes.size()) curves = s.layers[c.layer].nodes[c.node].curves;
                a.before = snapshot(s, c.layer, {c.node}, curves);
                return moveNode(s, c.layer, c.node, c.p);
            },
            [&](const AddNodeCmd& c) {
                a.before = snapshot(s, c.layer, {}, {});
                return addNode(s, c.layer, c.p);
            },
            [&](const AddCurveCmd& c) {
                a.before = snapshot(s, c.layer, {c.curve.start, c.curve.end}, {});
                return addCurve(s, c.layer, c.curve);
            },
            [&](const DeleteCurveCmd& c) {
                a.before = snapshot(s, c.layer, endsOf(s, c.layer, c.curve), {c.curve});
                return deleteCurve(s, c.layer, c.curve);
            },
            [&](const SetCurveWidthCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return setCurveWidth(s, c.layer, c.curve, c.w, c.wf);
            },
            [&](const SetCurveClassCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return setCurveClass(s, c.layer, c.curve, c.cls);
            },
            [&](const SetCurveFlagsCmd& c) {
                a.before = snapshot(s, c.layer, {}, {c.curve});
                return setCurveFlags(s, c.layer, c.curve, c.flags);
            },
            [&](const SetRoundaboutCmd& c) {
                // The node holds the radius; its curves' values do not change (only their expansion).
                a.before = snapshot(s, c.layer, {c.node}, {});
                return setNodeRoundabout(s, c.layer, c.node, c.radius);
            },
        },
        command);
    return a;
}

Changeset undo(Scene& s, const Applied& a) {
    Layer& l = s.layers[a.before.layer];
    for (const auto& [id, node] : a.before.nodes) l.nodes[id] = node;
    for (const auto& [id, curve] : a.before.curves) l.curves[id] = curve;
    l.nodes.resize(a.before.nodeSlots);
    l.curves.resize(a.before.curveSlots);
    l.areas.resize(a.before.areaSlots);
    // The restoration changes back what the command changed: its removals are added back and
    // its additions removed (modified elements are in both lists).
    Changeset back;
    back.removed = a.changeset.added;
    back.added = a.changeset.removed;
    back.normalize();
    return back;
}

bool continuesDrag(const Command& last, const Command& next) {
    if (const auto* a = std::get_if<MoveVertexCmd>(&last))
        if (const auto* b = std::get_if<MoveVertexCmd>(&next))
            return a->layer == b->layer && a->curve == b->curve && a->index == b->index;
    if (const auto* a = std::get_if<MoveNodeCmd>(&last))
        if (const auto* b = std::get_if<MoveNodeCmd>(&next)) return a->layer == b->layer && a->node == b->node;
    return false;
}

}  // namespace lacet
