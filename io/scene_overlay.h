#pragma once
// Edits of a scene file not yet saved, over the file (issue 23: editing a scene read lazily, §7):
// the root elements an edit changed, by their ids in the file, each with its value now (naming
// file ids) and its feature box now. A region read given an overlay (io/scene_region.h) reads
// each of these elements from the overlay instead of its row, finds it by its box now instead of
// the file's R-tree box, and so loads what it would load from the file saved with the edits:
// everything that read loads, with the same values (it may load more, where the file's
// R-tree boxes or largest widths are those from before the edit).
//
// A value is copied in whole (a node with its whole list of curves, read where every curve at it
// was loaded). Dead elements stay as dead values (an edit never frees an id). An element the edits
// added has an id past the file's largest; one added, saved, then taken back is `absent`: the file
// saved holds no row for it (as the whole scene, whose undo of an add frees the slot). Immutable
// once shared: an edit makes the next overlay from a copy (reads in flight keep theirs).

#include <cstddef>
#include <map>
#include <optional>
#include <variant>

#include "model/changeset.h"
#include "model/graph.h"

namespace lacet {

struct OverlayElement {
    std::variant<Node, Curve, Area> value;  // by its ElementRef's kind
    // Its feature's box in the file's R-tree as the feature tables would write it now
    // (io/scene_features.h: featureBox); none for a node, a dead element or a curve of an area's loop.
    std::optional<Box> box;
    // No such element in the file saved (its row is deleted): `value` is a dead element of its kind,
    // which reads see as they see a dead one (nothing alive names it).
    bool absent = false;
};

// The entry of an element of `kind` the file saved does not hold (above: absent).
OverlayElement absentElement(ElementKind kind);

struct SceneOverlay {
    std::map<ElementRef, OverlayElement> elements;  // ordered by layer, kind, file id

    bool empty() const { return elements.empty(); }
    const OverlayElement* find(const ElementRef& ref) const {
        const auto it = elements.find(ref);
        return it != elements.end() ? &it->second : nullptr;
    }
    // The elements of one kind of a layer, by file id.
    template <class F>
    void forEach(LayerId layer, ElementKind kind, F&& f) const {
        for (auto it = elements.lower_bound({layer, kind, 0}); it != elements.end() && it->first.layer == layer && it->first.kind == kind;
             ++it)
            f(it->first.id, it->second);
    }
};

// Element `id` of `layer` as an overlay keeps it: its references turned into the file's ids
// (Layer::sceneIds; a whole layer's are the file's), its feature box with the feature tables'
// `tolerance`. An element of a part must have been read with every element it names that the file
// saved would hold (a node with every curve at it): what the part did not read is left out.
OverlayElement overlayElement(const Layer& layer, ElementKind kind, ElementId id, double tolerance);
// A value of `layer` (its references ids of `layer`) as an overlay keeps it, as above.
OverlayElement overlayValue(const Layer& layer, Node n);
OverlayElement overlayValue(const Layer& layer, Curve c, double tolerance);
OverlayElement overlayValue(const Layer& layer, Area a, double tolerance);
// Its ElementRef in the file.
ElementRef fileRef(const Layer& layer, LayerId l, ElementKind kind, ElementId id);
// The id in `layer` (a part read: Layer::sceneIds; a whole layer: the file's) of the element of
// `kind` with file id `file`; kNoElement where the layer does not hold it.
ElementId localIdOf(const Layer& layer, ElementKind kind, ElementId file);

}  // namespace lacet
