#include <algorithm>
#include <map>

#include "editor/lazy_forest.h"
#include "editor/lazy_forest_part.h"
#include "model/graph.h"

// The edits a part takes in memory, without reading it again from the file (LazyForest::renew):
// what its read would load after the step is what it holds, changed as the step says.

namespace lacet {

namespace {

bool aliveIn(const OverlayElement& e) {
    if (e.absent) return false;
    if (const Node* n = std::get_if<Node>(&e.value)) return n->alive;
    if (const Curve* c = std::get_if<Curve>(&e.value)) return c->alive;
    return std::get<Area>(e.value).alive;
}

// The largest width with its falloff (Curve::wf) of the part's alive roads, over every roads layer.
float widestRoad(const Scene& scene) {
    float wf = 0.0f;
    for (const Layer& layer : scene.layers)
        if (layer.kind == LayerKind::Roads)
            for (const Curve& c : layer.curves)
                if (c.alive) wf = std::max(wf, c.wf);
    return wf;
}

}  // namespace

bool LazyForest::addsOrTakesCurves(const LazyStep& step) {
    for (std::size_t k = 0; k < step.refs.size() && k < step.before.size() && k < step.after.size(); ++k)
        if (step.refs[k].kind == ElementKind::Curve && aliveIn(step.before[k]) != aliveIn(step.after[k])) return true;
    return false;
}

bool LazyForest::riversHeld(const Part& part, const Curve& road, std::size_t k, StepRivers& rivers) {
    // A road's rivers (the graph step's bridges) are those whose boxes meet its hull: within the
    // region searched, every one is held; beyond it, each one the file's R-trees find there (with
    // the edits) must be held (a river held brought what it depends on).
    const Box hull = hullBox(road).dilated(part.tolerance);
    if (part.quad->bounds.dilated(part.reach).contains(hull)) return true;
    auto found = rivers.find(k);
    if (found == rivers.end()) {
        try {
            found = rivers.emplace(k, loadSceneFeaturesIn(connection_, hull, LayerKind::Rivers, overlay_.get())).first;
        } catch (const std::exception&) {
            return false;  // the read that follows says why
        }
    }
    return std::all_of(found->second.begin(), found->second.end(), [&](const ElementRef& river) { return holdsElement(part.doc.scene, river); });
}

bool LazyForest::moveInPlace(Part& part, const LazyStep& step, StepRivers& rivers, std::set<QuadKey>& changed) {
    Scene& scene = part.doc.scene;
    // What the part's read searched: its quad, dilated by its reach (io/scene_region.cpp).
    const Box searched = part.quad->bounds.dilated(part.reach);
    const auto meets = [&](const std::optional<Box>& b) { return b && b->intersects(searched); };
    if (step.before.size() != step.refs.size() || step.after.size() != step.refs.size()) return false;
    std::vector<std::pair<std::size_t, ElementId>> held;  // (index in the step, id in the part)
    for (std::size_t k = 0; k < step.refs.size(); ++k) {
        const ElementRef& r = step.refs[k];
        if (r.layer >= scene.layers.size()) return false;
        const Layer& layer = scene.layers[r.layer];
        const OverlayElement &was = step.before[k], &is = step.after[k];
        // A node without curves before and after (added, or taken back, apart from its curves): no
        // read finds it, no element held names it.
        if (const Node* a = std::get_if<Node>(&was.value))
            if (a->curves.empty() && std::get<Node>(is.value).curves.empty() && localIdOf(layer, r.kind, r.id) == kNoElement) continue;
        if (layer.kind == LayerKind::Rivers) return false;  // upstream walks, axial rivers, bridges over them
        // Geometry alone: the reach, the filters and the lists stay.
        if (const Node* a = std::get_if<Node>(&was.value)) {
            Node b = std::get<Node>(is.value);
            b.p = a->p;
            if (!(b == *a)) return false;
        } else if (const Curve* c = std::get_if<Curve>(&was.value)) {
            Curve d = std::get<Curve>(is.value);
            if ((c->flags | d.flags) & kBridge) return false;  // a bridge road brings the roads it crosses
            d.vertices = c->vertices;
            if (!(d == *c)) return false;
        } else if (!(std::get<Area>(was.value) == std::get<Area>(is.value))) {
            return false;
        }
        const ElementId id = localIdOf(layer, r.kind, r.id);
        // Found by the region's R-tree search now: held, and found before (else the curves at its
        // nodes, or its loops, would be read now).
        if (meets(is.box) && (id == kNoElement || !meets(was.box))) return false;
        if (id == kNoElement) continue;  // not found now, not held: what it brought stays as it was
        // A road's rivers (the graph step's bridges) are those whose boxes meet its hull: within
        // the region searched, every one is held; beyond it, each one the file's R-trees find
        // there (with the edits) must be held (a river held brought what it depends on).
        if (const Curve* c = std::get_if<Curve>(&is.value); c && layer.kind == LayerKind::Roads && !riversHeld(part, *c, k, rivers))
            return false;
        held.emplace_back(k, id);
    }
    Changeset cs;
    for (const auto& [k, id] : held) {
        const ElementRef& r = step.refs[k];
        Layer& layer = scene.layers[r.layer];
        if (r.kind == ElementKind::Node) {
            layer.nodes[id].p = std::get<Node>(step.after[k].value).p;
        } else if (r.kind == ElementKind::Curve) {
            Curve& c = layer.curves[id];
            part.bytes -= memoryBytes(c);
            c.vertices = std::get<Curve>(step.after[k].value).vertices;
            part.bytes += memoryBytes(c);
        }
        cs.modify({r.layer, r.kind, id});
    }
    applyChangeset(part, std::move(cs), changed);
    return true;
}

bool LazyForest::growInPlace(Part& part, const LazyStep& step, StepRivers& rivers, std::set<QuadKey>& changed) {
    Scene& scene = part.doc.scene;
    const Box searched = part.quad->bounds.dilated(part.reach);
    if (step.before.size() != step.refs.size() || step.after.size() != step.refs.size()) return false;
    const auto local = [&](LayerId l, ElementKind kind, ElementId file) { return localIdOf(scene.layers[l], kind, file); };
    // The step's elements by (layer, kind, file id): its index.
    std::map<ElementRef, std::size_t> index;
    std::vector<std::size_t> adds, takes;  // curves appearing, curves going (indices in the step)
    for (std::size_t k = 0; k < step.refs.size(); ++k) {
        const ElementRef& r = step.refs[k];
        if (r.layer >= scene.layers.size() || scene.layers[r.layer].kind != LayerKind::Roads) return false;
        if (r.kind == ElementKind::Area) return false;
        index[r] = k;
        const bool was = aliveIn(step.before[k]), is = aliveIn(step.after[k]);
        if (r.kind == ElementKind::Node) {
            // A node keeps all but its curves (a draw joins curves to it, its undo takes them off).
            if (was && is) {
                Node a = std::get<Node>(step.before[k].value);
                a.curves = std::get<Node>(step.after[k].value).curves;
                if (!(a == std::get<Node>(step.after[k].value))) return false;
            }
            continue;
        }
        if (was == is) return false;  // a curve changed by a step that adds or takes curves
        const Curve& c = std::get<Curve>((is ? step.after[k] : step.before[k]).value);
        // A bridge road brings the roads its hull meets; a curve of an area's loop, its areas.
        if ((c.flags & kBridge) || !c.areas.empty()) return false;
        (is ? adds : takes).push_back(k);
    }
    if (!adds.empty() && !takes.empty()) return false;
    // Widths: the region's reach follows the widest road; one no wider than a held road leaves it.
    const float widest = widestRoad(scene);
    const auto curveOf = [&](std::size_t k, bool after) -> const Curve& { return std::get<Curve>((after ? step.after[k] : step.before[k]).value); };

    Changeset cs;
    if (!takes.empty()) {
        // Taken back: each held one with its end nodes, when no other held curve ends there (those
        // nodes the step made with it); the last ids of their kinds, as the read after gives.
        std::map<LayerId, std::vector<ElementId>> curves, nodes;
        for (const std::size_t k : takes) {
            const ElementRef& r = step.refs[k];
            const ElementId id = local(r.layer, ElementKind::Curve, r.id);
            if (id == kNoElement) continue;  // not held, and nothing held names it
            const Curve& held = scene.layers[r.layer].curves[id];
            curves[r.layer].push_back(id);
            for (const ElementId n : {held.start, held.end}) {
                const std::vector<ElementId>& at = scene.layers[r.layer].nodes[n].curves;
                if (!std::all_of(at.begin(), at.end(), [&](ElementId c) {
                        const ElementId file = scene.layers[r.layer].sceneCurveId(c);
                        const auto it = index.find({r.layer, ElementKind::Curve, file});
                        return it != index.end() && !aliveIn(step.after[it->second]);
                    }))
                    return false;  // a node other curves keep: what they brought may go with this one
                nodes[r.layer].push_back(n);
            }
        }
        // Each kind's ids taken, largest first: they must be the last ones held.
        const auto areTails = [](std::map<LayerId, std::vector<ElementId>>& taken, const auto& held) {
            for (auto& [l, ids] : taken) {
                std::sort(ids.begin(), ids.end(), std::greater<>());
                ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
                for (std::size_t i = 0; i < ids.size(); ++i)
                    if (ids[i] != held(l).size() - 1 - i) return false;
            }
            return true;
        };
        const auto layerCurves = [&](LayerId l) -> const std::vector<Curve>& { return scene.layers[l].curves; };
        const auto layerNodes = [&](LayerId l) -> const std::vector<Node>& { return scene.layers[l].nodes; };
        if (!areTails(curves, layerCurves) || !areTails(nodes, layerNodes)) return false;
        // Popped from the end of the layer's elements and of their file ids.
        const auto pop = [&](auto& elements, std::vector<ElementId>& fileIds, LayerId l, ElementKind kind, ElementId id) {
            part.bytes -= memoryBytes(elements[id]) + sizeof(ElementId);
            elements.pop_back();
            fileIds.pop_back();
            cs.removed.push_back({l, kind, id});
        };
        for (const auto& [l, ids] : curves)
            for (const ElementId id : ids) pop(scene.layers[l].curves, scene.layers[l].sceneIds.curves, l, ElementKind::Curve, id);
        for (const auto& [l, ids] : nodes)
            for (const ElementId id : ids) pop(scene.layers[l].nodes, scene.layers[l].sceneIds.nodes, l, ElementKind::Node, id);
    } else {
        // Added: a curve the region search finds now (its box meets the region searched) with its
        // end nodes, when every curve at those nodes is held or comes with it (a read loads every
        // curve at a near curve's nodes) and its rivers are held. One the search does not find
        // and no held element brings (a held node at its end, a held bridge over it) changes nothing.
        std::vector<std::size_t> in;
        for (const std::size_t k : adds) {
            const ElementRef& r = step.refs[k];
            const Curve& c = curveOf(k, true);
            const std::optional<Box>& box = step.after[k].box;
            const bool endsHeld = local(r.layer, ElementKind::Node, c.start) != kNoElement || local(r.layer, ElementKind::Node, c.end) != kNoElement;
            // Wider than every held road: the read's reach may grow (it follows the widest road
            // of the file and the edits) and find what the search before did not.
            if (c.wf > widest) return false;
            if (!box || !box->intersects(searched)) {
                if (endsHeld) return false;
                for (const Layer& layer : scene.layers)
                    if (layer.kind == LayerKind::Roads)
                        for (const Curve& bridge : layer.curves)
                            if (bridge.alive && (bridge.flags & kBridge) && box && hullBox(bridge).dilated(part.tolerance).intersects(*box))
                                return false;
                continue;
            }
            if (!riversHeld(part, c, k, rivers)) return false;
            in.push_back(k);
        }
        const auto comes = [&](LayerId l, ElementId file) {
            return std::any_of(in.begin(), in.end(), [&](std::size_t k) { return step.refs[k].layer == l && step.refs[k].id == file; });
        };
        std::map<LayerId, std::vector<ElementId>> newNodes;  // file ids
        for (const std::size_t k : in) {
            const LayerId l = step.refs[k].layer;
            const Curve& c = curveOf(k, true);
            for (const ElementId n : {c.start, c.end}) {
                const auto it = index.find({l, ElementKind::Node, n});
                if (it == index.end()) return false;  // a node whose curves changed is in the step
                for (const ElementId at : std::get<Node>(step.after[it->second].value).curves)
                    if (local(l, ElementKind::Curve, at) == kNoElement && !comes(l, at)) return false;
                if (local(l, ElementKind::Node, n) == kNoElement) newNodes[l].push_back(n);
            }
        }
        // Appended in the file's order, past every id held (the read's order).
        std::map<LayerId, std::vector<ElementId>> newCurves;
        for (const std::size_t k : in) newCurves[step.refs[k].layer].push_back(step.refs[k].id);
        for (auto* m : {&newNodes, &newCurves})
            for (auto& [l, ids] : *m) {
                std::sort(ids.begin(), ids.end());
                ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
                const std::vector<ElementId>& held = m == &newNodes ? scene.layers[l].sceneIds.nodes : scene.layers[l].sceneIds.curves;
                if (!held.empty() && held.back() >= ids.front()) return false;
            }
        for (auto& [l, ids] : newNodes) {
            Layer& layer = scene.layers[l];
            for (const ElementId file : ids) {
                cs.added.push_back({l, ElementKind::Node, ElementId(layer.nodes.size())});
                Node n = std::get<Node>(step.after[index.at({l, ElementKind::Node, file})].value);
                n.curves.clear();  // below, with the curves
                part.bytes += memoryBytes(n) + sizeof(ElementId);
                layer.nodes.push_back(std::move(n));
                layer.sceneIds.nodes.push_back(file);
            }
        }
        for (auto& [l, ids] : newCurves) {
            Layer& layer = scene.layers[l];
            for (const ElementId file : ids) {
                cs.added.push_back({l, ElementKind::Curve, ElementId(layer.curves.size())});
                Curve c = std::get<Curve>(step.after[index.at({l, ElementKind::Curve, file})].value);
                c.start = localIdOf(layer, ElementKind::Node, c.start);
                c.end = localIdOf(layer, ElementKind::Node, c.end);
                part.bytes += memoryBytes(c) + sizeof(ElementId);
                layer.curves.push_back(std::move(c));
                layer.sceneIds.curves.push_back(file);
            }
        }
        for (const std::size_t k : in)
            for (const ElementId file : {curveOf(k, true).start, curveOf(k, true).end}) {
                const LayerId l = step.refs[k].layer;
                Layer& layer = scene.layers[l];
                const ElementId n = localIdOf(layer, ElementKind::Node, file);
                std::vector<ElementId> at;
                for (const ElementId c : std::get<Node>(step.after[index.at({l, ElementKind::Node, file})].value).curves)
                    if (const ElementId id = localIdOf(layer, ElementKind::Curve, c); id != kNoElement) at.push_back(id);
                if (layer.nodes[n].curves == at) continue;  // both ends at one node: set once
                part.bytes -= memoryBytes(layer.nodes[n]);
                layer.nodes[n].curves = std::move(at);
                part.bytes += memoryBytes(layer.nodes[n]);
                if (std::find(cs.added.begin(), cs.added.end(), ElementRef{l, ElementKind::Node, n}) == cs.added.end())
                    cs.modify({l, ElementKind::Node, n});
            }
    }
    applyChangeset(part, std::move(cs), changed);
    return true;
}

}  // namespace lacet
