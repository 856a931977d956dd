#pragma once
// The inside of editor/lazy_forest.h shared by its sources: a part held, and what it holds.

#include "editor/lazy_forest.h"
#include "io/scene_overlay.h"
#include "model/graph.h"

namespace lacet {

// One quad's part: its vector data, graph step, quadtree (down to the quad) and curve data.
struct LazyForest::Part {
    SceneDocument doc;
    GraphStep graphStep;
    Quadtree tree;
    CurveDataCache data;
    Quad* quad = nullptr;
    std::size_t bytes = 0;
    double reach = 0.0;        // m around the quad its read searched
    double tolerance = 0.0;    // of the file's feature boxes (io/scene_features.h)
    std::uint64_t wanted = 0;  // the clock of the last refine that wanted it
    double readMs = 0.0;       // its reading and clipping
    Part(SceneDocument d, const GraphStepParams& graph, const RefineParams& refine, const ZProfileParams& profiles,
         const HeightField& heights)
        : doc(std::move(d)), graphStep(doc.scene, graph), tree(doc.scene, refine, &graphStep), data(tree, heights, profiles) {}
};

// Whether `scene` (a part read) holds element `r` (its file id).
inline bool holdsElement(const Scene& scene, const ElementRef& r) {
    return r.layer < scene.layers.size() && localIdOf(scene.layers[r.layer], r.kind, r.id) != kNoElement;
}

}  // namespace lacet
