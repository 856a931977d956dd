#include "model/quadtree.h"

#include "model/validate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include <tbb/parallel_for.h>

namespace lacet {

struct Quadtree::Ancestors {
    struct Lists {
        std::vector<ElementId> nodes, areas;
        std::vector<AncestorId> curves;
        bool empty() const { return nodes.empty() && curves.empty() && areas.empty(); }
    };
    std::vector<Lists> layers;
    explicit Ancestors(std::size_t n) : layers(n) {}
    bool empty() const {
        return std::all_of(layers.begin(), layers.end(), [](const Lists& l) { return l.empty(); });
    }
    void normalize() {
        auto sortUnique = [](auto& v) {
            std::sort(v.begin(), v.end());
            v.erase(std::unique(v.begin(), v.end()), v.end());
        };
        for (auto& l : layers) {
            sortUnique(l.nodes);
            sortUnique(l.curves);
            sortUnique(l.areas);
        }
    }
};

static_assert(kProceduralIndexBits + 32 < 64, "the flag, a root curve's id and k fit in an AncestorId");

AncestorId proceduralId(ElementId root, std::size_t k) {
    if (k >= kMaxProceduralCurves) {
        std::ostringstream s;
        s << "proceduralId(): root curve " << root << " expands to more than " << kMaxProceduralCurves
          << " procedural curves (piece " << k << ")";
        throw std::length_error(s.str());
    }
    return kProceduralBit | AncestorId(root) << kProceduralIndexBits | AncestorId(k);
}

Quadtree::Quadtree(const Scene& scene, RefineParams params, ProceduralStep* procedural)
    : scene_(scene), params_(params), procedural_(procedural) {
    if (!(params_.toleranceTexels > 0.0))
        throw std::invalid_argument("Quadtree: the refinement tolerance must be positive");
    params_.grid().validate();
    validateOrThrow(scene);
    root_.bounds = scene.extent;
    expandedFrom_.resize(scene.layers.size());
    proceduralCurves_.resize(scene.layers.size());
    areaAttributes_.resize(scene.layers.size());
    geometryOnlyAreas_.resize(scene.layers.size());
    for (LayerId l = 0; l < scene.layers.size(); ++l)
        for (ElementId id = 0; id < scene.layers[l].areas.size(); ++id) {
            const Area& a = scene.layers[l].areas[id];
            if (a.alive) areaAttributes_[l][id] = {a.wf, a.cls, a.axial};
        }
    if (procedural_)
        for (LayerId l = 0; l < scene.layers.size(); ++l)
            for (ElementId id = 0; id < scene.layers[l].curves.size(); ++id)
                if (scene.layers[l].curves[id].alive) expandRoot(l, id);
}

void Quadtree::expandRoot(LayerId layer, ElementId id) {
    if (!procedural_) return;
    std::vector<ProceduralCurve> out;
    if (!procedural_->expand(scene_, layer, id, out)) return;
    std::vector<AncestorId> ids;
    for (std::size_t k = 0; k < out.size(); ++k) {
        const AncestorId pid = proceduralId(id, k);
        ids.push_back(pid);
        proceduralCurves_[layer][pid] = std::move(out[k]);
    }
    expandedFrom_[layer][id] = std::move(ids);
}

template <class F>
void Quadtree::forEachRootCurveAncestor(LayerId layer, ElementId id, F&& f) const {
    const auto it = expandedFrom_[layer].find(id);
    if (it == expandedFrom_[layer].end()) return f(id);
    for (AncestorId pid : it->second) f(pid);
}

const Curve& Quadtree::ancestorCurve(LayerId layer, AncestorId id) const {
    if (id & kProceduralBit) return proceduralCurves_[layer].at(id).curve;
    return scene_.layers[layer].curves[ElementId(id)];
}

const ProceduralCurve* Quadtree::proceduralCurve(LayerId layer, AncestorId id) const {
    if (!(id & kProceduralBit)) return nullptr;
    const auto it = proceduralCurves_[layer].find(id);
    return it == proceduralCurves_[layer].end() ? nullptr : &it->second;
}

std::size_t Quadtree::proceduralCount(std::uint16_t flags) const {
    std::size_t n = 0;
    for (const auto& layer : proceduralCurves_)
        for (const auto& [id, pc] : layer) n += (pc.curve.flags & flags) != 0;
    return n;
}

std::span<const AncestorId> Quadtree::expansionOf(LayerId layer, ElementId id) const {
    const auto it = expandedFrom_[layer].find(id);
    if (it == expandedFrom_[layer].end()) return {};
    return it->second;
}

double Quadtree::nodeMargin(LayerId layer, ElementId id, double quadSize) const {
    const Layer& l = scene_.layers[layer];
    double m = 0.0;  // an isolated node is kept only inside the quad
    for (ElementId c : l.nodes[id].curves) m = std::max(m, curveMargin(layer, c, quadSize));
    return m;
}

Box Quadtree::childBounds(const Quad& q, int k) {
    // Children share the parent's corners and one midpoint, so siblings meet exactly (no ulp gaps
    // at huge coordinates) and tile the parent.
    const Vec2 mid = q.bounds.center();
    const Vec2 min((k & 1) ? mid.x : q.bounds.min.x, (k >> 1) ? mid.y : q.bounds.min.y);
    const Vec2 max((k & 1) ? q.bounds.max.x : mid.x, (k >> 1) ? q.bounds.max.y : mid.y);
    return {min, max};
}

ClippedCurve Quadtree::rootCurve(LayerId layer, AncestorId ancestor) const {
    const Curve& a = ancestorCurve(layer, ancestor);
    ClippedCurve c;
    c.vertices = a.vertices;
    for (const Vertex& v : a.vertices)
        if (v.onCurve) c.s.push_back(double(c.s.size()));
    c.startsAtNode = a.start != kNoElement;
    c.endsAtNode = a.end != kNoElement;
    return c;
}

ClippedArea Quadtree::rootArea(LayerId layer, ElementId id) const {
    const Layer& l = scene_.layers[layer];
    ClippedArea a;
    const auto& loops = l.areas[id].loops;
    for (std::size_t i = 0; i < loops.size(); ++i) a.loops.push_back({loopVertices(l, loops[i]), i > 0});
    return a;
}

void Quadtree::clipCurveInto(LayerId layer, AncestorId ancestor, std::span<const ClippedCurve> parent,
                             const Quad& child, std::vector<ClippedCurve>& out) const {
    const double margin = curveMargin(layer, ancestor, child.bounds.size().x);
    const double tol = params_.tolerance(child.bounds.size().x);
    for (std::size_t i = 0; i < parent.size(); ++i)
        clipAndRefineCurve(parent[i], std::uint32_t(i), child.bounds, margin, tol, out);
}

void Quadtree::clipAreaInto(LayerId layer, ElementId id, std::span<const ClippedArea> parent, const Quad& child,
                            std::vector<ClippedArea>& out) const {
    const double margin = areaMargin(layer, id, child.bounds.size().x);
    const double tol = params_.tolerance(child.bounds.size().x);
    for (std::size_t i = 0; i < parent.size(); ++i)
        clipAndRefineArea(parent[i], std::uint32_t(i), child.bounds, margin, tol, out);
}

void Quadtree::subdivide(Quad& q) {
    if (q.isLeaf()) attach(q, makeChildren(q));
}

void Quadtree::attach(Quad& q, QuadChildren children) {
    if (!q.isLeaf()) return;
    for (auto& c : children) c->parent = &q;
    q.children = std::move(children);
}

QuadChildren Quadtree::makeChildren(const Quad& q, const CancelFlag* cancel) const {
    const std::size_t nLayers = scene_.layers.size();
    QuadChildren kids;
    for (int k = 0; k < 4; ++k) {
        kids[k] = std::make_unique<Quad>();
        Quad& c = *kids[k];
        c.level = q.level + 1;
        c.tx = q.tx * 2 + std::uint32_t(k & 1);
        c.ty = q.ty * 2 + std::uint32_t(k >> 1);
        c.bounds = childBounds(q, k);
        c.layers.resize(nLayers);
    }
    // Kid by kid, so that the four can be filled on different threads (each writes only its
    // own graph; clipping is const and its buffers are per thread). The result does not depend
    // on how they are scheduled. A small quad is not worth the tasks. At the root each kid
    // builds the scene's curves and areas as root pieces itself: four times the (cheap)
    // construction, run in parallel, rather than holding the whole scene's pieces at once.
    auto fill = [&](Quad& kid) {
        std::vector<ClippedCurve> curves;
        std::vector<ClippedArea> areas;
        std::size_t handled = 0;
        auto addCurves = [&](LayerId l, AncestorId a, std::span<const ClippedCurve> parent) {
            if ((handled++ & 63) == 0) throwIfCancelled(cancel);
            curves.clear();
            clipCurveInto(l, a, parent, kid, curves);
            if (!curves.empty()) kid.layers[l].curves.emplace(a, std::move(curves));
        };
        auto addAreas = [&](LayerId l, ElementId a, std::span<const ClippedArea> parent) {
            if ((handled++ & 63) == 0) throwIfCancelled(cancel);
            areas.clear();
            clipAreaInto(l, a, parent, kid, areas);
            if (!areas.empty()) kid.layers[l].areas.emplace(a, std::move(areas));
        };
        auto addNode = [&](LayerId l, ElementId a, Vec2 p) {
            if (keepNode(p, kid.bounds, nodeMargin(l, a, kid.bounds.size().x))) kid.layers[l].nodes.emplace(a, p);
        };
        for (LayerId l = 0; l < nLayers; ++l) {
            if (!q.parent) {  // the root: its graph is the scene, after the procedural step
                const Layer& layer = scene_.layers[l];
                for (ElementId id = 0; id < layer.nodes.size(); ++id)
                    if (layer.nodes[id].alive) addNode(l, id, layer.nodes[id].p);
                for (ElementId id = 0; id < layer.curves.size(); ++id)
                    if (layer.curves[id].alive)
                        forEachRootCurveAncestor(l, id, [&](AncestorId a) {
                            const ClippedCurve rc = rootCurve(l, a);
                            addCurves(l, a, {&rc, 1});
                        });
                for (ElementId id = 0; id < layer.areas.size(); ++id)
                    if (layer.areas[id].alive) {
                        const ClippedArea ra = rootArea(l, id);
                        addAreas(l, id, {&ra, 1});
                    }
            } else {
                const QuadLayer& ql = q.layers[l];
                for (const auto& [a, p] : ql.nodes) addNode(l, a, p);
                for (const auto& [a, pieces] : ql.curves) addCurves(l, a, pieces);
                for (const auto& [a, pieces] : ql.areas) addAreas(l, a, pieces);
            }
        }
    };
    const std::size_t elements = elementCount(q);  // the root's graph is the scene's
    constexpr std::size_t kParallelElements = 256;
    if (!q.parent || elements >= kParallelElements) tbb::parallel_for(0, 4, [&](int k) { fill(*kids[std::size_t(k)]); });
    else
        for (auto& kid : kids) fill(*kid);
    return kids;
}

void Quadtree::merge(Quad& q) {
    for (auto& c : q.children) c.reset();
}

double Quadtree::viewDistance(const Quad& q, glm::dvec3 viewer) {
    const Vec2 v(viewer.x, viewer.y);
    const Vec2 d = glm::max(glm::max(q.bounds.min - v, v - q.bounds.max), Vec2(0.0));
    return std::sqrt(d.x * d.x + d.y * d.y + viewer.z * viewer.z);
}

bool Quadtree::wantsSubdivision(const Quad& q, glm::dvec3 viewer, const ViewParams& view) {
    return q.level < view.maxLevel && viewDistance(q, viewer) < view.K * q.bounds.size().x;
}

namespace {

// A leaf the viewers want subdivided, and how much: the first viewer's wants before the others'
// (tier 0 before 1), then the smallest distance over size (the quad that stands largest on screen
// for its size), then level and position so that the order is total and the same on every run.
struct PendingSubdivision {
    int tier = 0;
    double ratio = 0.0;
    Quad* quad = nullptr;
    auto key() const { return std::make_tuple(tier, ratio, quad->level, quad->ty, quad->tx); }
    // std::priority_queue keeps the greatest on top: the most wanted is the "greatest".
    bool operator<(const PendingSubdivision& o) const { return o.key() < key(); }
};

}  // namespace

bool Quadtree::wantedByAny(const Quad& q, std::span<const glm::dvec3> viewers, const ViewParams& view) {
    return std::any_of(viewers.begin(), viewers.end(), [&](const glm::dvec3& v) { return wantsSubdivision(q, v, view); });
}

bool Quadtree::refine(Quad& top, std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                      ChildMaker* maker) {
    if (viewers.empty()) throw std::invalid_argument("Quadtree::refineForViewers(): no viewer");
    // First the tree as it stands: merge what no viewer wants, and find the wanted leaves.
    std::priority_queue<PendingSubdivision> pending;
    auto want = [&](Quad& q) {
        const double size = q.bounds.size().x;
        if (wantsSubdivision(q, viewers[0], view)) return pending.push({0, viewDistance(q, viewers[0]) / size, &q});
        double ratio = std::numeric_limits<double>::infinity();
        for (const glm::dvec3& v : viewers.subspan(1))
            if (wantsSubdivision(q, v, view)) ratio = std::min(ratio, viewDistance(q, v) / size);
        pending.push({1, ratio, &q});
    };
    std::vector<Quad*> stack{&top};
    while (!stack.empty()) {
        Quad& q = *stack.back();
        stack.pop_back();
        if (!wantedByAny(q, viewers, view)) merge(q);
        else if (q.isLeaf()) want(q);
        else
            for (auto& c : q.children) stack.push_back(c.get());
    }
    // Then the subdivisions, most wanted first; with a deadline, the first whatever the deadline
    // and each other one while it has not passed.
    bool deferred = false;
    for (std::size_t done = 0; !pending.empty();) {
        if (done > 0 && deadline && deadline->passed()) return false;
        Quad& q = *pending.top().quad;
        pending.pop();
        if (!maker) {
            subdivide(q);
        } else if (std::optional<QuadChildren> kids = maker->children(*this, q)) {
            attach(q, std::move(*kids));
        } else {
            deferred = true;
            continue;
        }
        ++done;
        for (auto& c : q.children)
            if (wantedByAny(*c, viewers, view)) want(*c);
    }
    return !deferred;
}

void Quadtree::refineForViewer(glm::dvec3 viewer, const ViewParams& view) { refine(root_, {&viewer, 1}, view, std::nullopt, nullptr); }

bool Quadtree::refineForViewers(std::span<const glm::dvec3> viewers, const ViewParams& view, std::optional<Deadline> deadline,
                                ChildMaker* maker) {
    return refine(root_, viewers, view, deadline, maker);
}

bool Quadtree::refineSubtree(Quad& top, std::span<const glm::dvec3> viewers, const ViewParams& view, std::optional<Deadline> deadline,
                             ChildMaker* maker) {
    return refine(top, viewers, view, deadline, maker);
}

Quad& Quadtree::reach(int level, std::uint32_t tx, std::uint32_t ty) {
    if (level < 0 || level > ViewParams::kMaxLevel || (std::uint64_t(tx) >> level) != 0 || (std::uint64_t(ty) >> level) != 0)
        throw std::out_of_range("Quadtree::reach(): no quad " + std::to_string(level) + "/" + std::to_string(tx) + "/" +
                                std::to_string(ty));
    Quad* q = &root_;
    while (q->level < level) {
        if (q->isLeaf()) subdivide(*q);
        const int shift = level - q->level - 1;
        q = q->children[std::size_t(int((tx >> shift) & 1u) | int(((ty >> shift) & 1u) << 1))].get();
    }
    return *q;
}

void Quadtree::copyQuad(Quad& q, const Quad& like) {
    if (like.isLeaf()) return merge(q);
    subdivide(q);
    for (int k = 0; k < 4; ++k) copyQuad(*q.children[k], *like.children[k]);
}

void Quadtree::copyStructureOf(const Quadtree& other) { copyQuad(root_, other.root_); }

UpdateStats Quadtree::update(const Changeset& changeset) {
    // Root curves whose procedural expansion reads what the edit changed are re-expanded too.
    Changeset cs = changeset;
    std::vector<ElementRef> dependents;
    if (procedural_) {
        procedural_->update(scene_, changeset, dependents);
        for (const ElementRef& r : dependents) cs.modify(r);
        cs.normalize();
    }
    const std::size_t nLayers = scene_.layers.size();
    Ancestors removed(nLayers), added(nLayers);
    for (const ElementRef& r : cs.removed) {
        auto& lists = removed.layers.at(r.layer);
        switch (r.kind) {
            case ElementKind::Node: lists.nodes.push_back(r.id); break;
            case ElementKind::Area: lists.areas.push_back(r.id); break;
            case ElementKind::Curve: {
                auto it = expandedFrom_[r.layer].find(r.id);
                if (it == expandedFrom_[r.layer].end()) {
                    lists.curves.push_back(r.id);
                    break;
                }
                for (AncestorId pid : it->second) {
                    lists.curves.push_back(pid);
                    proceduralCurves_[r.layer].erase(pid);
                }
                expandedFrom_[r.layer].erase(it);
                break;
            }
        }
    }
    for (const ElementRef& a : cs.added) {
        const Layer& layer = scene_.layers.at(a.layer);
        auto& lists = added.layers[a.layer];
        switch (a.kind) {
            case ElementKind::Node:
                if (a.id < layer.nodes.size() && layer.nodes[a.id].alive) lists.nodes.push_back(a.id);
                break;
            case ElementKind::Area:
                if (a.id < layer.areas.size() && layer.areas[a.id].alive) lists.areas.push_back(a.id);
                break;
            case ElementKind::Curve:
                if (a.id < layer.curves.size() && layer.curves[a.id].alive) {
                    expandRoot(a.layer, a.id);
                    forEachRootCurveAncestor(a.layer, a.id, [&](AncestorId pid) { lists.curves.push_back(pid); });
                }
                break;
        }
    }
    removed.normalize();
    added.normalize();
    // Modified areas whose attributes are those they were clipped with: their quads are pruned
    // where their pieces come out the same (updateQuad).
    for (LayerId l = 0; l < nLayers; ++l) {
        auto& prune = geometryOnlyAreas_[l];
        prune.clear();
        const LayerKind kind = scene_.layers[l].kind;
        if (kind == LayerKind::Fields || kind == LayerKind::Forests || kind == LayerKind::Other)
            for (ElementId id : added.layers[l].areas) {
                const Area& a = scene_.layers[l].areas[id];
                const auto it = areaAttributes_[l].find(id);
                if (a.axial == kNoElement && it != areaAttributes_[l].end() && it->second == AreaAttributes{a.wf, a.cls, a.axial} &&
                    std::binary_search(removed.layers[l].areas.begin(), removed.layers[l].areas.end(), id))
                    prune.push_back(id);
            }
        for (ElementId id : removed.layers[l].areas) areaAttributes_[l].erase(id);
        for (ElementId id : added.layers[l].areas) {
            const Area& a = scene_.layers[l].areas[id];
            areaAttributes_[l][id] = {a.wf, a.cls, a.axial};
        }
    }
    UpdateStats stats;
    stats.quadsVisited = 1;
    stats.reexpanded = std::move(dependents);
    if (!root_.isLeaf() && !(removed.empty() && added.empty()))
        for (auto& c : root_.children) updateQuad(*c, removed, added, stats);
    return stats;
}

void Quadtree::updateQuad(Quad& q, const Ancestors& removed, const Ancestors& added, UpdateStats& stats) {
    ++stats.quadsVisited;
    const Quad& p = *q.parent;
    const bool parentIsRoot = p.parent == nullptr;
    Ancestors removed2(removed.layers.size()), added2(added.layers.size());
    std::vector<ClippedCurve> curves;
    std::vector<ClippedArea> areas;
    for (LayerId l = 0; l < removed.layers.size(); ++l) {
        QuadLayer& ql = q.layers[l];
        const auto& r = removed.layers[l];
        const auto& a = added.layers[l];
        auto& r2 = removed2.layers[l];
        auto& a2 = added2.layers[l];
        auto erase = [](const auto& ids, auto& map, auto& erased) {
            for (const auto id : ids)
                if (map.erase(id)) erased.push_back(id);
        };
        // Alg. 6.1: first remove what was made from the removed elements...
        erase(r.nodes, ql.nodes, r2.nodes);
        erase(r.curves, ql.curves, r2.curves);
        // Areas that may come out the same: keep their old pieces to compare.
        std::vector<std::pair<ElementId, std::vector<ClippedArea>>> before;
        for (ElementId id : geometryOnlyAreas_[l]) {
            if (std::find(r.areas.begin(), r.areas.end(), id) == r.areas.end()) continue;  // not re-clipped here
            const auto it = ql.areas.find(id);
            if (it != ql.areas.end()) before.push_back({id, std::move(it->second)});
        }
        erase(r.areas, ql.areas, r2.areas);
        // ...then SUBDIVIDE the added ones into q (an element added without being removed first
        // replaces what q had of it).
        erase(a.nodes, ql.nodes, r2.nodes);
        erase(a.curves, ql.curves, r2.curves);
        erase(a.areas, ql.areas, r2.areas);
        for (ElementId id : a.nodes) {
            Vec2 pos;
            if (parentIsRoot) {
                pos = scene_.layers[l].nodes[id].p;
            } else {
                const auto it = p.layers[l].nodes.find(id);
                if (it == p.layers[l].nodes.end()) continue;
                pos = it->second;
            }
            if (!keepNode(pos, q.bounds, nodeMargin(l, id, q.bounds.size().x))) continue;
            ql.nodes[id] = pos;
            a2.nodes.push_back(id);
        }
        for (AncestorId id : a.curves) {
            curves.clear();
            if (parentIsRoot) {
                const ClippedCurve rc = rootCurve(l, id);
                clipCurveInto(l, id, {&rc, 1}, q, curves);
            } else {
                const auto it = p.layers[l].curves.find(id);
                if (it == p.layers[l].curves.end()) continue;
                clipCurveInto(l, id, it->second, q, curves);
            }
            if (curves.empty()) continue;
            ql.curves[id] = std::move(curves);
            a2.curves.push_back(id);
        }
        for (ElementId id : a.areas) {
            areas.clear();
            if (parentIsRoot) {
                const ClippedArea ra = rootArea(l, id);
                clipAreaInto(l, id, {&ra, 1}, q, areas);
            } else {
                const auto it = p.layers[l].areas.find(id);
                if (it == p.layers[l].areas.end()) continue;
                clipAreaInto(l, id, it->second, q, areas);
            }
            if (areas.empty()) continue;
            const auto old = std::find_if(before.begin(), before.end(), [&](const auto& b) { return b.first == id; });
            // Bitwise: the children are clipped from these pieces, and must come out bit for bit.
            const bool same = old != before.end() && old->second.size() == areas.size() &&
                              std::equal(areas.begin(), areas.end(), old->second.begin(),
                                         [](const ClippedArea& x, const ClippedArea& y) { return identical(x, y); });
            ql.areas[id] = std::move(areas);
            if (same) {
                r2.areas.erase(std::find(r2.areas.begin(), r2.areas.end(), id));
                continue;
            }
            a2.areas.push_back(id);
        }
    }
    if (removed2.empty() && added2.empty()) return;
    stats.changedQuads.push_back(&q);
    if (!q.isLeaf())
        for (auto& c : q.children) updateQuad(*c, removed2, added2, stats);
}

std::span<const ClippedCurve> Quadtree::createdFrom(const Quad& q, LayerId layer, AncestorId ancestor,
                                                    std::uint32_t parentIndex) {
    if (layer >= q.layers.size()) return {};
    const auto it = q.layers[layer].curves.find(ancestor);
    if (it == q.layers[layer].curves.end()) return {};
    const auto& v = it->second;
    const auto lo = std::lower_bound(v.begin(), v.end(), parentIndex,
                                     [](const ClippedCurve& c, std::uint32_t i) { return c.parentIndex < i; });
    const auto hi = std::upper_bound(lo, v.end(), parentIndex,
                                     [](std::uint32_t i, const ClippedCurve& c) { return i < c.parentIndex; });
    return {lo, hi};
}

std::size_t Quadtree::quadCount() const {
    std::size_t n = 0;
    forEachQuad([&](const Quad&) { ++n; });
    return n;
}

int Quadtree::depth() const {
    int d = 0;
    forEachQuad([&](const Quad& q) { d = std::max(d, q.level); });
    return d;
}

}  // namespace lacet
