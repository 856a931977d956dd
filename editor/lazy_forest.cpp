#include "editor/lazy_forest.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "model/graph.h"

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

// One quad's part: its vector data, graph step, quadtree (down to the quad) and curve data.
struct LazyForest::Part {
    SceneDocument doc;
    GraphStep graphStep;
    Quadtree tree;
    CurveDataCache data;
    Quad* quad = nullptr;
    std::size_t bytes = 0;
    double reach = 0.0;        // m around the quad its read searched
    std::uint64_t wanted = 0;  // the clock of the last refine that wanted it
    double readMs = 0.0;       // its reading and clipping
    Part(SceneDocument d, const GraphStepParams& graph, const RefineParams& refine, const ZProfileParams& profiles,
         const HeightField& heights)
        : doc(std::move(d)), graphStep(doc.scene, graph), tree(doc.scene, refine, &graphStep), data(tree, heights, profiles) {}
};

LazyForest::LazyForest(std::string path, std::string storedChecksum, Quadtree& top, const CurveDataCache& topData, const HeightField& heights,
                       const SessionParams& params, LazyParams lazy)
    : path_(std::move(path)),
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

std::unique_ptr<LazyForest::Part> LazyForest::read(const QuadKey& key, const Box& bounds, double budgetMiB,
                                                   std::shared_ptr<const SceneOverlay> overlay) const {
    SceneRegionOptions filter;
    filter.overlay = overlay.get();
    filter.dem = false;  // the session's DEM serves every part
    filter.budgetMiB = budgetMiB;
    // The quad alone, as a pyramid shard reads it: a box inside it (its neighbours touch its border).
    const Box inside = bounds.dilated(-1e-3 * bounds.size().x);
    SceneRegionStats st;
    SceneDocument doc = loadSceneRegion(path_, inside, refine_, level_, &st, filter);
    if (!storedChecksum_.empty() && st.checksum != storedChecksum_)
        throw SceneFileError(path_ + ": the file changed since it was opened (its stored checksum is " + st.checksum + ", was " +
                             storedChecksum_ + "): open it again");
    auto part = std::make_unique<Part>(std::move(doc), graph_, refine_, profiles_, heights_);
    part->quad = &part->tree.reach(std::get<0>(key), std::get<1>(key), std::get<2>(key));
    part->bytes = st.bytes;
    part->reach = st.reach;
    return part;
}

void LazyForest::settle(Read& r) {
    std::unique_ptr<Part> part;
    try {
        part = r.result.get();
        if (r.version != version_) return;  // read before the last edit: read again when wanted
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

bool LazyForest::refine(std::span<const glm::dvec3> viewers, const ViewParams& view, const std::optional<Deadline>& deadline) {
    ++clock_;
    ViewParams topView = view;
    topView.maxLevel = std::min(view.maxLevel, level_);
    bool done = top_->refineForViewers(viewers, topView, deadline);
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
        auto job = [this, key, bounds, left, overlay = overlay_] {
            const auto t0 = std::chrono::steady_clock::now();
            std::unique_ptr<Part> part = read(key, bounds, left, overlay);
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
            done = it->second->tree.refineSubtree(*it->second->quad, viewers, view, deadline) && done;
    evict(0);
    return done;
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
    for (const ElementRef& r : refs) {
        if (r.layer >= doc.scene.layers.size()) continue;
        const Layer::SceneIds& ids = doc.scene.layers[r.layer].sceneIds;
        const std::vector<ElementId>& of = r.kind == ElementKind::Node ? ids.nodes : r.kind == ElementKind::Curve ? ids.curves : ids.areas;
        if (std::binary_search(of.begin(), of.end(), r.id)) return true;
    }
    return false;
}

std::vector<QuadKey> LazyForest::renew(const std::vector<ElementRef>& refs, const std::vector<Box>& boxes, double margin) {
    std::vector<QuadKey> renewed;
    for (auto it = parts_.begin(); it != parts_.end();) {
        Part& part = *it->second;
        const Box region = part.quad->bounds.dilated(part.reach + margin);
        const bool touched = holdsAny(part.doc, refs) ||
                             std::any_of(boxes.begin(), boxes.end(), [&](const Box& b) { return b.intersects(region); });
        if (!touched) {
            ++it;
            continue;
        }
        const QuadKey key = it->first;
        renewed.push_back(key);
        held_ -= part.bytes;
        const std::uint64_t wanted = part.wanted;
        const Box bounds = part.quad->bounds;
        it = parts_.erase(it);
        try {
            const auto t0 = std::chrono::steady_clock::now();
            std::unique_ptr<Part> again = read(key, bounds, budgetLeft(), overlay_);
            again->readMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            again->wanted = wanted;
            held_ += again->bytes;
            stats_.largestPartMiB = std::max(stats_.largestPartMiB, toMiB(again->bytes));
            ++stats_.partsRenewed;
            it = parts_.emplace_hint(it, key, std::move(again));
            ++it;
        } catch (const SceneBudgetError&) {
            refused_[key] = budgetLeft();
            ++stats_.partsRefused;
        } catch (const std::exception& e) {
            refused_[key] = std::numeric_limits<double>::infinity();
            ++stats_.partsRefused;
            stats_.lastError = e.what();
        }
    }
    stats_.partsHeld = parts_.size();
    stats_.heldMiB = toMiB(held_);
    stats_.peakMiB = std::max(stats_.peakMiB, stats_.heldMiB);
    return renewed;
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
