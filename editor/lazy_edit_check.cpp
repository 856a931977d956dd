#include "editor/lazy_edit_check.h"

#include <chrono>
#include <random>

#include "io/scene_checksum.h"
#include "model/edits.h"
#include "model/work_clock.h"

namespace lacet {
namespace {

// The kinds of random edits (randomEdit's `kind`, 0..kEditKinds - 1).
constexpr int kEditKinds = 8;
constexpr int kDrawKind = 7;  // a new node and a new curve to it from curve c's end: one group

// The commands of one random edit of curve `c` of layer `l` (empty: none of this kind there);
// `newNode`: the id the next node added to `l` gets.
std::vector<Command> randomEdit(const Layer& layer, LayerId l, ElementId c, int kind, ElementId newNode, const LazyEditCheckParams& p,
                                std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Curve& curve = layer.curves[c];
    const Vec2 shift = (Vec2(u(rng), u(rng)) * 2.0 - 1.0) * p.reach;
    std::vector<Command> commands;
    switch (kind) {
    case 0:
    case 1:
        if (curve.vertices.size() < 3) break;
        {
            const std::size_t i = 1 + std::size_t(u(rng) * double(curve.vertices.size() - 2)) % (curve.vertices.size() - 2);
            for (int step = 1; step <= p.dragSteps; ++step)  // a drag: one undo step
                commands.push_back(MoveVertexCmd{l, c, i, curve.vertices[i].p + shift * (double(step) / p.dragSteps)});
        }
        break;
    case 2:
        for (int step = 1; step <= p.dragSteps; ++step)
            commands.push_back(MoveNodeCmd{l, curve.start, layer.nodes[curve.start].p + shift * (double(step) / p.dragSteps)});
        break;
    case 3: {
        const float w = float(2.0 + 12.0 * u(rng));
        commands.push_back(SetCurveWidthCmd{l, c, w, w * 2.0f});
        break;
    }
    case 4:
        commands.push_back(SetCurveFlagsCmd{l, c, std::uint16_t(curve.flags ^ kBridge)});
        break;
    case 5:
        commands.push_back(SetRoundaboutCmd{l, curve.end, float(10.0 + 15.0 * u(rng))});
        break;
    case kDrawKind: {
        // As the draw tool makes one: a node, then a curve (a quadratic piece) from c's end to it.
        const Vec2 a = layer.nodes[curve.end].p, b = a + shift;
        const Vec2 side(-(b - a).y, (b - a).x);
        Curve drawn;
        drawn.start = curve.end;
        drawn.end = newNode;
        drawn.w = curve.w;
        drawn.wf = curve.wf;
        drawn.cls = curve.cls;
        drawn.vertices = {Vertex{a, true, false}, Vertex{(a + b) * 0.5 + side * (0.5 * (u(rng) - 0.5)), false, false}, Vertex{b, true, false}};
        commands.push_back(AddNodeCmd{l, b});
        commands.push_back(AddCurveCmd{l, drawn});
        break;
    }
    default:
        commands.push_back(DeleteCurveCmd{l, c});
        break;
    }
    return commands;
}

}  // namespace

LazyEditCheckReport checkLazyEdits(EditSession& lazy, EditSession& whole, const LazyEditCheckParams& p) {
    if (!lazy.lazyForest() || whole.lazyForest()) throw std::invalid_argument("checkLazyEdits: a lazy session and a whole one");
    std::mt19937_64 rng(p.seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Scene& scene = whole.document().scene;  // the file's ids
    const Box extent = scene.extent;
    const int partLevel = lazy.lazyForest()->partLevel();
    LazyEditCheckReport r;
    int edit = 0;
    const auto compare = [&](glm::dvec3 viewer) {
        whole.frame(viewer, 0.0);
        lazy.frame(viewer, 0.0);
        for (const auto& [key, w] : whole.tiles()) {
            const CachedTile* t = lazy.tile(key);
            if (w.dirty || !t || t->dirty) continue;
            const auto [level, x, y] = key;
            // Drawn from the top tree: above the part level, or at it where its part is not held.
            const bool top = level < partLevel || (level == partLevel && !lazy.lazyForest()->holds(key));
            std::string differs;
            if (level >= p.appearanceFrom && (!p.topElevationOnly || !top) && t->texels() != w.texels()) differs += " appearance";
            if (t->elevation.zm != w.elevation.zm) differs += " elevation";
            if ((!p.topElevationOnly || !top) && t->objects.indices.size() != w.objects.indices.size()) differs += " objects";
            ++r.tilesCompared;
            if (differs.empty()) continue;
            ++r.mismatches;
            if (r.details.size() < p.maxDetails)
                r.details.push_back("edit " + std::to_string(edit) + ": tile " + std::to_string(level) + "/" + std::to_string(x) + "/" +
                                    std::to_string(y) + " differs:" + differs);
        }
    };
    // The lazy session's edits saved into its file: the rows the file holds now sum to the whole
    // session's document (io/scene_checksum.h: every value of every element, bit for bit).
    const auto save = [&]() {
        const SceneEditsSaved saved = lazy.saveEdits();
        ++r.saves;
        r.saveMs.push_back(saved.totalMs);
        const std::string expected = sceneChecksumText(whole.document());
        if (saved.checksum != expected || lazy.modified()) {
            ++r.mismatches;
            if (r.details.size() < p.maxDetails)
                r.details.push_back("edit " + std::to_string(edit) + ": the file saved sums to " + saved.checksum + ", the whole scene to " + expected);
        }
    };
    for (edit = 0; edit < p.edits; ++edit) {
        const LayerId l = LayerId(std::size_t(u(rng) * double(scene.layers.size())) % scene.layers.size());
        const Layer& layer = scene.layers[l];
        if (layer.curves.empty()) continue;
        const ElementId c = ElementId(std::size_t(u(rng) * double(layer.curves.size())) % layer.curves.size());
        if (!layer.curves[c].alive) continue;
        const Vec2 at = layer.curves[c].vertices.front().p;
        const int kind = edit % kEditKinds;
        // The id a new node gets: the same in both (the whole scene's slot, the file's next id).
        const ElementId newNode = whole.nextId(l, ElementKind::Node);
        if (kind == kDrawKind && lazy.nextId(l, ElementKind::Node) != newNode) {
            ++r.mismatches;
            if (r.details.size() < p.maxDetails)
                r.details.push_back("edit " + std::to_string(edit) + ": a new node's id is " + std::to_string(lazy.nextId(l, ElementKind::Node)) +
                                    " lazily, " + std::to_string(newNode) + " in the whole scene");
        }
        const std::vector<Command> commands = randomEdit(layer, l, c, kind, newNode, p, rng);
        if (kind == kDrawKind) whole.beginGroup(), lazy.beginGroup();
        bool applied = false;
        for (std::size_t i = 0; i < commands.size(); ++i) {
            bool wholeRefused = false, lazyRefused = false;
            auto t0 = std::chrono::steady_clock::now();
            try {
                whole.execute(commands[i], i > 0);
                r.wholeMs.push_back(msSince(t0));
            } catch (const EditError&) {
                wholeRefused = true;
            }
            t0 = std::chrono::steady_clock::now();
            try {
                const CommandReport done = lazy.execute(commands[i], i > 0);
                r.lazyMs.push_back(msSince(t0));
                r.topReads += done.topReadAgain;
                r.partsRenewed += done.changedQuads - (done.topReadAgain ? 1 : 0);
            } catch (const EditError& e) {
                lazyRefused = true;
                if (!wholeRefused && r.details.size() < p.maxDetails)
                    r.details.push_back("edit " + std::to_string(edit) + ": refused lazily only: " + e.what());
            }
            if (wholeRefused != lazyRefused) {
                ++r.refusedDifferently;
                ++r.mismatches;
            }
            if (wholeRefused || lazyRefused) {
                r.refused += wholeRefused && lazyRefused;
                break;
            }
            applied = true;
            ++r.commands;
        }
        if (kind == kDrawKind) whole.endGroup(), lazy.endGroup();
        r.edits += applied;
        if (lazy.undoDepth() != whole.undoDepth()) {
            ++r.mismatches;
            if (r.details.size() < p.maxDetails) r.details.push_back("edit " + std::to_string(edit) + ": the undo depths differ");
        }
        if (u(rng) < p.undoChance) {
            const bool a = lazy.undo(), b = whole.undo();
            r.undos += a && b;
            r.mismatches += a != b;
            if (u(rng) < 0.5) {
                const bool c2 = lazy.redo(), d = whole.redo();
                r.redos += c2 && d;
                r.mismatches += c2 != d;
            }
        }
        if (p.saveEvery > 0 && (edit + 1) % p.saveEvery == 0) save();
        compare({at.x, at.y, 40.0 + 300.0 * u(rng)});
        if (edit % 3 == 0) {
            const Vec2 q = extent.min + Vec2(u(rng), u(rng)) * extent.size();
            compare({q.x, q.y, 60.0});
        }
    }
    // Everything undone: the file as it was opened, in both (saved again when edits were saved).
    while (whole.undo())
        if (!lazy.undo()) ++r.mismatches;
    if (lazy.undo()) ++r.mismatches;
    if (r.saves > 0) save();
    if (lazy.modified()) ++r.mismatches;
    compare({extent.center().x, extent.center().y, 80.0});
    return r;
}

}  // namespace lacet
