#include "editor/lazy_forest.h"
#include "editor/lazy_forest_part.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "model/graph.h"
#include "model/quadtree.h"

namespace lacet {

int LazyParams::level(const Box& extent) const {
    validate();
    if (partLevel >= 1) return partLevel;
    int l = 1;
    while (l < 30 && extent.size().x / double(std::int64_t(1) << l) > partQuadM * (1.0 + 1e-9)) ++l;
    return l;
}

void LazyParams::validate() const {
    if (partLevel != -1 && (partLevel < 1 || partLevel > 30))
        throw std::invalid_argument("LazyParams: the part level must be -1 (from partQuadM) or in 1..30, not " + std::to_string(partLevel));
    if (!(partQuadM > 0.0) || !std::isfinite(partQuadM)) throw std::invalid_argument("LazyParams: partQuadM must be > 0 m");
    if (!(vectorBudgetMiB > 0.0)) throw std::invalid_argument("LazyParams: the vector budget must be > 0 MiB");
}

LazyForest::LazyForest(std::string path, std::string storedChecksum, Quadtree& top, const CurveDataCache& topData, const HeightField& heights,
                       const SessionParams& params, LazyParams lazy)
    : path_(std::move(path)),
      connection_(path_),
      storedChecksum_(std::move(storedChecksum)),
      top_(&top),
      topData_(&topData),
      overlay_(std::make_shared<const SceneOverlay>()),
      heights_(heights),
      refine_(params.refine),
      graph_(params.graph),
      profiles_(params.profiles),
      lazy_(lazy) {
    level_ = lazy_.level(top_->root().bounds);
    stats_.partLevel = level_;
    // The parts share the budget with the top tree's vector data.
    stats_.topMiB = toMiB(memoryBytes(top_->scene()));
    partsBudgetMiB_ = lazy_.vectorBudgetMiB - stats_.topMiB;
    if (!(partsBudgetMiB_ > 0.0))
        throw SceneBudgetError(path_ + ": the levels down to the part level " + std::to_string(level_) + " hold " +
                               std::to_string(stats_.topMiB) + " MiB of vector data, the whole vector budget of " +
                               std::to_string(lazy_.vectorBudgetMiB) + " MiB; raise it, or read their appearance from a pyramid");
}

double LazyForest::topMinCurveWidth(const Box& extent, const LazyParams& lazy, const RefineParams& refine) {
    return 2.0 * extent.size().x / double(std::int64_t(1) << lazy.level(extent)) / double(refine.elevationResolution);
}

LazyTop LazyForest::readTop(const std::string& path, const LazyParams& lazy, const RefineParams& refine, bool dem,
                            const SceneOverlay* overlay) {
    const Box extent = loadSceneExtent(path);
    const int level = lazy.level(extent);
    SceneRegionOptions filter;
    filter.elevationOnly = lazy.topElevationOnly;
    filter.minCurveWidth = topMinCurveWidth(extent, lazy, refine);
    filter.budgetMiB = lazy.vectorBudgetMiB;
    filter.dem = dem;
    filter.overlay = overlay;
    LazyTop top;
    top.path = path;
    top.doc = loadSceneRegion(path, extent, refine, level, &top.stats, filter);
    return top;
}

LazyForest::~LazyForest() {
    for (Read& r : reading_)
        if (r.result.valid()) r.result.wait();
}

SceneDocument LazyForest::readPart(const Box& bounds, double budgetMiB, const SceneOverlay* overlay, SceneRegionStats& st,
                                   SceneFileConnection* connection) const {
    SceneRegionOptions filter;
    filter.overlay = overlay;
    filter.dem = false;  // the session's DEM serves every part
    filter.budgetMiB = budgetMiB;
    // The quad alone, as a pyramid shard reads it: a box inside it (its neighbours touch its border).
    const Box inside = bounds.dilated(-1e-3 * bounds.size().x);
    SceneDocument doc = connection ? loadSceneRegion(*connection, inside, refine_, level_, &st, filter)
                                   : loadSceneRegion(path_, inside, refine_, level_, &st, filter);
    if (!storedChecksum_.empty() && st.checksum != storedChecksum_)
        throw SceneFileError(path_ + ": the file changed since it was opened (its stored checksum is " + st.checksum + ", was " +
                             storedChecksum_ + "): open it again");
    return doc;
}

std::unique_ptr<LazyForest::Part> LazyForest::makePart(const QuadKey& key, SceneDocument doc, const SceneRegionStats& st) const {
    auto part = std::make_unique<Part>(std::move(doc), graph_, refine_, profiles_, heights_);
    part->quad = &part->tree.reach(std::get<0>(key), std::get<1>(key), std::get<2>(key));
    part->bytes = st.bytes;
    part->reach = st.reach;
    part->tolerance = st.tolerance;
    return part;
}

std::unique_ptr<LazyForest::Part> LazyForest::read(const QuadKey& key, const Box& bounds, double budgetMiB,
                                                   std::shared_ptr<const SceneOverlay> overlay, SceneFileConnection* connection) const {
    SceneRegionStats st;
    SceneDocument doc = readPart(bounds, budgetMiB, overlay.get(), st, connection);
    return makePart(key, std::move(doc), st);
}

void LazyForest::warmCurveData(const Part& part) {
    const Scene& scene = part.doc.scene;
    const Box near = part.quad->bounds.dilated(part.reach);
    for (LayerId l = 0; l < scene.layers.size(); ++l) {
        const Layer& layer = scene.layers[l];
        if (layer.kind == LayerKind::Roads || layer.kind == LayerKind::Rivers) {
            for (ElementId c = 0; c < layer.curves.size(); ++c) {
                const Curve& curve = layer.curves[c];
                if (!curve.alive || curve.vertices.empty() || !hullBox(curve).intersects(near)) continue;
                const std::span<const AncestorId> expansion = part.tree.expansionOf(l, c);
                if (expansion.empty()) part.data.zProfile(l, AncestorId(c));
                for (const AncestorId a : expansion) part.data.zProfile(l, a);
            }
        } else if (layer.kind == LayerKind::Lakes) {
            for (ElementId a = 0; a < layer.areas.size(); ++a) {
                if (!layer.areas[a].alive) continue;
                bool meets = false;
                for (const auto& loop : layer.areas[a].loops)
                    for (const AreaEdge& e : loop) meets = meets || hullBox(layer.curves[e.curve]).intersects(near);
                if (meets) part.data.lakeLevel(l, a);
            }
        }
    }
}

namespace {

// Whether two parts read hold the same elements (the same file ids, layer by layer) but for
// elements at the end of a kind's ids that one holds and the other not: the elements a step
// added (ids past the file's, the largest) or took back, or an element of the part's largest id
// that moved in or out (either way the part becomes the new read, with the changeset to match).
bool sameButTails(const Scene& a, const Scene& b) {
    if (a.layers.size() != b.layers.size()) return false;
    const auto prefix = [](const std::vector<ElementId>& x, const std::vector<ElementId>& y) {
        const std::size_t n = std::min(x.size(), y.size());
        return std::equal(x.begin(), x.begin() + std::ptrdiff_t(n), y.begin());
    };
    for (std::size_t l = 0; l < a.layers.size(); ++l) {
        const Layer::SceneIds &x = a.layers[l].sceneIds, &y = b.layers[l].sceneIds;
        if (!prefix(x.nodes, y.nodes) || !prefix(x.curves, y.curves) || !prefix(x.areas, y.areas)) return false;
    }
    return true;
}

// Makes `into` `from` (the same ids but for a tail one has): sets each element of the ids both
// hold that differs and names it modified; the elements `from` holds past `into`'s are added,
// those `into` holds past `from`'s removed (as the whole scene's add and its undo).
template <class T>
void copyChanged(std::vector<T>& into, std::vector<T>& from, LayerId l, ElementKind kind, Changeset& cs) {
    const std::size_t common = std::min(into.size(), from.size());
    for (std::size_t id = 0; id < common; ++id)
        if (!(into[id] == from[id])) {
            into[id] = from[id];
            cs.modify({l, kind, ElementId(id)});
        }
    for (std::size_t id = common; id < from.size(); ++id) cs.added.push_back({l, kind, ElementId(id)});
    for (std::size_t id = common; id < into.size(); ++id) cs.removed.push_back({l, kind, ElementId(id)});
    into.resize(common);
    for (std::size_t id = common; id < from.size(); ++id) into.push_back(std::move(from[id]));
}

}  // namespace

void LazyForest::update(Part& part, SceneDocument doc, const LazyStep& step, std::set<QuadKey>& changed) {
    Changeset cs;
    Scene& scene = part.doc.scene;
    // What the edit named changed besides the values that differ: the areas whose loops a moved
    // curve is in, the nodes whose curves' widths changed (model/edits.h); those held before and
    // after (an element added or taken back is in the tails below).
    for (const ElementRef& r : step.refs)
        if (r.layer < scene.layers.size())
            if (const ElementId id = localIdOf(scene.layers[r.layer], r.kind, r.id);
                id != kNoElement && localIdOf(doc.scene.layers[r.layer], r.kind, r.id) == id)
                cs.modify({r.layer, r.kind, id});
    for (std::size_t l = 0; l < scene.layers.size(); ++l) {
        Layer& into = scene.layers[l];
        Layer& from = doc.scene.layers[l];
        copyChanged(into.nodes, from.nodes, LayerId(l), ElementKind::Node, cs);
        copyChanged(into.curves, from.curves, LayerId(l), ElementKind::Curve, cs);
        copyChanged(into.areas, from.areas, LayerId(l), ElementKind::Area, cs);
        into.sceneIds = std::move(from.sceneIds);
    }
    part.doc.attributes = std::move(doc.attributes);
    applyChangeset(part, std::move(cs), changed);
}

void LazyForest::applyChangeset(Part& part, Changeset cs, std::set<QuadKey>& changed) {
    if (cs.empty()) return;
    cs.normalize();
    const Scene& scene = part.doc.scene;
    // As a whole scene's edit (editor/edit_session.cpp: afterEdit): the curve data, UPDATE, and
    // the procedural curves expanded again.
    std::vector<ElementRef> dropped = part.data.invalidate(cs);
    const UpdateStats st = part.tree.update(cs);
    if (!st.reexpanded.empty()) {
        Changeset again;
        for (const ElementRef& e : st.reexpanded) again.modify(e);
        const std::vector<ElementRef> more = part.data.invalidate(again);
        dropped.insert(dropped.end(), more.begin(), more.end());
    }
    const std::set<const Quad*> updated(st.changedQuads.begin(), st.changedQuads.end());
    auto visit = [&](const Quad& q, const auto& self) -> void {
        if (updated.count(&q) > 0 || holdsDropped(q, part.tree, scene, dropped)) changed.insert(keyOf(q));
        if (!q.isLeaf())
            for (const auto& c : q.children) self(*c, self);
    };
    visit(*part.quad, visit);
}

void LazyForest::settle(Read& r) {
    std::unique_ptr<Part> part;
    try {
        part = r.result.get();
        if (r.version != version_) {
            // Read before the last edits: read again now if one of them touched it.
            const bool stale = std::any_of(steps_.begin(), steps_.end(), [&](const Step& s) {
                return s.version > r.version && touches(*part, s.step, s.margin);
            });
            if (stale) {
                const Box bounds = part->quad->bounds;
                part = read(r.key, bounds, r.budgetMiB, overlay_, &connection_);
            }
        }
    } catch (const SceneBudgetError&) {
        refused_[r.key] = r.budgetMiB;  // tried again only with more room
        ++stats_.partsRefused;
        return;
    } catch (const std::exception& e) {  // the file cannot give it: the top tree's quad stays
        refused_[r.key] = std::numeric_limits<double>::infinity();
        ++stats_.partsRefused;
        stats_.lastError = e.what();
        return;
    }
    stats_.readMs += part->readMs;
    stats_.slowestReadMs = std::max(stats_.slowestReadMs, part->readMs);
    // Room beside the parts wanted now: what was read while they changed may no longer fit.
    evict(part->bytes);
    if (toMiB(held_ + part->bytes) > partsBudgetMiB_) {
        refused_[r.key] = budgetLeft();
        ++stats_.partsRefused;
        return;
    }
    refused_.erase(r.key);
    held_ += part->bytes;
    part->wanted = wanted_.count(r.key) > 0 ? clock_ : clock_ - 1;  // one no viewer wants now goes first
    stats_.largestPartMiB = std::max(stats_.largestPartMiB, toMiB(part->bytes));
    ++stats_.partsRead;
    arrived_.push_back(r.key);
    parts_[r.key] = std::move(part);
    stats_.partsHeld = parts_.size();
    stats_.partsHeldPeak = std::max(stats_.partsHeldPeak, parts_.size());
    stats_.heldMiB = toMiB(held_);
    stats_.peakMiB = std::max(stats_.peakMiB, stats_.heldMiB);
}

void LazyForest::evict(std::size_t keepBytes) {
    while (held_ > 0 && toMiB(held_ + keepBytes) > partsBudgetMiB_) {
        auto oldest = parts_.end();
        for (auto it = parts_.begin(); it != parts_.end(); ++it)
            if (it->second->wanted < clock_ && (oldest == parts_.end() || it->second->wanted < oldest->second->wanted)) oldest = it;
        if (oldest == parts_.end()) return;  // every part held is wanted now
        held_ -= oldest->second->bytes;
        parts_.erase(oldest);
        ++stats_.partsEvicted;
    }
    stats_.partsHeld = parts_.size();
    stats_.heldMiB = toMiB(held_);
}

double LazyForest::budgetLeft() const {
    std::size_t wanted = 0;
    for (const auto& [key, part] : parts_)
        if (part->wanted == clock_) wanted += part->bytes;
    return partsBudgetMiB_ - toMiB(wanted);
}

bool LazyForest::refine(std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline,
                        ChildMaker* maker) {
    ++clock_;
    ViewParams topView = view;
    topView.maxLevel = std::min(view.maxLevel, level_);
    bool done = top_->refineForViewers(viewers, topView, deadline, maker);
    // The quads of level P a viewer wants subdivided, nearest to the first viewer first.
    std::vector<const Quad*> wanted;
    if (view.maxLevel > level_)
        top_->forEachQuad([&](const Quad& q) {
            if (q.level != level_) return;
            for (const glm::dvec3& v : viewers)
                if (Quadtree::wantsSubdivision(q, v, view)) return wanted.push_back(&q);
        });
    std::stable_sort(wanted.begin(), wanted.end(), [&](const Quad* a, const Quad* b) {
        return Quadtree::viewDistance(*a, viewers[0]) < Quadtree::viewDistance(*b, viewers[0]);
    });
    wanted_.clear();
    for (const Quad* q : wanted) {
        wanted_.insert(keyOf(*q));
        if (const auto it = parts_.find(keyOf(*q)); it != parts_.end()) it->second->wanted = clock_;
    }
    // The parts the worker finished, now that the parts wanted are known (those are kept).
    std::erase_if(reading_, [&](Read& r) {
        if (r.result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
        settle(r);
        return true;
    });
    // A part no viewer wants now is its quad alone (a leaf, as the top tree has it): what was
    // refined below it for an earlier view goes.
    for (auto& [key, part] : parts_)
        if (part->wanted != clock_) part->tree.merge(*part->quad);
    // The missing ones: read now, or the nearest asked of the worker when it is free.
    for (const Quad* q : wanted) {
        const QuadKey key = keyOf(*q);
        if (parts_.count(key) > 0) continue;
        if (std::any_of(reading_.begin(), reading_.end(), [&](const Read& r) { return r.key == key; })) {
            done = false;
            continue;
        }
        const double left = budgetLeft();
        if (const auto it = refused_.find(key); it != refused_.end() && !(left > it->second)) continue;  // still no room
        if (left <= 0.0) {
            refused_[key] = left;
            ++stats_.partsRefused;
            continue;
        }
        if (lazy_.background && !reading_.empty()) {
            done = false;
            continue;
        }
        const Box bounds = q->bounds;
        Read r{key, left, version_, {}};
        // The worker's read opens the file itself; one in this thread keeps the connection.
        auto job = [this, key, bounds, left, overlay = overlay_, connection = lazy_.background ? nullptr : &connection_] {
            const auto t0 = std::chrono::steady_clock::now();
            std::unique_ptr<Part> part = read(key, bounds, left, overlay, connection);
            if (!connection) {  // on the worker: off the frames
                try {
                    warmCurveData(*part);
                } catch (const std::exception&) {
                    // A warm-up only: the frame that asks for what failed makes it, and says why.
                }
            }
            part->readMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            return part;
        };
        if (lazy_.background) {
            r.result = std::async(std::launch::async, job);
            reading_.push_back(std::move(r));
            done = false;
        } else {
            r.result = std::async(std::launch::deferred, job);
            settle(r);
        }
    }
    for (const Quad* q : wanted)
        if (const auto it = parts_.find(keyOf(*q)); it != parts_.end())
            done = it->second->tree.refineSubtree(*it->second->quad, viewers, view, deadline, maker) && done;
    evict(0);
    return done;
}

void LazyForest::forEachPart(const std::function<void(const SceneDocument&)>& f) const {
    for (const auto& [key, part] : parts_) f(part->doc);
}

void LazyForest::waitForReads() const {
    for (const Read& r : reading_)
        if (r.result.valid()) r.result.wait();
}

void LazyForest::setOverlay(std::shared_ptr<const SceneOverlay> overlay, std::uint64_t version) {
    if (!overlay) throw std::invalid_argument("LazyForest::setOverlay: no overlay");
    overlay_ = std::move(overlay);
    version_ = version;
}

void LazyForest::setTop(Quadtree& top, const CurveDataCache& topData) {
    top_ = &top;
    topData_ = &topData;
    stats_.topMiB = toMiB(memoryBytes(top_->scene()));
    partsBudgetMiB_ = lazy_.vectorBudgetMiB - stats_.topMiB;
    evict(0);
}


bool LazyForest::holdsAny(const SceneDocument& doc, const std::vector<ElementRef>& refs) {
    return std::any_of(refs.begin(), refs.end(), [&](const ElementRef& r) { return holdsElement(doc.scene, r); });
}

bool LazyForest::touches(const Part& part, const LazyStep& step, double margin) {
    const Box region = part.quad->bounds.dilated(part.reach + margin);
    if (holdsAny(part.doc, step.refs) || std::any_of(step.boxes.begin(), step.boxes.end(), [&](const Box& b) { return b.intersects(region); }))
        return true;
    // A held road's read brought the rivers its hull meets, a bridge road's the roads too
    // (io/scene_region.cpp: closeCurve), wherever they are: a river of the step (or a road, for a
    // held bridge) whose box meets such a hull is one the part's read holds now, or would.
    std::vector<Box> rivers, roads;
    for (std::size_t k = 0; k < step.refs.size(); ++k) {
        const ElementRef& r = step.refs[k];
        if (r.kind == ElementKind::Node || r.layer >= part.doc.scene.layers.size()) continue;
        const LayerKind kind = part.doc.scene.layers[r.layer].kind;
        if (kind != LayerKind::Rivers && kind != LayerKind::Roads) continue;
        for (const std::vector<OverlayElement>* side : {&step.before, &step.after})
            if (k < side->size() && (*side)[k].box) (kind == LayerKind::Rivers ? rivers : roads).push_back(*(*side)[k].box);
    }
    if (rivers.empty() && roads.empty()) return false;
    const auto meets = [](const std::vector<Box>& boxes, const Box& hull) {
        return std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.intersects(hull); });
    };
    for (const Layer& layer : part.doc.scene.layers) {
        if (layer.kind != LayerKind::Roads) continue;
        for (const Curve& c : layer.curves) {
            if (!c.alive || c.vertices.empty() || (rivers.empty() && !(c.flags & kBridge))) continue;
            const Box hull = hullBox(c).dilated(part.tolerance);
            if (meets(rivers, hull) || ((c.flags & kBridge) && meets(roads, hull))) return true;
        }
    }
    return false;
}

LazyForest::Renewal LazyForest::renew(const LazyStep& step, double margin) {
    // The steps a read in flight began before (settle() reads such a part again when one touches it).
    std::uint64_t oldest = version_;
    for (const Read& r : reading_) oldest = std::min(oldest, r.version);
    std::erase_if(steps_, [&](const Step& s) { return s.version <= oldest; });
    if (!reading_.empty()) steps_.push_back({version_, step, margin});
    Renewal out;
    StepRivers rivers;  // read once for the step, whatever the parts that ask
    for (auto it = parts_.begin(); it != parts_.end();) {
        Part& part = *it->second;
        if (!touches(part, step, margin)) {
            ++it;
            continue;
        }
        const QuadKey key = it->first;
        out.parts.push_back(key);
        ++stats_.partsRenewed;
        const std::size_t bytes = part.bytes;
        const bool grows = addsOrTakesCurves(step);
        if (grows ? growInPlace(part, step, rivers, out.changed) : moveInPlace(part, step, rivers, out.changed)) {
            held_ = held_ - bytes + part.bytes;
            ++(grows ? stats_.partsGrown : stats_.partsMoved);
            ++it;
            continue;
        }
        const auto t0 = std::chrono::steady_clock::now();
        try {
            SceneRegionStats st;
            // Room for it beside the others wanted now.
            SceneDocument doc = readPart(part.quad->bounds, budgetLeft() + (part.wanted == clock_ ? toMiB(part.bytes) : 0.0), overlay_.get(), st,
                                         &connection_);
            if (sameButTails(part.doc.scene, doc.scene)) {
                update(part, std::move(doc), step, out.changed);
                held_ = held_ - part.bytes + st.bytes;
                part.bytes = st.bytes;
                part.reach = st.reach;
                ++stats_.partsUpdated;
                ++it;
                continue;
            }
            std::unique_ptr<Part> again = makePart(key, std::move(doc), st);
            again->wanted = part.wanted;
            again->readMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            held_ = held_ - part.bytes + again->bytes;
            stats_.largestPartMiB = std::max(stats_.largestPartMiB, toMiB(again->bytes));
            it->second = std::move(again);
            ++it;
        } catch (const SceneBudgetError&) {
            held_ -= part.bytes;
            it = parts_.erase(it);
            refused_[key] = budgetLeft();
            ++stats_.partsRefused;
        } catch (const std::exception& e) {
            held_ -= part.bytes;
            it = parts_.erase(it);
            refused_[key] = std::numeric_limits<double>::infinity();
            ++stats_.partsRefused;
            stats_.lastError = e.what();
        }
        out.rebuilt.push_back(key);
    }
    stats_.partsHeld = parts_.size();
    stats_.heldMiB = toMiB(held_);
    stats_.peakMiB = std::max(stats_.peakMiB, stats_.heldMiB);
    return out;
}

std::vector<QuadKey> LazyForest::takeArrived() {
    std::vector<QuadKey> out;
    out.swap(arrived_);
    return out;
}

const LazyForest::Part* LazyForest::owner(const Quad& q) const {
    if (q.level < level_) return nullptr;
    const Quad* a = &q;
    while (a->level > level_) a = a->parent;
    const auto it = parts_.find(keyOf(*a));
    return it != parts_.end() && it->second->quad == a ? it->second.get() : nullptr;
}

const Quad& LazyForest::resolve(const Quad& q) const {
    if (q.level != level_) return q;
    const auto it = parts_.find(keyOf(q));
    return it != parts_.end() ? *it->second->quad : q;
}

const Quad* LazyForest::parentOf(const Quad& q) const {
    if (q.level != level_ || !owner(q)) return q.parent;
    // A part's quad: its parent is the top tree's quad above the top's quad it stands for (the
    // levels above P resolve to the top tree's own quads).
    return findQuad(*this, {level_ - 1, q.tx >> 1, q.ty >> 1});
}

const Quadtree& LazyForest::treeOf(const Quad& q) const {
    const Part* p = owner(q);
    return p ? p->tree : *top_;
}

const CurveDataCache& LazyForest::dataOf(const Quad& q) const {
    const Part* p = owner(q);
    return p ? p->data : *topData_;
}

}  // namespace lacet
