#include "editor/tile_loop.h"

#include <algorithm>
#include <atomic>
#include <climits>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "model/work_clock.h"

namespace lacet {
namespace {

using Clock = std::chrono::steady_clock;

// Sorts quads nearest to the viewer `v` first (Quadtree::viewDistance, the K rule's distance).
auto nearestFirst(glm::dvec3 v) {
    return [v](const Quad* a, const Quad* b) { return Quadtree::viewDistance(*a, v) < Quadtree::viewDistance(*b, v); };
}

}  // namespace

TileLoop::TileLoop(const SessionParams& params, const Scene& scene, const Dem& dem, DemStream* stream)
    : params_(params), scene_(scene), dem_(dem), stream_(stream) {}

TileLoop::~TileLoop() { quiesce(); }

void TileLoop::setTree(Quadtree& tree, const CurveDataCache& data) {
    quiesce();  // before the old forest goes
    whole_ = std::make_unique<WholeTree>(tree, data);
    setForest(*whole_);
}

void TileLoop::setForest(QuadForest& forest) {
    quiesce();
    if (&forest != whole_.get()) whole_.reset();
    forest_ = &forest;
    cache_.clear();
    plan_.clear();
    planPending_ = false;
}

std::size_t TileLoop::edited(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped, bool edited) {
    quiesce();  // the session stopped them before the edit (EditSession::execute); a caller that did not
    ++edits_;
    const std::size_t dirty = markDirty(changed, dropped);
    if (touchLevels_ > 0) recordTouched(changed, dropped, edited);
    return dirty;
}

std::size_t TileLoop::editedLazily(const std::set<QuadKey>& changed, const std::vector<QuadKey>& touched) {
    quiesce();
    ++edits_;
    const std::size_t dirty = markDirty(changed, {});
    if (touchLevels_ > 0)
        for (const QuadKey& key : touched)
            if (std::get<0>(key) < touchLevels_) touched_[key] = touchedBelow_[key] = edits_;
    return dirty;
}

std::size_t TileLoop::markDirty(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped) {
    std::size_t dirty = 0;
    for (auto& [key, tile] : cache_) {
        if (tile.dirty) continue;
        const Quad* q = findQuad(*forest_, key);
        // A tile whose quad is not in the tree now cannot be checked: it is redone if needed.
        if (!q || changed.count(key) > 0 || holdsDropped(*q, dropped)) {
            tile.dirty = true;
            ++dirty;
        }
    }
    return dirty;
}

void TileLoop::layerChanged(LayerId layer) {
    quiesce();  // made with the layers shown before
    for (auto& [key, tile] : cache_) {
        const Quad* q = findQuad(*forest_, key);
        if (!q || (q->layers.size() > layer && !q->layers[layer].empty())) tile.dirty = true;
    }
}

bool TileLoop::holdsDropped(const Quad& q, const std::vector<ElementRef>& dropped) const {
    return lacet::holdsDropped(q, forest_->treeOf(q), scene_, dropped);
}

void TileLoop::recordTouched(const std::set<QuadKey>& changed, const std::vector<ElementRef>& dropped, bool edited) {
    // The quads below L, walked from the root (a few hundred at most): UPDATE says exactly which
    // children of a changed quad changed, but nothing of the quads below a leaf, which the tree
    // will make from the changed graph when it subdivides: all of them count as changed.
    auto visit = [&](const Quad& q, const auto& self) -> void {
        if (q.level >= touchLevels_) return;
        const QuadKey key = keyOf(q);
        if ((edited && !q.parent) || changed.count(key) > 0 || holdsDropped(q, dropped)) {
            touched_[key] = edits_;
            if (q.isLeaf()) touchedBelow_[key] = edits_;
        }
        if (!q.isLeaf())
            for (const auto& c : q.children) self(forest_->resolve(*c), self);
    };
    visit(forest_->resolve(forest_->root()), visit);
}

bool TileLoop::touched(const Quad& q) const {
    if (touched_.count(keyOf(q)) > 0) return true;
    if (touchedBelow_.empty()) return false;
    for (const Quad* a = &q; a; a = a->parent)
        if (touchedBelow_.count(keyOf(*a)) > 0) return true;
    return false;
}

bool TileLoop::readsPyramid(const Quad& q) const {
    if (!pyramid_ || !pyramid_->serves(q.level)) return false;
    const std::vector<bool>& hidden = params_.appearance.hiddenLayers;
    if (std::find(hidden.begin(), hidden.end(), true) != hidden.end()) return false;  // made with every layer
    // Where the forest cannot make it (a lazy scene's levels above its parts), an edit shows once
    // the pyramid is updated.
    return !touched(q) || !forest_->holdsAppearance(q);
}

void TileLoop::setPyramid(std::shared_ptr<PyramidReader> pyramid, std::optional<std::uint64_t> madeAt) {
    if (pyramid && pyramid->tileSize() != params_.refine.resolution)
        throw std::invalid_argument("EditSession::setPyramid(): the pyramid's tiles are " + std::to_string(pyramid->tileSize()) +
                                    " texels, the session's " + std::to_string(params_.refine.resolution));
    const std::uint64_t at = madeAt.value_or(edits_);
    if (at > edits_) throw std::invalid_argument("EditSession::setPyramid(): madeAt is after the last edit");
    // What the new pyramid holds already is no longer touched.
    std::erase_if(touched_, [&](const auto& e) { return e.second <= at; });
    std::erase_if(touchedBelow_, [&](const auto& e) { return e.second <= at; });
    if (pyramid) touchLevels_ = std::max(touchLevels_, std::min(pyramid->vectorLevel(), pyramid->maxLevel() + 1));
    pyramid_ = std::move(pyramid);
}

TileLoop::Source TileLoop::runJob(bool appearance, const Quad& q, const Quadtree& tree, const CurveDataCache& data, bool read,
                                  const Dem& dem, const std::function<const Dem&()>& objectDem, const JobParams& p, CachedTile& t,
                                  const CancelFlag* cancel) {
    const std::size_t elements = elementCount(q);
    Source source = kLive;
    auto j0 = p.clock();
    if (read) {
        std::optional<AppearanceTile> tile = p.pyramid->appearance(q, p.border);
        estimates_[2].add(0, msSince(p.clock, j0));
        if (tile) {
            t.appearance = std::move(*tile);
            return kRead;
        }
        source = kFailed;  // made live below
        j0 = p.clock();
    }
    if (appearance) {
        t.appearance = produceAppearance(q, tree, data, dem, p.appearance, nullptr, cancel);
    } else {
        // The quad's objects stand on its displayed ground: made right after its z_m.
        t.elevation = produceElevation(q, tree, data, dem, p.elevation, nullptr, cancel);
        throwIfCancelled(cancel);
        t.objects = produceObjects(q, tree, data, objectDem(), &t.elevation, p.objects, &objectCounters_);
    }
    // The root's graph is empty (the scene is its graph): its time says nothing of the others'.
    if (q.parent) estimates_[appearance ? 0 : 1].add(elements, msSince(p.clock, j0));
    return source;
}

void TileLoop::countPyramidUse(char source) {
    pyramidUse_.read += source == kRead;
    pyramidUse_.failed += source == kFailed;
    pyramidUse_.touched += source == kTouched;
    pyramidUse_.live += source != kRead;
}

void TileLoop::store(const QuadKey& key, CachedTile&& made, char source, const DemWindow* window, int objectLevel, FrameReport& r) {
    r.fromPyramid += source == kRead;
    r.pyramidFailed += source == kFailed;
    CachedTile& t = cache_[key];
    t = std::move(made);
    if (window && window->dem) {
        t.demLevel = std::min(window->level, objectLevel);
        t.demWanted = window->wanted;
        r.demFallbacks += !window->complete();
    }
    t.lastUsed = clock_;
    t.version = ++version_;
}

std::size_t TileLoop::produce(const std::vector<const Quad*>& all, glm::dvec3 viewer, double budgetMs, Clock::time_point t0,
                                 FrameReport& r) {
    // A work queue in nearest-first order, one job per producer and quad (so the two threads
    // stay busy until the last tile, whatever each tile costs). Each worker takes the next job;
    // with a budget, a job whose estimated time (editor/production_estimate.h) would overrun it
    // is not started, and the workers take no more (a job the other worker took just before may
    // still run if its own estimate fits; a quad with one job of two made is dropped). The first
    // quad of a call is always made, so every frame makes progress. A quad is made when both its
    // jobs are. An appearance job of a quad the pyramid serves reads it there (its own estimate:
    // a read costs the same whatever the quad holds), or makes it live when the read fails.
    // With a budget and background tiles, a slow quad is left to the background thread (the
    // nearest, when it is free) and the others wait.
    std::vector<const Quad*> quads;
    std::vector<char> fromPyramid;
    quads.reserve(all.size());
    for (const Quad* q : all) {
        const bool read = readsPyramid(*q);
        if (budgetMs > 0.0 && params_.backgroundMs > 0.0) {
            const QuadKey key = keyOf(*q);
            if (std::any_of(background_.begin(), background_.end(), [&](const Background& b) { return b.key == key; })) continue;
            if (slow(*q, read)) {
                if (background_.size() < backgroundLanes()) startBackground(*q, read, viewer, r);
                continue;
            }
        }
        quads.push_back(q);
        fromPyramid.push_back(read);
    }
    const std::size_t jobs = 2 * quads.size();
    std::vector<CachedTile> made(quads.size());
    std::vector<char> done(jobs, 0);  // each written by one worker, read after they join
    std::vector<char> source(quads.size(), kLive);
    for (std::size_t i = 0; i < quads.size(); ++i)
        if (!fromPyramid[i] && pyramid_ && pyramid_->serves(quads[i]->level)) source[i] = kTouched;
    const JobParams p{params_.appearance, params_.elevation, params_.objects, params_.clock, params_.refine.appearanceBorder, pyramid_.get()};
    // With a streamed DEM, each quad's window (a copy of a few thousand samples), cut by the first
    // of its two jobs to run, so that both read the same one.
    std::vector<DemWindow> windows(stream_ ? quads.size() : 0);
    const std::unique_ptr<std::once_flag[]> cutOnce(stream_ ? new std::once_flag[quads.size()] : nullptr);
    std::vector<int> objectLevel(windows.size(), INT_MAX);  // the level the objects' window was cut from
    auto demOf = [&](std::size_t i) -> const Dem& {
        if (windows.empty()) return dem_;
        std::call_once(cutOnce[i], [&] { windows[i] = demWindow(*quads[i], viewer); });
        return *windows[i].dem;
    };
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    const int workers = std::max(1, std::min(tbb::this_task_arena::max_concurrency(), int(jobs)));
    tbb::parallel_for(0, workers, [&](int) {
        for (;;) {
            if (stop) return;
            const std::size_t j = next.fetch_add(1);
            if (j >= jobs) return;
            const bool appearance = j % 2 == 0;
            const std::size_t i = j / 2;
            const Quad& q = *quads[i];
            const bool read = appearance && fromPyramid[i];
            const std::size_t x = read ? 0 : elementCount(q);
            if (budgetMs > 0.0 && j >= 2 && msSince(params_.clock, t0) + estimates_[read ? 2 : appearance ? 0 : 1].predict(x) > budgetMs) {
                stop = true;
                return;
            }
            std::shared_ptr<const Dem> objects;  // a wider window over the bridges the quad makes
            const Source s = runJob(appearance, q, forest_->treeOf(q), forest_->dataOf(q), read, demOf(i), [&]() -> const Dem& {
                if (windows.empty()) return demOf(i);
                const DemWindow w = objectWindow(q, viewer, windows[i]);
                objectLevel[i] = w.level;
                objects = w.dem;
                return *objects;
            }, p, made[i], nullptr);
            if (appearance && s != kLive) source[i] = s;
            done[j] = 1;
        }
    });
    std::size_t count = 0;
    for (std::size_t i = 0; i < quads.size(); ++i) {
        if (done[2 * i]) countPyramidUse(source[i]);  // even when its quad is dropped (the pyramid's work is done)
        if (!done[2 * i] || !done[2 * i + 1]) continue;
        store(keyOf(*quads[i]), std::move(made[i]), source[i], windows.empty() ? nullptr : &windows[i], windows.empty() ? INT_MAX : objectLevel[i], r);
        ++count;
    }
    return count;
}

// §8, each frame: refine the quadtree for the viewer, choose the quads shown within the cache
// (§9.1), make their missing and dirty tiles nearest first within the budget, then those of the
// predicted viewer, evict, and plan what is drawn.
FrameReport TileLoop::frame(glm::dvec3 viewer, double budgetMs, const QuadVisibility& visible,
                               std::optional<glm::dvec3> predicted) {
    FrameReport r;
    takeBackground(r);
    refine(viewer, predicted, budgetMs > 0.0 && params_.backgroundMs > 0.0, r);
    if (budgetMs > 0.0) budgetMs = std::max(1e-9, budgetMs - r.refineMs);
    ++clock_;
    FrameLeaves leaves = collectLeaves(viewer, predicted, visible, r);
    const CacheFit fit = fitToCache(leaves.view, params_.cacheTiles, viewer, [&](const Quad& q) { return cache_.count(keyOf(q)) > 0; }, forest_);
    r.shown = fit.shown.size();
    r.replaced = fit.replaced.size();
    if (stream_) followDemStream(fit, viewer, r);
    std::vector<const Quad*> needed = keepShown(fit);
    if (predicted) keepMadeAhead(std::move(leaves.madeAhead), fit.kept, *predicted);
    std::stable_sort(needed.begin(), needed.end(), nearestFirst(viewer));
    const auto t0 = params_.clock();
    r.produced = produce(needed, viewer, budgetMs, t0, r);
    r.pending = needed.size() - r.produced;
    if (predicted && r.pending == 0) r.prefetched = prefetch(std::move(leaves.ahead), *predicted, budgetMs, t0, r);
    r.produceMs = msSince(params_.clock, t0);
    plan_.clear();  // it points at tiles eviction may drop
    planPending_ = false;
    evict();
    r.cached = cache_.size();
    for (const auto& [key, t] : cache_) r.kept += t.lastUsed == clock_;
    // The plan of this frame is made when it is first read (plan(), displayedHeight, tileAt): by
    // the window, at once; a caller that draws nothing (a benchmark) does not pay for it.
    planVisible_ = visible;
    planPending_ = true;
    return r;
}

void TileLoop::refine(glm::dvec3 viewer, std::optional<glm::dvec3> predicted, bool background, FrameReport& r) {
    const auto t0 = params_.clock();
    std::optional<Deadline> deadline;
    if (params_.refineBudgetMs > 0.0) deadline = Deadline::after(t0, params_.refineBudgetMs, params_.clock);
    // With a predicted viewer, the leaves of both views: its quads exist (and can be made) now.
    const glm::dvec3 both[2] = {viewer, predicted.value_or(viewer)};
    const std::span<const glm::dvec3> viewers(both, predicted ? 2 : 1);
    guardBackground(viewers, r);
    const std::size_t begun = subdivisions_.begun();
    r.refineDeferred = !forest_->refine(viewers, params_.view, deadline, background ? &subdivisions_ : nullptr);
    r.backgroundSubdivisions = subdivisions_.begun() - begun;
    r.backgroundDropped += subdivisions_.settle();
    // A tile made before its quad's vector data arrived (a part read, editor/lazy_forest.h) is made again.
    const std::vector<QuadKey> arrived = forest_->takeArrived();
    staleBackground(arrived);
    for (const QuadKey& key : arrived) {
        const auto it = cache_.find(key);
        if (it != cache_.end() && !it->second.dirty) it->second.dirty = true, ++r.partsArrived;
    }
    r.refineMs = msSince(params_.clock, t0);
}

TileLoop::FrameLeaves TileLoop::collectLeaves(glm::dvec3 viewer, std::optional<glm::dvec3> predicted,
                                                    const QuadVisibility& visible, FrameReport& r) const {
    FrameLeaves out;
    auto isViewLeaf = [&](const Quad& q) {
        // With a predicted viewer the tree is refined for both: a quad is a leaf of the current
        // view when the current viewer alone would not subdivide it.
        if (q.isLeaf()) return !q.parent || Quadtree::wantsSubdivision(*q.parent, viewer, params_.view);
        return !Quadtree::wantsSubdivision(q, viewer, params_.view) &&
               (!q.parent || Quadtree::wantsSubdivision(*q.parent, viewer, params_.view));
    };
    forEachQuad(*forest_, [&](const Quad& q) {
        const bool viewLeaf = predicted ? isViewLeaf(q) : q.isLeaf();
        if (!viewLeaf && !(predicted && q.isLeaf())) return;
        if (visible && !visible(q)) {
            r.culled += viewLeaf;
            return;
        }
        if (viewLeaf) {
            out.view.push_back(&q);
            return;
        }
        const auto it = cache_.find(keyOf(q));
        (it == cache_.end() || it->second.dirty ? out.ahead : out.madeAhead).push_back(&q);
    });
    r.viewQuads = out.view.size();
    return out;
}

std::vector<const Quad*> TileLoop::keepShown(const CacheFit& fit) {
    std::vector<const Quad*> needed;
    for (const Quad* q : fit.shown) {
        const auto it = cache_.find(keyOf(*q));
        if (it != cache_.end()) it->second.lastUsed = clock_;
        // The ancestors' tiles stay too: they are what is drawn while a quad is made (the draw
        // plan). A tile already marked this frame was reached from a sibling: so were those above it.
        for (const Quad* a = forest_->parentOf(*q); a; a = forest_->parentOf(*a)) {
            const auto at = cache_.find(keyOf(*a));
            if (at == cache_.end()) continue;
            if (at->second.lastUsed == clock_) break;
            at->second.lastUsed = clock_;
        }
        if (it == cache_.end() || it->second.dirty) needed.push_back(q);
    }
    return needed;
}

void TileLoop::keepMadeAhead(std::vector<const Quad*> madeAhead, std::size_t kept, glm::dvec3 predicted) {
    // Tiles made ahead are kept until the view gets there, nearest to the predicted viewer first,
    // in the room the view leaves (its tiles, made this frame or not, and their ancestors').
    std::stable_sort(madeAhead.begin(), madeAhead.end(), nearestFirst(predicted));
    for (std::size_t i = 0; i < madeAhead.size() && kept < params_.cacheTiles; ++i, ++kept)
        cache_.at(keyOf(*madeAhead[i])).lastUsed = clock_;
}

std::size_t TileLoop::prefetch(std::vector<const Quad*> ahead, glm::dvec3 predicted, double budgetMs, Clock::time_point t0,
                                  FrameReport& r) {
    // Prefetch only with time left for the first quad ahead (it would otherwise always be made).
    // Prefetching fills the cache's room and no more (§9.1: "limited by the cache capacity"): the
    // budget less the tiles the LRU may not evict this frame (the view's, its ancestors', those
    // made ahead). Past it, the LRU would evict tiles made ahead before the view reached them.
    if (ahead.empty()) return 0;
    std::size_t kept = 0;
    for (const auto& [key, t] : cache_) kept += t.lastUsed == clock_;
    const std::size_t room = params_.cacheTiles > kept ? params_.cacheTiles - kept : 0;
    std::stable_sort(ahead.begin(), ahead.end(), nearestFirst(predicted));
    ahead.resize(std::min(ahead.size(), room));
    if (ahead.empty()) return 0;
    const std::size_t first = elementCount(*ahead.front());
    const double appearance = readsPyramid(*ahead.front()) ? estimates_[2].predict(0) : estimates_[0].predict(first);
    if (budgetMs > 0.0 && msSince(params_.clock, t0) + appearance + estimates_[1].predict(first) >= budgetMs) return 0;
    return produce(ahead, predicted, budgetMs <= 0.0 ? 0.0 : std::max(1e-9, budgetMs - msSince(params_.clock, t0)), params_.clock(), r);
}

void TileLoop::evict() {
    // A dirty tile nobody keeps this frame (a replaced leaf's, one between it and the quad standing
    // in for it, one below a replaced view leaf, a culled leaf's) is not made again now: the
    // window would draw what an edit changed, so it goes, and the plan takes an ancestor's.
    std::erase_if(cache_, [&](const auto& entry) { return entry.second.dirty && entry.second.lastUsed != clock_; });
    // LRU: drop the least recently used tiles outside the view beyond the budget.
    if (cache_.size() <= params_.cacheTiles) return;
    std::vector<std::pair<std::uint64_t, QuadKey>> old;
    for (const auto& [key, t] : cache_)
        if (t.lastUsed < clock_) old.push_back({t.lastUsed, key});
    std::sort(old.begin(), old.end());
    for (std::size_t i = 0; i < old.size() && cache_.size() > params_.cacheTiles; ++i) cache_.erase(old[i].second);
}

const CachedTile* TileLoop::tile(const QuadKey& key) const {
    const auto it = cache_.find(key);
    return it == cache_.end() ? nullptr : &it->second;
}

const DrawPlan& TileLoop::plan() const {
    if (planPending_) {
        plan_ = makeDrawPlan(*forest_, [&](const QuadKey& key) { return tile(key); }, planVisible_, params_.skirt);
        planPending_ = false;
    }
    return plan_;
}

std::pair<const Quad*, const CachedTile*> TileLoop::tileAt(Vec2 p) const {
    const DrawItem* item = plan().itemAt(p);
    if (!item || !item->tile) return {nullptr, nullptr};
    return {findQuad(*forest_, item->tileKey), item->tile};
}

double TileLoop::displayedHeight(Vec2 p) const {
    const DrawItem* item = plan().itemAt(p);
    if (!item || !item->tile || !item->tile->elevation.bounds.contains(p)) return dem_.sample(p);
    const ElevationTile& e = item->tile->elevation;
    const Vec2 g = (p - e.bounds.min) / e.delta;
    const int i = std::clamp(int(std::floor(g.x)), 0, e.resolution - 1), j = std::clamp(int(std::floor(g.y)), 0, e.resolution - 1);
    const double fx = g.x - i, fy = g.y - j;
    auto z = [&](int a, int b) { return double(e.zm[e.index(a, b)]); };
    return (1 - fy) * ((1 - fx) * z(i, j) + fx * z(i + 1, j)) + fy * ((1 - fx) * z(i, j + 1) + fx * z(i + 1, j + 1));
}

}  // namespace lacet
