#pragma once
// A changeset: the root elements an edit removed and added (§6). A modified element is both
// removed (its old version) and added (its new version). UPDATE consumes it.

#include <vector>

#include "model/types.h"

namespace lacet {

struct ElementRef {
    LayerId layer = 0;
    ElementKind kind = ElementKind::Node;
    ElementId id = kNoElement;
    friend bool operator==(const ElementRef&, const ElementRef&) = default;
    friend auto operator<=>(const ElementRef&, const ElementRef&) = default;
};

struct Changeset {
    std::vector<ElementRef> removed;
    std::vector<ElementRef> added;

    void modify(ElementRef r) { removed.push_back(r); added.push_back(r); }
    bool empty() const { return removed.empty() && added.empty(); }
    // Sorts and removes duplicates from both lists.
    void normalize();
    void append(const Changeset& other);
};

}  // namespace lacet
