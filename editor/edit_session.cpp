#include "editor/edit_session.h"

#include <chrono>
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
    lazy_ = lazy;
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
        loop_->setForest(*forest_);
    }
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

template <class Step>
CommandReport EditSession::edits(Step&& step) {
    if (forest_) throw EditError("EditSession: " + lazyPath_ + " is read lazily (a vector budget): editing it is not built yet");
    CommandReport total;
    step([&](const Changeset& cs, double applyMs) {
        const CommandReport r = afterEdit(cs, applyMs);
        total.applyMs += r.applyMs, total.updateMs += r.updateMs;
        total.changedQuads += r.changedQuads, total.dirtyTiles += r.dirtyTiles;
    });
    return total;
}

CommandReport EditSession::execute(const Command& command, bool merge) {
    return edits([&](const CommandHistory::AfterEdit& after) { history_.execute(doc_.scene, command, merge, after); });
}

void EditSession::beginGroup() { history_.beginGroup(); }
void EditSession::endGroup() { history_.endGroup(); }

bool EditSession::undo(CommandReport* report) {
    if (forest_) return false;  // a scene read lazily has no edit to undo
    bool done = false;
    const CommandReport r = edits([&](const CommandHistory::AfterEdit& after) { done = history_.undo(doc_.scene, after); });
    if (done && report) *report = r;
    return done;
}

bool EditSession::redo(CommandReport* report) {
    if (forest_) return false;
    bool done = false;
    const CommandReport r = edits([&](const CommandHistory::AfterEdit& after) { done = history_.redo(doc_.scene, after); });
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
    // A scene read lazily: what the top tree needs depends on the refinement (the reach, the
    // narrowest curve read), so it is read again (the DEM stays).
    if (lazy_) doc_.scene = std::move(LazyForest::readTop(lazyPath_, *lazy_, refine, /*dem=*/false).doc.scene);
    params_.refine = refine;
    buildTree();
}

void EditSession::setLayerVisible(LayerId layer, bool visible) {
    if (layer >= doc_.scene.layers.size()) throw std::out_of_range("EditSession::setLayerVisible: no layer " + std::to_string(layer));
    if (layerVisible(layer) == visible) return;
    for (std::vector<bool>* hidden : {&params_.appearance.hiddenLayers, &params_.elevation.hiddenLayers, &params_.objects.hiddenLayers}) {
        hidden->resize(doc_.scene.layers.size(), false);
        (*hidden)[layer] = !visible;
    }
    loop_->layerChanged(layer);
}

}  // namespace lacet
