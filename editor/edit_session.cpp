#include "editor/edit_session.h"

#include <algorithm>
#include <set>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace lacet {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

const Quad* findQuad(const Quad& root, const QuadKey& key) {
    const auto [level, tx, ty] = key;
    const Quad* q = &root;
    while (q->level < level) {
        if (q->isLeaf()) return nullptr;
        const int shift = level - q->level - 1;
        q = q->children[std::size_t(int((tx >> shift) & 1u) | int(((ty >> shift) & 1u) << 1))].get();
    }
    return q->tx == tx && q->ty == ty ? q : nullptr;
}

double viewDistance(const Quad& q, glm::dvec3 viewer) {
    const Vec2 p(viewer.x, viewer.y);
    const Vec2 d = glm::max(glm::max(q.bounds.min - p, p - q.bounds.max), Vec2(0.0));
    return std::sqrt(glm::dot(d, d) + viewer.z * viewer.z);
}

}  // namespace

QuadKey keyOf(const Quad& q) { return {q.level, q.tx, q.ty}; }

EditSession::EditSession(SceneDocument document, SessionParams params) : doc_(std::move(document)), params_(params) {
    if (!doc_.dem) throw std::invalid_argument("EditSession: the document has no DEM");
    heights_ = std::make_unique<DemHeightField>(*doc_.dem);
    quadtree_ = std::make_unique<Quadtree>(doc_.scene, params_.refine);
    data_ = std::make_unique<CurveDataCache>(*quadtree_, *heights_);
}

CommandReport EditSession::afterEdit(const Changeset& cs, double applyMs) {
    CommandReport r;
    r.applyMs = applyMs;
    const std::vector<ElementRef> dropped = data_->invalidate(cs);
    const auto t0 = Clock::now();
    const UpdateStats st = quadtree_->update(cs);
    r.updateMs = msSince(t0);
    r.changedQuads = st.changedQuads.size();
    std::set<QuadKey> changed;
    for (const Quad* q : st.changedQuads) changed.insert(keyOf(*q));
    for (auto& [key, tile] : cache_) {
        if (tile.dirty) continue;
        const Quad* q = findQuad(quadtree_->root(), key);
        // A tile whose quad is not in the tree now cannot be checked: it is redone if needed.
        bool stale = !q || changed.count(key) > 0;
        for (std::size_t i = 0; !stale && i < dropped.size(); ++i)
            stale = q->layers.size() > dropped[i].layer && q->layers[dropped[i].layer].curves.count(dropped[i].id) > 0;
        if (stale) {
            tile.dirty = true;
            ++r.dirtyTiles;
        }
    }
    return r;
}

CommandReport EditSession::execute(const Command& command) {
    const auto t0 = Clock::now();
    Applied a = lacet::apply(doc_.scene, command);
    const double ms = msSince(t0);
    done_.push_back({command, std::move(a)});
    undone_.clear();
    return afterEdit(done_.back().second.changeset, ms);
}

bool EditSession::undo(CommandReport* report) {
    if (done_.empty()) return false;
    const auto t0 = Clock::now();
    const Changeset cs = lacet::undo(doc_.scene, done_.back().second);
    const double ms = msSince(t0);
    undone_.push_back(std::move(done_.back().first));
    done_.pop_back();
    const CommandReport r = afterEdit(cs, ms);
    if (report) *report = r;
    return true;
}

bool EditSession::redo(CommandReport* report) {
    if (undone_.empty()) return false;
    const auto t0 = Clock::now();
    Applied a = lacet::apply(doc_.scene, undone_.back());
    const double ms = msSince(t0);
    done_.push_back({std::move(undone_.back()), std::move(a)});
    undone_.pop_back();
    const CommandReport r = afterEdit(done_.back().second.changeset, ms);
    if (report) *report = r;
    return true;
}

FrameReport EditSession::frame(glm::dvec3 viewer, double budgetMs) {
    FrameReport r;
    auto t0 = Clock::now();
    quadtree_->refineForViewer(viewer, params_.K, params_.maxLevel);
    r.refineMs = msSince(t0);
    ++clock_;
    std::vector<const Quad*> needed;
    quadtree_->forEachQuad([&](const Quad& q) {
        if (!q.isLeaf()) return;
        ++r.viewQuads;
        const auto it = cache_.find(keyOf(q));
        if (it != cache_.end()) it->second.lastUsed = clock_;
        if (it == cache_.end() || it->second.dirty) needed.push_back(&q);
    });
    std::stable_sort(needed.begin(), needed.end(),
                     [&](const Quad* a, const Quad* b) { return viewDistance(*a, viewer) < viewDistance(*b, viewer); });
    t0 = Clock::now();
    const std::size_t batch = 8;
    std::size_t next = 0;
    while (next < needed.size()) {
        const std::size_t end = std::min(needed.size(), next + batch);
        std::vector<CachedTile> made(end - next);
        tbb::parallel_for(next, end, [&](std::size_t i) {
            made[i - next].appearance = produceAppearance(*needed[i], *quadtree_, *data_, *doc_.dem, params_.appearance);
            made[i - next].elevation = produceElevation(*needed[i], *quadtree_, *data_, *doc_.dem, params_.elevation);
        });
        for (std::size_t i = next; i < end; ++i) {
            CachedTile& t = cache_[keyOf(*needed[i])];
            t = std::move(made[i - next]);
            t.lastUsed = clock_;
        }
        r.produced += end - next;
        next = end;
        if (budgetMs > 0.0 && msSince(t0) >= budgetMs) break;
    }
    r.produceMs = msSince(t0);
    r.pending = needed.size() - next;
    // LRU: drop the least recently used tiles outside the view beyond the budget.
    if (cache_.size() > params_.cacheTiles) {
        std::vector<std::pair<std::uint64_t, QuadKey>> old;
        for (const auto& [key, t] : cache_)
            if (t.lastUsed < clock_) old.push_back({t.lastUsed, key});
        std::sort(old.begin(), old.end());
        for (std::size_t i = 0; i < old.size() && cache_.size() > params_.cacheTiles; ++i) cache_.erase(old[i].second);
    }
    r.cached = cache_.size();
    return r;
}

const CachedTile* EditSession::tile(const QuadKey& key) const {
    const auto it = cache_.find(key);
    return it == cache_.end() ? nullptr : &it->second;
}

}  // namespace lacet
