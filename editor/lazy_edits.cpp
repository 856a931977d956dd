#include "editor/lazy_edits.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <variant>

#include "io/scene_features.h"
#include "io/scene_region.h"
#include "model/edits.h"
#include "model/work_clock.h"

namespace lacet {
namespace {

// The level whose quads a command's region is read at: the deepest, so that the region is the
// elements' own boxes and the margins of what lies at them.
constexpr int kEditLevel = 30;

const char* kindName(ElementKind k) { return k == ElementKind::Node ? "node" : k == ElementKind::Curve ? "curve" : "area"; }

// The elements a command names, the file's ids.
std::vector<ElementRef> named(const Command& command) {
    return std::visit(
        [](const auto& c) -> std::vector<ElementRef> {
            using T = std::decay_t<decltype(c)>;
            if constexpr (std::is_same_v<T, MoveNodeCmd> || std::is_same_v<T, SetRoundaboutCmd>)
                return {{c.layer, ElementKind::Node, c.node}};
            else if constexpr (std::is_same_v<T, AddNodeCmd>)
                return {};
            else if constexpr (std::is_same_v<T, AddCurveCmd>)
                return {{c.layer, ElementKind::Node, c.curve.start}, {c.layer, ElementKind::Node, c.curve.end}};
            else
                return {{c.layer, ElementKind::Curve, c.curve}};
        },
        command);
}

// The id in `scene` (a part read) of `ref`, an element the command names.
ElementId localId(const Scene& scene, const ElementRef& ref) {
    const ElementId id = localIdOf(scene.layers[ref.layer], ref.kind, ref.id);
    if (id == kNoElement)
        throw EditError(std::string(kindName(ref.kind)) + " " + std::to_string(ref.id) + " of layer " + std::to_string(ref.layer) +
                        " is not in the scene");
    return id;
}

// `command` with the ids of `scene` (a part read) for the file's.
Command localized(Command command, const Scene& scene) {
    std::visit(
        [&](auto& c) {
            using T = std::decay_t<decltype(c)>;
            if (c.layer >= scene.layers.size()) throw EditError("the scene has no layer " + std::to_string(c.layer));
            if constexpr (std::is_same_v<T, MoveNodeCmd> || std::is_same_v<T, SetRoundaboutCmd>) {
                c.node = localId(scene, {c.layer, ElementKind::Node, c.node});
            } else if constexpr (std::is_same_v<T, AddCurveCmd>) {
                c.curve.start = localId(scene, {c.layer, ElementKind::Node, c.curve.start});
                c.curve.end = localId(scene, {c.layer, ElementKind::Node, c.curve.end});
            } else if constexpr (!std::is_same_v<T, AddNodeCmd>) {
                c.curve = localId(scene, {c.layer, ElementKind::Curve, c.curve});
            }
        },
        command);
    return command;
}

std::optional<Box> boxOf(const OverlayElement& e) {
    if (e.absent) return std::nullopt;
    if (const Node* n = std::get_if<Node>(&e.value)) return Box{n->p, n->p};
    if (const Curve* c = std::get_if<Curve>(&e.value)) {
        const Box b = hullBox(*c);
        return b.min.x <= b.max.x ? std::optional<Box>(b) : std::nullopt;
    }
    return e.box;
}

}  // namespace

LazyEdits::LazyEdits(std::string path, RefineParams refine)
    : path_(std::move(path)), connection_(path_), refine_(refine), overlay_(std::make_shared<const SceneOverlay>()) {}

LazyStep LazyEdits::execute(const Command& command, bool merge) {
    const auto t0 = std::chrono::steady_clock::now();
    Box region{Vec2(std::numeric_limits<double>::infinity()), Vec2(-std::numeric_limits<double>::infinity())};
    const std::vector<ElementRef> names = named(command);
    for (const ElementRef& ref : names) {
        const Box b = loadSceneElementBox(connection_, ref, overlay_.get());
        region = {glm::min(region.min, b.min), glm::max(region.max, b.max)};
    }
    if (const auto* add = std::get_if<AddNodeCmd>(&command)) {
        if (!std::isfinite(add->p.x) || !std::isfinite(add->p.y)) throw EditError("a node's position must be finite");
        region = {add->p, add->p};
    }
    SceneRegionOptions options;
    options.dem = false;
    options.overlay = overlay_.get();
    for (const ElementRef& ref : names)
        if (ref.kind == ElementKind::Node) options.nodes.push_back(ref);
    SceneRegionStats stats;
    SceneDocument doc = loadSceneRegion(connection_, region, refine_, kEditLevel, &stats, options);
    if (stats.wholeScene) throw EditError(path_ + " has no feature index, which editing it read lazily needs: save it again");
    const double readMs = msSince(t0);

    Scene& scene = doc.scene;
    const Command localCommand = localized(command, scene);
    // The feature boxes before the command of the areas it may change: those of the curves it
    // names, or of the node's curves.
    std::map<ElementRef, std::optional<Box>> areaBoxes;
    std::visit(
        [&](const auto& c) {
            using T = std::decay_t<decltype(c)>;
            const Layer& layer = scene.layers[c.layer];
            std::vector<ElementId> curves;
            if constexpr (std::is_same_v<T, MoveNodeCmd> || std::is_same_v<T, SetRoundaboutCmd>)
                curves = layer.nodes.at(c.node).curves;
            else if constexpr (!std::is_same_v<T, AddNodeCmd> && !std::is_same_v<T, AddCurveCmd>)
                curves = {c.curve};
            for (ElementId curve : curves)
                for (ElementId a : layer.curves.at(curve).areas)
                    areaBoxes[{c.layer, ElementKind::Area, a}] = featureBox(layer, layer.areas[a], stats.tolerance);
        },
        localCommand);
    const LayerId commandLayer = std::visit([](const auto& c) { return c.layer; }, localCommand);
    const std::size_t nodesBefore = scene.layers[commandLayer].nodes.size(), curvesBefore = scene.layers[commandLayer].curves.size(),
                      areasBefore = scene.layers[commandLayer].areas.size();
    // The element it adds gets the file's next id (the whole scene's slot), named in the part first.
    if (std::holds_alternative<AddNodeCmd>(localCommand))
        scene.layers[commandLayer].sceneIds.nodes.push_back(nextId(commandLayer, ElementKind::Node));
    if (std::holds_alternative<AddCurveCmd>(localCommand))
        scene.layers[commandLayer].sceneIds.curves.push_back(nextId(commandLayer, ElementKind::Curve));
    const Applied applied = lacet::apply(scene, localCommand);  // EditError: nothing changed (the part is dropped)
    const auto added = [&](const ElementRef& ref) {
        const std::size_t before = ref.kind == ElementKind::Node ? nodesBefore : ref.kind == ElementKind::Curve ? curvesBefore : areasBefore;
        return ref.layer == commandLayer && ref.id >= before;
    };
    // The elements the command changed (the ids of the part read): its snapshot's and changeset's.
    std::set<ElementRef> local;
    for (const auto& [id, n] : applied.before.nodes) local.insert({applied.before.layer, ElementKind::Node, id});
    for (const auto& [id, c] : applied.before.curves) local.insert({applied.before.layer, ElementKind::Curve, id});
    for (const std::vector<ElementRef>* refs : {&applied.changeset.removed, &applied.changeset.added}) local.insert(refs->begin(), refs->end());
    std::vector<Change> changes;
    for (const ElementRef& ref : local) {
        const Layer& layer = scene.layers[ref.layer];
        Change ch;
        ch.ref = fileRef(layer, ref.layer, ref.kind, ref.id);
        if (const OverlayElement* e = overlay_->find(ch.ref)) ch.before = *e;
        ch.after = overlayElement(layer, ref.kind, ref.id, stats.tolerance);
        ch.afterBox = boxOf(ch.after);
        // Its value before: the snapshot's (nodes and curves), else as now (an area's value does
        // not change, its box does); with the ids of the file.
        ch.value = ch.after;
        for (const auto& [id, n] : applied.before.nodes)
            if (ref.kind == ElementKind::Node && id == ref.id) ch.value = overlayValue(layer, n);
        for (const auto& [id, c] : applied.before.curves)
            if (ref.kind == ElementKind::Curve && id == ref.id) ch.value = overlayValue(layer, c, stats.tolerance);
        if (ref.kind == ElementKind::Area) {
            const auto it = areaBoxes.find(ref);
            ch.value.box = it != areaBoxes.end() ? it->second : ch.before ? ch.before->box : std::nullopt;
        }
        if (added(ref)) ch.value = absentElement(ref.kind);  // none before
        ch.beforeBox = boxOf(ch.value);
        changes.push_back(std::move(ch));
    }

    Before before{.overlay = overlay_, .serial = serial_, .redo = std::move(undone_)};
    undone_.clear();
    if (merge && !done_.empty() && continuesDrag(done_.back().command, command) && done_.back().serial != savedSerial_) {
        before.merged = done_.back();
        // One undo step: each element's state before the drag began, after this command.
        Step& last = done_.back();
        for (const Change& ch : changes) {
            const auto it = std::find_if(last.changes.begin(), last.changes.end(), [&](const Change& c) { return c.ref == ch.ref; });
            if (it == last.changes.end()) {
                last.changes.push_back(ch);
            } else {
                it->after = ch.after;
                it->afterBox = ch.afterBox;
            }
        }
        last.command = command;
        last.serial = ++serial_;
    } else {
        done_.push_back({command, changes, group_, ++serial_});
        before.pushed = true;
    }
    before_ = std::move(before);
    LazyStep step = replay(changes, true);
    step.readMs = readMs;
    return step;
}

LazyStep LazyEdits::replay(const std::vector<Change>& changes, bool forward) {
    auto next = std::make_shared<SceneOverlay>(*overlay_);
    LazyStep step;
    for (const Change& ch : changes) {
        if (forward)
            next->elements[ch.ref] = ch.after;
        else if (ch.before)
            next->elements[ch.ref] = *ch.before;
        else
            next->elements.erase(ch.ref);
        step.refs.push_back(ch.ref);
        step.before.push_back(forward ? ch.value : ch.after);
        step.after.push_back(forward ? ch.after : ch.value);
        for (const std::optional<Box>& b : {ch.beforeBox, ch.afterBox})
            if (b) step.boxes.push_back(*b);
    }
    overlay_ = std::move(next);
    ++version_;
    return step;
}

LazyStep LazyEdits::moveSteps(std::vector<Step>& from, std::vector<Step>& to, bool forward) {
    const std::uint64_t group = from.back().group;
    Before before{.overlay = overlay_, .serial = serial_, .undid = !forward};
    LazyStep total;
    do {
        const LazyStep s = replay(from.back().changes, forward);
        total.refs.insert(total.refs.end(), s.refs.begin(), s.refs.end());
        total.boxes.insert(total.boxes.end(), s.boxes.begin(), s.boxes.end());
        total.before.insert(total.before.end(), s.before.begin(), s.before.end());
        total.after.insert(total.after.end(), s.after.begin(), s.after.end());
        to.push_back(std::move(from.back()));
        from.pop_back();
        ++before.moved;
    } while (group != 0 && !from.empty() && from.back().group == group);
    before_ = std::move(before);
    return total;
}

bool LazyEdits::rollback() {
    if (!before_) return false;
    Before& b = *before_;
    if (b.moved > 0) {
        std::vector<Step>& from = b.undid ? undone_ : done_;  // where the move put them
        std::vector<Step>& to = b.undid ? done_ : undone_;
        for (std::size_t k = 0; k < b.moved; ++k) {
            to.push_back(std::move(from.back()));
            from.pop_back();
        }
    } else {
        if (b.merged) done_.back() = std::move(*b.merged);
        else if (b.pushed) done_.pop_back();
        undone_ = std::move(b.redo);
    }
    overlay_ = std::move(b.overlay);
    serial_ = b.serial;
    ++version_;  // the overlay as it was, under a new version: reads of the one taken back are stale
    before_.reset();
    return true;
}

void LazyEdits::markSaved() {
    // A change whose value before was the file's row names it now: the row is this state's.
    for (std::vector<Step>* steps : {&done_, &undone_})
        for (Step& s : *steps)
            for (Change& ch : s.changes)
                if (!ch.before) ch.before = ch.value;
    overlay_ = std::make_shared<const SceneOverlay>();
    ++version_;
    savedSerial_ = topSerial();
    before_.reset();  // what was saved is not taken back
}

ElementId LazyEdits::nextId(LayerId layer, ElementKind kind) const {
    std::size_t next = loadSceneIdCounts(connection_, kind).at(layer);
    overlay_->forEach(layer, kind, [&](ElementId id, const OverlayElement&) { next = std::max(next, std::size_t(id) + 1); });
    for (; next > 0; --next) {
        const OverlayElement* e = overlay_->find({layer, kind, ElementId(next - 1)});
        if (!e || !e->absent) break;
    }
    return ElementId(next);
}

std::optional<LazyStep> LazyEdits::undo() {
    if (done_.empty()) return std::nullopt;
    return moveSteps(done_, undone_, false);
}

std::optional<LazyStep> LazyEdits::redo() {
    if (undone_.empty()) return std::nullopt;
    return moveSteps(undone_, done_, true);
}

}  // namespace lacet
