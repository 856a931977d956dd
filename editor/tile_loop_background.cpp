// The live loop's background tiles (editor/tile_loop.h; SessionParams::backgroundMs, issue 24:
// no slow frame): slow quads' tiles made on idle threads while frames go on.
#include <algorithm>
#include <chrono>
#include <thread>

#include "editor/background_work.h"
#include "editor/tile_loop.h"

namespace lacet {

bool TileLoop::slow(const Quad& q, bool fromPyramid) const {
    if (!q.parent) return false;  // the root: no tile stands in for it
    const std::size_t x = elementCount(q);
    const ProductionEstimate& a = fromPyramid ? estimates_[2] : estimates_[0];
    const std::size_t ax = fromPyramid ? 0 : x;
    return a.mayExceed(ax, params_.backgroundMs) || estimates_[1].mayExceed(x, params_.backgroundMs);
}

void TileLoop::startBackground(const Quad& q, bool fromPyramid, glm::dvec3 viewer, FrameReport& r) {
    Background b;
    b.key = keyOf(q);
    b.quad = &q;
    b.cancel = std::make_unique<CancelFlag>(false);
    // The DEM windows are cut now (the stream's requests follow the frames).
    std::shared_ptr<const Dem> ground, objectGround;
    if (stream_) {
        b.window = demWindow(q, viewer);
        const DemWindow w = objectWindow(q, viewer, b.window);
        b.objectLevel = w.level;
        ground = b.window.dem;
        objectGround = w.dem;
    }
    // What the thread reads besides the quad: copies of the session's knobs (they may change
    // between frames), and the quad's tree and curve data found now (the forest's maps change).
    struct Inputs {
        AppearanceParams appearance;
        ElevationParams elevation;
        ObjectParams objects;
        WorkClock clock;  // the thread's CPU time: its waits at idle priority are not its tiles' cost
        int border = 0;
        std::shared_ptr<PyramidReader> pyramid;
        const Quadtree* tree = nullptr;
        const CurveDataCache* data = nullptr;
        std::shared_ptr<const Dem> ground, objectGround;  // null: the DEM in memory
    };
    auto in = std::make_shared<Inputs>(Inputs{params_.appearance, params_.elevation, params_.objects, threadCpuClock(),
                                              params_.refine.appearanceBorder, pyramid_, &forest_->treeOf(q), &forest_->dataOf(q),
                                              std::move(ground), std::move(objectGround)});
    const Source preset = !fromPyramid && pyramid_ && pyramid_->serves(q.level) ? kTouched : kLive;
    const CancelFlag* cancel = b.cancel.get();
    if (!workers_) workers_ = std::make_unique<BackgroundWorkers>(backgroundLanes());
    b.result = workers_->submit([this, in, quad = &q, fromPyramid, preset, cancel] {
        const JobParams p{in->appearance, in->elevation, in->objects, in->clock, in->border, in->pyramid.get()};
        const Dem& dem = in->ground ? *in->ground : dem_;
        const Dem& objects = in->objectGround ? *in->objectGround : dem;
        const auto objectDem = [&]() -> const Dem& { return objects; };
        Background::Made m;
        const Source s = runJob(true, *quad, *in->tree, *in->data, fromPyramid, dem, objectDem, p, m.tile, cancel);
        m.source = s != kLive ? s : preset;
        runJob(false, *quad, *in->tree, *in->data, false, dem, objectDem, p, m.tile, cancel);
        return m;
    });
    background_.push_back(std::move(b));
    ++r.backgroundStarted;
}

void TileLoop::takeBackground(FrameReport& r) {
    for (auto it = background_.begin(); it != background_.end();) {
        if (it->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            ++it;
            continue;
        }
        Background b = std::move(*it);
        it = background_.erase(it);
        Background::Made m = b.result.get();  // a producer's error surfaces here, as in a frame's own production
        countPyramidUse(m.source);
        if (b.stale) {
            ++r.backgroundDropped;
            continue;
        }
        store(b.key, std::move(m.tile), m.source, stream_ ? &b.window : nullptr, b.objectLevel, r);
        ++r.backgroundTaken;
    }
}

void TileLoop::waitForBackground() {
    for (Background& b : background_) b.result.wait();
    subdivisions_.wait();
}

std::size_t TileLoop::quiesce() { return subdivisions_.quiesce() + dropBackgroundTiles(); }

std::size_t TileLoop::dropBackgroundTiles() {
    for (Background& b : background_) b.cancel->store(true);  // all at once, then wait
    for (Background& b : background_) stopJob(*b.cancel, b.result);
    const std::size_t n = background_.size();
    background_.clear();
    return n;
}

void TileLoop::guardBackground(std::span<const glm::dvec3> viewers, FrameReport& r) {
    std::erase_if(background_, [&](Background& b) {
        if (forest_->keeps(*b.quad, viewers, params_.view)) return false;
        stopJob(*b.cancel, b.result);
        ++r.backgroundDropped;
        return true;
    });
    if (const Quad* leaf = subdivisions_.leaf(); leaf && !forest_->keeps(*leaf, viewers, params_.view))
        r.backgroundDropped += subdivisions_.quiesce();
}

void TileLoop::staleBackground(const std::vector<QuadKey>& arrived) {
    for (Background& b : background_)
        if (std::find(arrived.begin(), arrived.end(), b.key) != arrived.end()) b.stale = true;
}

std::size_t TileLoop::backgroundLanes() const {
    return params_.backgroundThreads > 0 ? params_.backgroundThreads : std::max(1u, std::thread::hardware_concurrency());
}

}  // namespace lacet
