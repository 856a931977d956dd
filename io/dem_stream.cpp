#include "io/dem_stream.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

namespace lacet {
namespace {

// Samples of margin around a window, beyond the box: the Catmull-Rom stencil reads one sample
// before and two after the cell holding a point, plus one for rounding at the border.
constexpr int kWindowMargin = 3;

using Clock = std::chrono::steady_clock;

DemBlockKey parentOf(const DemBlockKey& k) {
    const auto [l, c, r] = k;
    return {l - 1, c / 2, r / 2};
}

}  // namespace

DemNeed quadDemNeed(const Box& quad, double samplesPerQuad) {
    if (!(samplesPerQuad > 0.0) || !std::isfinite(samplesPerQuad))
        throw std::invalid_argument("quadDemNeed(): samplesPerQuad must be > 0, got " + std::to_string(samplesPerQuad));
    const double size = quad.size().x;
    return {Box{quad.min - size / 4.0, quad.max + size / 4.0}, size / samplesPerQuad};
}

DemStream::DemStream(std::shared_ptr<const DemLodFile> file, DemStreamParams params)
    : file_(std::move(file)), params_(params), heights_(*this, 0) {
    if (!file_) throw std::invalid_argument("DemStream: no DEM file");
    if (!std::isfinite(params.profileSpacing) || params.profileSpacing <= 0.0)
        throw std::invalid_argument("DemStream: profileSpacing must be > 0 metres");
    heights_ = ProfileHeights(*this, layout().levelFor(params.profileSpacing));
    setBudget(params.budgetMiB);
    const auto t0 = Clock::now();
    std::vector<float> root = file_->readBlock(0, 0, 0, {});
    stats_.loadMs += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    ++stats_.loaded;
    blocks_[{0, 0, 0}] = Block{std::make_shared<const std::vector<float>>(std::move(root)), 0, 0, 0.0};
    if (params_.background) loader_ = std::thread([this] { loaderLoop(); });
}

DemStream::~DemStream() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    if (loader_.joinable()) loader_.join();
}

void DemStream::setBudget(double budgetMiB) {
    if (!std::isfinite(budgetMiB) || budgetMiB <= 0.0)
        throw std::invalid_argument("DemStream: the budget must be a positive number of MiB, got " + std::to_string(budgetMiB));
    const double blockBytes = double(layout().blockSide) * double(layout().blockSide) * sizeof(float);
    std::lock_guard lock(mutex_);
    params_.budgetMiB = budgetMiB;
    maxBlocks_ = std::max<std::size_t>(1, std::size_t(budgetMiB * 1048576.0 / blockBytes));
    makeRoom(0, 0.0, true);
    refused_.clear();
}

bool DemStream::wants(const DemBlockKey& key) const {
    if (failed_.count(key) > 0) return false;
    const auto it = refused_.find(key);
    return it == refused_.end() || it->second + kRetryRefusedFrames <= frame_;
}

void DemStream::touch(Block& b, double priority) {
    if (b.lastUsed != frame_) {
        usedChanged_ = usedChanged_ || b.lastUsed + 1 != frame_;  // not used in the last frame
        ++usedThisFrame_;
        b.priority = priority;
    } else {
        b.priority = std::min(b.priority, priority);
    }
    b.lastUsed = frame_;
    b.tick = ++tick_;
}

void DemStream::beginFrame() {
    std::lock_guard lock(mutex_);
    // The blocks in use changed (some new, or some no longer used): what the budget refused may
    // fit now.
    if (usedChanged_ || usedThisFrame_ != usedLastFrame_) refused_.clear();
    usedChanged_ = false;
    usedLastFrame_ = usedThisFrame_;
    usedThisFrame_ = 0;
    ++frame_;
    requests_.clear();
}

std::array<int, 4> DemStream::range(const Box& box, int level) const {
    const DemLodLayout& L = layout();
    const double cell = L.levelCell(level);
    const int w = L.levelWidth(level), h = L.levelHeight(level);
    auto clampRange = [](double lo, double hi, int n) {
        // Beyond the grid a Dem continues its border (it clamps the point to its extent): the
        // window there is the border's samples, with the stencil's margin inside.
        lo = std::clamp(lo, -0.5, double(n) - 0.5);
        hi = std::clamp(hi, -0.5, double(n) - 0.5);
        const double a = std::clamp(std::floor(lo) - kWindowMargin, 0.0, double(n - 1));
        const double b = std::clamp(std::ceil(hi) + kWindowMargin + 1, a + 1.0, double(n));
        return std::pair<int, int>(int(a), int(b));
    };
    const auto [k0, k1] = clampRange((box.min.x - L.origin.x) / cell, (box.max.x - L.origin.x) / cell, w);
    const auto [r0, r1] = clampRange((L.origin.y - box.max.y) / cell, (L.origin.y - box.min.y) / cell, h);
    return {k0, k1, r0, r1};
}

Box DemStream::blockBox(const DemBlockKey& key) const {
    const auto [l, c, r] = key;
    const DemLodLayout& L = layout();
    const double cell = L.levelCell(l);
    const int b = L.blockSide;
    const int k1 = std::min((c + 1) * b, L.levelWidth(l)), r1 = std::min((r + 1) * b, L.levelHeight(l));
    return Box{{L.origin.x + (c * b - 0.5) * cell, L.origin.y - (r1 - 0.5) * cell},
               {L.origin.x + (k1 - 0.5) * cell, L.origin.y - (r * b - 0.5) * cell}};
}

Dem DemStream::cut(int level, const std::array<int, 4>& rg, const std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>>& blocks) const {
    const DemLodLayout& L = layout();
    const auto [k0, k1, r0, r1] = rg;
    const int w = k1 - k0, h = r1 - r0, b = L.blockSide;
    std::vector<float> heights(std::size_t(w) * std::size_t(h));
    for (int j = 0; j < h; ++j) {
        const int rr = r1 - 1 - j;  // Dem rows grow with y, the tree's rows from the top
        const std::vector<float>* block = nullptr;
        int blockCol = -1;
        for (int i = 0; i < w; ++i) {
            const int k = k0 + i;
            if (k / b != blockCol) {
                blockCol = k / b;
                block = blocks.at({level, blockCol, rr / b}).get();
            }
            heights[std::size_t(j) * std::size_t(w) + std::size_t(i)] = (*block)[std::size_t(rr % b) * std::size_t(b) + std::size_t(k % b)];
        }
    }
    const double cell = L.levelCell(level);
    const Box extent{{L.origin.x + (k0 - 0.5) * cell, L.origin.y - (r1 - 0.5) * cell},
                     {L.origin.x + (k1 - 0.5) * cell, L.origin.y - (r0 - 0.5) * cell}};
    return Dem(extent, w, h, std::move(heights));
}

std::vector<DemBlockKey> DemStream::blocksOf(int level, const std::array<int, 4>& rg) const {
    const int b = layout().blockSide;
    const auto [k0, k1, r0, r1] = rg;
    std::vector<DemBlockKey> keys;
    for (int r = r0 / b; r <= (r1 - 1) / b; ++r)
        for (int c = k0 / b; c <= (k1 - 1) / b; ++c) keys.emplace_back(level, c, r);
    return keys;
}

void DemStream::enqueue(const DemBlockKey& key, double priority) {
    auto [q, fresh] = requests_.try_emplace(key, priority);
    if (!fresh) q->second = std::min(q->second, priority);
}

int DemStream::availableLevel(const Box& box, double spacing) const {
    const int wanted = layout().levelFor(spacing);
    std::lock_guard lock(mutex_);
    for (int level = wanted; level > 0; --level) {
        const std::vector<DemBlockKey> keys = blocksOf(level, range(box, level));
        if (std::all_of(keys.begin(), keys.end(), [&](const DemBlockKey& k) { return blocks_.count(k) > 0; })) return level;
    }
    return 0;
}

DemWindow DemStream::window(const Box& box, double spacing, double priority) {
    const int wanted = layout().levelFor(spacing);
    std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>> use;
    int level = wanted;
    std::array<int, 4> rg{};
    {
        std::lock_guard lock(mutex_);
        for (;; --level) {
            rg = range(box, level);
            use.clear();
            bool all = true;
            for (const DemBlockKey& key : blocksOf(level, rg)) {
                const auto it = blocks_.find(key);
                if (it != blocks_.end()) {
                    use[key] = it->second.samples;
                    continue;
                }
                all = false;
                if (level == wanted && wants(key)) enqueue(key, priority);
            }
            if (all || level == 0) break;
        }
        for (const auto& [key, samples] : use) touch(blocks_.at(key), priority);
        ++stats_.windows;
        ++stats_.windowsAtLevel[std::size_t(level)];
        stats_.fallbacks += level < wanted;
    }
    if (level < wanted) wake_.notify_one();
    DemWindow w;
    w.dem = std::make_shared<const Dem>(cut(level, rg, use));
    w.level = level;
    w.wanted = wanted;
    return w;
}

DemWindow DemStream::windowNow(const Box& box, double spacing) {
    const int wanted = layout().levelFor(spacing);
    for (int level = wanted;; --level) {
        const std::array<int, 4> rg = range(box, level);
        std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>> use;
        try {
            use = readNow(level, rg, kBatchPriority);
        } catch (const std::exception&) {
            if (level == 0) throw;
            std::lock_guard lock(mutex_);
            ++stats_.failed;
            continue;
        }
        {
            std::lock_guard lock(mutex_);
            ++stats_.windows;
            ++stats_.windowsAtLevel[std::size_t(level)];
            stats_.fallbacks += level < wanted;
        }
        DemWindow w;
        w.dem = std::make_shared<const Dem>(cut(level, rg, use));
        w.level = level;
        w.wanted = wanted;
        return w;
    }
}

void DemStream::request(const Box& box, double spacing, double priority) {
    const int wanted = layout().levelFor(spacing);
    const std::vector<DemBlockKey> keys = blocksOf(wanted, range(box, wanted));
    bool any = false;
    {
        std::lock_guard lock(mutex_);
        for (const DemBlockKey& key : keys) {
            if (blocks_.count(key) > 0 || !wants(key)) continue;
            enqueue(key, priority);
            any = true;
        }
    }
    if (any) wake_.notify_one();
}

std::size_t DemStream::profileFloor() const { return std::size_t(layout().levels) + kProfileSpare; }

bool DemStream::makeRoom(std::size_t count, double priority, bool force, std::size_t capacity) {
    capacity = std::max(capacity, maxBlocks_);
    if (blocks_.size() + count <= capacity) return true;
    const std::size_t excess = blocks_.size() + count - capacity;
    // The victims, least useful first: the blocks this frame has not used, longest unused first,
    // then those it used, least important first. Chosen before any is dropped, so that a refusal
    // leaves the cache as it was.
    std::vector<std::map<DemBlockKey, Block>::iterator> order;
    order.reserve(blocks_.size());
    for (auto it = blocks_.begin(); it != blocks_.end(); ++it)
        if (std::get<0>(it->first) != 0) order.push_back(it);  // the root stays
    if (order.size() < excess) {
        if (!force) return false;
    }
    const std::size_t take = std::min(excess, order.size());
    auto lessUseful = [&](const auto& a, const auto& b) {
        const bool usedA = a->second.lastUsed == frame_, usedB = b->second.lastUsed == frame_;
        if (usedA != usedB) return !usedA;
        if (usedA && a->second.priority != b->second.priority) return a->second.priority > b->second.priority;
        return a->second.tick < b->second.tick;
    };
    std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(take), order.end(), lessUseful);
    if (!force)
        for (std::size_t i = 0; i < take; ++i)
            if (order[i]->second.lastUsed == frame_ && order[i]->second.priority <= priority) return false;
    for (std::size_t i = 0; i < take; ++i) blocks_.erase(order[i]);
    stats_.evicted += take;
    return take == excess;
}

std::shared_ptr<const std::vector<float>> DemStream::fetch(const DemBlockKey& key, double priority, bool sync) {
    // The missing chain: the block and its ancestors up to one held (the root always is).
    std::vector<DemBlockKey> chain;
    std::shared_ptr<const std::vector<float>> parent;
    {
        std::lock_guard lock(mutex_);
        for (DemBlockKey k = key;; k = parentOf(k)) {
            if (failed_.count(k) > 0) throw std::runtime_error("DEM block not readable");
            const auto it = blocks_.find(k);
            if (it != blocks_.end()) {
                parent = it->second.samples;
                break;
            }
            chain.push_back(k);
        }
        if (chain.empty()) return parent;
        // A chain that cannot fit beside the root is refused at once (it would empty the cache).
        if (!sync && (chain.size() >= maxBlocks_ || !makeRoom(chain.size(), priority, false))) {
            ++stats_.refused;
            refused_[key] = frame_;
            return nullptr;
        }
    }
    const auto t0 = Clock::now();
    std::vector<std::pair<DemBlockKey, std::shared_ptr<const std::vector<float>>>> read;
    std::optional<DemBlockKey> failed;
    for (auto k = chain.rbegin(); k != chain.rend() && !failed; ++k) {
        const auto [l, c, r] = *k;
        try {
            parent = std::make_shared<const std::vector<float>>(file_->readBlock(l, c, r, *parent));
            read.emplace_back(*k, parent);
        } catch (const std::exception&) {
            failed = *k;  // the ancestors read before it are kept: windows there are cut from them
        }
    }
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    {
        std::lock_guard lock(mutex_);
        stats_.loadMs += ms;
        stats_.loaded += read.size();
        if (sync) stats_.loadedSync += read.size();
        // The z-profiles' reads keep a chain and a few blocks more even under a smaller budget (a
        // profile walks block after block: it would read each chain again for every sample).
        const std::size_t capacity = sync ? profileFloor() : maxBlocks_;
        makeRoom(read.size(), priority, sync, capacity);
        for (auto& [k, samples] : read) {
            Block& b = blocks_.try_emplace(k, Block{samples, 0, 0, priority}).first->second;
            touch(b, priority);
        }
        // Keep within the budget even when a synchronous read had to exceed it for a moment.
        makeRoom(0, priority, true, capacity);
        if (failed) failed_.insert(*failed);
    }
    if (failed) throw std::runtime_error("DEM block not readable");
    return parent;
}

bool DemStream::loadOne() {
    DemBlockKey key;
    double priority = 0.0;
    {
        std::lock_guard lock(mutex_);
        if (requests_.empty()) return false;
        auto best = std::min_element(requests_.begin(), requests_.end(),
                                     [](const auto& a, const auto& b) { return a.second < b.second; });
        key = best->first;
        priority = best->second;
        requests_.erase(best);
        ++inFlight_;  // even when held already: the one exit below tells load() it is done
    }
    bool failed = false;
    try {
        fetch(key, priority, false);  // returns at once when the block is held
    } catch (const std::exception&) {
        failed = true;
    }
    std::lock_guard lock(mutex_);
    if (failed) {
        ++stats_.failed;
        failed_.insert(key);  // not asked again: its windows stay coarser
    }
    --inFlight_;
    idle_.notify_all();
    return true;
}

void DemStream::loaderLoop() {
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || !requests_.empty(); });
            if (stop_) return;
        }
        loadOne();
    }
}

std::size_t DemStream::load(std::size_t count) {
    if (params_.background) {
        std::unique_lock lock(mutex_);
        idle_.wait(lock, [&] { return stop_ || (requests_.empty() && inFlight_ == 0); });
        return 0;
    }
    std::size_t n = 0;
    while (n < count && loadOne()) ++n;
    return n;
}

DemStreamStats DemStream::stats() const {
    std::lock_guard lock(mutex_);
    DemStreamStats s = stats_;
    s.held = blocks_.size();
    const double blockBytes = double(layout().blockSide) * double(layout().blockSide) * sizeof(float);
    s.heldMiB = double(s.held) * blockBytes / 1048576.0;
    s.pending = requests_.size() + inFlight_;
    return s;
}

double DemStream::ProfileHeights::height(Vec2 p) const {
    if (std::isnan(p.x) || std::isnan(p.y)) return std::numeric_limits<double>::quiet_NaN();
    // A block that cannot be read (a corrupt tile) leaves these heights to the next coarser level,
    // the same for every call: the profiles stay a function of the file.
    for (int level = level_;; --level) {
        try {
            return s_->sampleLevel(level, p);
        } catch (const std::exception&) {
            if (level == 0) throw;
            std::lock_guard lock(s_->mutex_);
            ++s_->stats_.failed;
        }
    }
}

std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>> DemStream::readNow(int level, const std::array<int, 4>& rg,
                                                                               double priority) {
    std::map<DemBlockKey, std::shared_ptr<const std::vector<float>>> use;
    for (const DemBlockKey& key : blocksOf(level, rg)) {
        std::shared_ptr<const std::vector<float>> samples;
        {
            std::lock_guard lock(mutex_);
            if (failed_.count(key) > 0) throw std::runtime_error("DEM block not readable");
            const auto it = blocks_.find(key);
            if (it != blocks_.end()) {
                // A block this frame used already keeps its importance.
                touch(it->second, it->second.lastUsed == frame_ ? it->second.priority : priority);
                samples = it->second.samples;
            }
        }
        // Held by `use` until the caller is done with it, whatever the cache drops meanwhile.
        if (!samples) samples = fetch(key, priority, true);
        use[key] = std::move(samples);
    }
    return use;
}

double DemStream::sampleLevel(int level, Vec2 p) {
    const auto rg = range(Box{p, p}, level);
    return cut(level, rg, readNow(level, rg, kProfilePriority)).sample(p);
}

StreamedDem::StreamedDem(std::shared_ptr<const DemLodFile> file, double budgetMiB)
    : stream_(std::move(file), DemStreamParams{.budgetMiB = budgetMiB, .background = false}) {}

std::shared_ptr<const Dem> StreamedDem::quadDem(const Quad& q) const {
    const DemNeed n = quadDemNeed(q.bounds);
    return stream_.windowNow(n.box, n.spacing).dem;
}

namespace {

// Flat ground at 0 m over a scene without a DEM, owned by its source.
class FlatDem final : public DemSource {
public:
    explicit FlatDem(const Box& extent) : dem_(extent, 2, 2, std::vector<float>(4, 0.0f)), inner_(dem_) {}
    const HeightField& heights() const override { return inner_.heights(); }
    std::shared_ptr<const Dem> quadDem(const Quad& q) const override { return inner_.quadDem(q); }

private:
    Dem dem_;
    InMemoryDem inner_;
};

}  // namespace

std::unique_ptr<DemSource> batchDemSource(const SceneDocument& doc, double budgetMiB) {
    if (doc.demLod) return std::make_unique<StreamedDem>(doc.demLod, budgetMiB);
    if (doc.dem) return std::make_unique<InMemoryDem>(*doc.dem);
    return std::make_unique<FlatDem>(doc.scene.extent);
}

}  // namespace lacet
