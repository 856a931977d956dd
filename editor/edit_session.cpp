#include "editor/edit_session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/edits.h"
#include "model/work_clock.h"

namespace lacet {

EditSession::EditSession(SceneDocument document, SessionParams params) : doc_(std::move(document)), params_(params) {
    if (!doc_.dem) throw std::invalid_argument("EditSession: the document has no DEM");
    params_.view.validate();
    params_.objects.deckThickness = params_.graph.deckThickness;
    params_.objects.validate();
    if (doc_.demLod) {
        demStream_ = std::make_unique<DemStream>(doc_.demLod, params_.demStream);
        heights_ = &demStream_->heights();
    } else {
        demHeights_ = std::make_unique<DemHeightField>(*doc_.dem);
        heights_ = demHeights_.get();
    }
    loop_ = std::make_unique<TileLoop>(params_, doc_.scene, *doc_.dem, demStream_.get());
    buildTree();
}

EditSession::EditSession(const std::string& path, LazyParams lazy, SessionParams params)
    : EditSession(LazyForest::readTop(path, lazy, params.refine), lazy, params) {}

EditSession::EditSession(LazyTop top, LazyParams lazy, SessionParams params) : EditSession(std::move(top.doc), params) {
    lazyPath_ = top.path;
    storedChecksum_ = top.stats.checksum;
    topReach_ = top.stats.reach;
    lazy_ = lazy;
    lazyEdits_ = std::make_unique<LazyEdits>(lazyPath_, params_.refine);
    forest_ = std::make_unique<LazyForest>(lazyPath_, storedChecksum_, *quadtree_, *data_, *heights_, params_, *lazy_);
    loop_->setForest(*forest_);
}

void EditSession::buildTree() {
    forest_.reset();
    data_.reset();
    quadtree_.reset();
    graphStep_ = std::make_unique<GraphStep>(doc_.scene, params_.graph);
    quadtree_ = std::make_unique<Quadtree>(doc_.scene, params_.refine, graphStep_.get());
    data_ = std::make_unique<CurveDataCache>(*quadtree_, *heights_, params_.profiles);
    loop_->setTree(*quadtree_, *data_);
    if (lazy_) {
        forest_ = std::make_unique<LazyForest>(lazyPath_, storedChecksum_, *quadtree_, *data_, *heights_, params_, *lazy_);
        if (lazyEdits_) forest_->setOverlay(lazyEdits_->overlay(), lazyEdits_->version());
        loop_->setForest(*forest_);
    }
}

SceneEditsSaved EditSession::saveEdits() {
    if (!lazyEdits_) throw std::logic_error("EditSession::saveEdits: the session holds a whole document: save it with saveScene");
    loop_->quiesce();
    forest_->waitForReads();  // read with the file's stored checksum before the save: taken as they are
    const SceneEditsSaved saved = saveSceneEdits(lazyPath_, *lazyEdits_->overlay(), storedChecksum_);
    storedChecksum_ = saved.checksum;
    forest_->setStoredChecksum(saved.checksum);
    lazyEdits_->markSaved();
    forest_->setOverlay(lazyEdits_->overlay(), lazyEdits_->version());
    return saved;
}

void EditSession::readTopAgain() {
    LazyTop top = LazyForest::readTop(lazyPath_, *lazy_, params_.refine, /*dem=*/false, lazyEdits_->overlay().get());
    if (top.stats.checksum != storedChecksum_)  // as a part's read refuses it
        throw SceneFileError(lazyPath_ + ": the file changed since it was opened (its stored checksum is " + top.stats.checksum + ", was " +
                             storedChecksum_ + "): open it again");
    doc_.scene = std::move(top.doc.scene);
    doc_.attributes = std::move(top.doc.attributes);
    auto step = std::make_unique<GraphStep>(doc_.scene, params_.graph);
    auto tree = std::make_unique<Quadtree>(doc_.scene, params_.refine, step.get());
    auto data = std::make_unique<CurveDataCache>(*tree, *heights_, params_.profiles);
    forest_->setTop(*tree, *data);
    data_ = std::move(data);  // the old curve data goes before its tree, the tree before its graph step
    quadtree_ = std::move(tree);
    graphStep_ = std::move(step);
}

ElementId EditSession::nextId(LayerId layer, ElementKind kind) const {
    if (lazyEdits_) return lazyEdits_->nextId(layer, kind);
    const Layer& l = doc_.scene.layers.at(layer);
    return ElementId(kind == ElementKind::Node ? l.nodes.size() : kind == ElementKind::Curve ? l.curves.size() : l.areas.size());
}

bool EditSession::topTouched(const LazyStep& step) const {
    if (!lazy_->topElevationOnly) return true;  // the top holds the whole scene
    if (LazyForest::holdsAny(doc_, step.refs)) return true;
    const double minWidth = LazyForest::topMinCurveWidth(doc_.scene.extent, *lazy_, params_.refine);
    const SceneOverlay& overlay = *lazyEdits_->overlay();
    for (const ElementRef& r : step.refs) {
        const LayerKind kind = doc_.scene.layers.at(r.layer).kind;
        // A river anywhere may be one a road of the top bridges, or upstream of one of its rivers.
        if (kind == LayerKind::Rivers || kind == LayerKind::Lakes) return true;
        const OverlayElement* e = overlay.find(r);
        const Curve* c = e ? std::get_if<Curve>(&e->value) : nullptr;
        // A curve the top would read now (one it read before it holds).
        if (c && c->alive && kind == LayerKind::Roads && ((c->flags & kBridge) || double(c->w) >= minWidth)) return true;
    }
    return false;
}

CommandReport EditSession::afterLazyStep(const LazyStep& step, double applyMs) {
    CommandReport r;
    r.applyMs = applyMs;
    const auto t0 = std::chrono::steady_clock::now();
    forest_->setOverlay(lazyEdits_->overlay(), lazyEdits_->version());
    // How far beyond a part's reach what changed may now reach: its footprint and ring.
    double margin = 0.0;
    for (const ElementRef& ref : step.refs)
        if (const OverlayElement* e = lazyEdits_->overlay()->find(ref)) {
            if (const Curve* c = std::get_if<Curve>(&e->value)) margin = std::max(margin, double(c->wf));
            if (const Node* n = std::get_if<Node>(&e->value)) margin = std::max(margin, double(n->roundabout));
            if (const Area* a = std::get_if<Area>(&e->value)) margin = std::max(margin, double(a->wf));
        }
    r.topReadAgain = topTouched(step);
    if (r.topReadAgain) {
        try {
            readTopAgain();
        } catch (...) {
            // The top could not be read again with the step (the file changed or cannot be read);
            // nothing else has changed yet: the step is taken back, the forest reads over the
            // edits as they were.
            lazyEdits_->rollback();
            forest_->setOverlay(lazyEdits_->overlay(), lazyEdits_->version());
            throw;
        }
    }
    const LazyForest::Renewal renewed = forest_->renew(step, margin);
    r.updateMs = msBetween(t0, std::chrono::steady_clock::now());
    r.changedQuads = renewed.parts.size() + (r.topReadAgain ? 1 : 0);
    // The tiles to make again: below the parts made anew, the quads UPDATE changed in the parts
    // updated in place, and the top's when it was read again.
    const int P = forest_->partLevel();
    const std::set<QuadKey> rebuilt(renewed.rebuilt.begin(), renewed.rebuilt.end());
    std::set<QuadKey> changed = renewed.changed;
    for (const auto& [key, tile] : loop_->tiles()) {
        const auto [level, x, y] = key;
        if (level < P ? r.topReadAgain : rebuilt.count({P, x >> (level - P), y >> (level - P)}) > 0 || (r.topReadAgain && level == P))
            changed.insert(key);
    }
    // The quads of the part level where the step was and is, and every quad below them: their
    // appearance is made from the parts now, no longer read from the pyramid.
    std::set<QuadKey> touched(renewed.parts.begin(), renewed.parts.end());
    const Box extent = doc_.scene.extent;
    const double cells = double(std::int64_t(1) << P), side = extent.size().x / cells;
    for (const Box& b : step.boxes) {
        const Box d = b.dilated(topReach_ + margin);
        const auto cell = [&](double v, double origin) { return std::int64_t(std::clamp(std::floor((v - origin) / side), 0.0, cells - 1.0)); };
        for (std::int64_t x = cell(d.min.x, extent.min.x); x <= cell(d.max.x, extent.min.x); ++x)
            for (std::int64_t y = cell(d.min.y, extent.min.y); y <= cell(d.max.y, extent.min.y); ++y) touched.insert({P, int(x), int(y)});
    }
    r.dirtyTiles = loop_->editedLazily(changed, std::vector<QuadKey>(touched.begin(), touched.end()));
    return r;
}

CommandReport EditSession::afterEdit(const Changeset& cs, double applyMs) {
    CommandReport r;
    r.applyMs = applyMs;
    std::vector<ElementRef> dropped = data_->invalidate(cs);
    const auto t0 = std::chrono::steady_clock::now();
    const UpdateStats st = quadtree_->update(cs);
    r.updateMs = msBetween(t0, std::chrono::steady_clock::now());
    if (!st.reexpanded.empty()) {  // their procedural curves may keep their ids with a new shape
        Changeset again;
        for (const ElementRef& e : st.reexpanded) again.modify(e);
        const std::vector<ElementRef> more = data_->invalidate(again);
        dropped.insert(dropped.end(), more.begin(), more.end());
    }
    r.changedQuads = st.changedQuads.size();
    std::set<QuadKey> changed;
    for (const Quad* q : st.changedQuads) changed.insert(keyOf(*q));
    // UPDATE never lists the root (its graph is the scene's): any edit changes it.
    const bool edited = !cs.empty();
    if (edited) changed.insert(keyOf(quadtree_->root()));
    r.dirtyTiles = loop_->edited(changed, dropped, edited);
    return r;
}

bool EditSession::afterLazyHistory(const std::optional<LazyStep>& step, CommandReport* report, std::size_t stopped) {
    if (!step) return false;
    CommandReport r = afterLazyStep(*step, 0.0);
    r.backgroundStopped = stopped;
    if (report) *report = r;
    return true;
}

template <class Step>
CommandReport EditSession::edits(Step&& step) {
    CommandReport total;
    step([&](const Changeset& cs, double applyMs) {
        const CommandReport r = afterEdit(cs, applyMs);
        total.applyMs += r.applyMs, total.updateMs += r.updateMs;
        total.changedQuads += r.changedQuads, total.dirtyTiles += r.dirtyTiles;
    });
    return total;
}

CommandReport EditSession::execute(const Command& command, bool merge) {
    const std::size_t stopped = loop_->quiesce();  // the background work reads the scene and the trees the command changes
    CommandReport r;
    if (lazyEdits_) {
        const auto t0 = std::chrono::steady_clock::now();
        const LazyStep step = lazyEdits_->execute(command, merge);
        r = afterLazyStep(step, msBetween(t0, std::chrono::steady_clock::now()));
    } else {
        r = edits([&](const CommandHistory::AfterEdit& after) { history_.execute(doc_.scene, command, merge, after); });
    }
    r.backgroundStopped = stopped;
    return r;
}

void EditSession::beginGroup() { lazyEdits_ ? lazyEdits_->beginGroup() : history_.beginGroup(); }
void EditSession::endGroup() { lazyEdits_ ? lazyEdits_->endGroup() : history_.endGroup(); }

bool EditSession::undo(CommandReport* report) {
    const std::size_t stopped = loop_->quiesce();
    if (lazyEdits_) return afterLazyHistory(lazyEdits_->undo(), report, stopped);
    bool done = false;
    CommandReport r = edits([&](const CommandHistory::AfterEdit& after) { done = history_.undo(doc_.scene, after); });
    r.backgroundStopped = stopped;
    if (done && report) *report = r;
    return done;
}

bool EditSession::redo(CommandReport* report) {
    const std::size_t stopped = loop_->quiesce();
    if (lazyEdits_) return afterLazyHistory(lazyEdits_->redo(), report, stopped);
    bool done = false;
    CommandReport r = edits([&](const CommandHistory::AfterEdit& after) { done = history_.redo(doc_.scene, after); });
    r.backgroundStopped = stopped;
    if (done && report) *report = r;
    return done;
}

void EditSession::setK(double K) {
    ViewParams view = params_.view;
    view.K = K;
    view.validate();
    params_.view = view;
}

void EditSession::setRefineParams(const RefineParams& refine) {
    loop_->quiesce();
    // A scene read lazily: what the top tree needs depends on the refinement (the reach, the
    // narrowest curve read), so it is read again (the DEM stays).
    if (lazy_)
        doc_.scene = std::move(LazyForest::readTop(lazyPath_, *lazy_, refine, /*dem=*/false, lazyEdits_->overlay().get()).doc.scene);
    params_.refine = refine;
    buildTree();
}

void EditSession::setLayerVisible(LayerId layer, bool visible) {
    if (layer >= doc_.scene.layers.size()) throw std::out_of_range("EditSession::setLayerVisible: no layer " + std::to_string(layer));
    if (layerVisible(layer) == visible) return;
    loop_->quiesce();  // before the knobs change
    for (std::vector<bool>* hidden : {&params_.appearance.hiddenLayers, &params_.elevation.hiddenLayers, &params_.objects.hiddenLayers}) {
        hidden->resize(doc_.scene.layers.size(), false);
        (*hidden)[layer] = !visible;
    }
    loop_->layerChanged(layer);
}

}  // namespace lacet
