#pragma once
// A 64-bit checksum of a scene document's values, stored in the scene file: SQLite checks the file's
// structure, not the values inside it; the checksum catches damaged coordinates, heights and ids
// that would otherwise load silently. Every field counts, dead slots included, floats and doubles
// by their bits (so -0.0 and NaN payloads too).
//
// Two forms, by the file's format version (io/scene_file.h):
//   1  one digest of every value in order (files written before format 2 are checked so);
//   2  the digest of the head (extent, layers' names, kinds and counts, attributes, georeference,
//      DEM) and the sum modulo 2^64 of one digest per element (its layer, kind and id, then its
//      values as in 1), combined. An element's change changes the sum by its digest after less
//      its digest before, so edits saved in place (io/scene_save_edits.h) update it from the rows
//      they write, not from every row of the scene; the file keeps the two parts beside the
//      checksum (lacet_meta 'checksum_head', 'checksum_elements'), which loading does not trust:
//      it sums the document again and compares the checksum.
//
// A streamed DEM (doc.demLod) counts by its layout (width, height, cell, origin, block side, levels)
// and the digest stored with the tree (kDemLodMetaTable's 'digest', io/dem_lod.h), not by its
// samples nor by doc.dem, which is derived from them: loading a scene never reads the whole tree, so
// no checksum over the samples could be checked there, and the stored digest is what the writer
// computed, not recomputed at load. A damaged tile is caught instead when it is decoded
// (DemLodFile::readStored: a tile that does not decode or has the wrong size, a value where the null
// belongs, a null or non-finite value where a height belongs), and loadScene checks that every tile
// the layout needs is there; a tile whose heights changed to other plausible heights passes both.

#include <cstdint>
#include <string>

#include "io/digest.h"
#include "io/document.h"
#include "io/scene_file.h"

namespace lacet {

// The checksum as the file stores it (16 lowercase hex digits each): the same document always gives
// the same text, on any host. head and elements: format 2's parts (0 for format 1).
struct SceneChecksumParts {
    std::string text;
    std::uint64_t head = 0, elements = 0;
};

// The checksum of `doc` in format `version` (1 or 2; std::invalid_argument otherwise).
std::string sceneChecksumText(const SceneDocument& doc, int version = kSceneFormatVersion);
SceneChecksumParts sceneChecksumParts(const SceneDocument& doc, int version = kSceneFormatVersion);

// The same sum fed a piece at a time, for a document never whole in memory (saveSceneStreamed):
// construct with the scene (its extent and layer count), then for each layer in order either
// layer() or layerHead(), count(nodes), node()..., count(curves), curve()..., count(areas), area()...;
// then finish() with the document's attributes, georeference and DEM.
class SceneChecksum {
public:
    explicit SceneChecksum(const Scene& scene, int version = kSceneFormatVersion);
    void layer(const Layer& layer);
    void layerHead(const Layer& layer);  // name and kind
    void count(std::size_t n);
    void node(const Node& n);
    void curve(const Curve& c);
    void area(const Area& a);
    SceneChecksumParts finish(const SceneDocument& doc);
    // finish() with attributes other than doc's (a scene written in parts: its rows): the count,
    // each attribute in order, then the rest of doc.
    void attributeCount(std::size_t n);
    void attribute(const ElementAttribute& a);
    SceneChecksumParts finishAfterAttributes(const SceneDocument& doc);

    // Format 2: one element's digest, the checksum of a head and a sum, and the text of a part.
    static std::uint64_t elementDigest(LayerId layer, ElementId id, const Node& n);
    static std::uint64_t elementDigest(LayerId layer, ElementId id, const Curve& c);
    static std::uint64_t elementDigest(LayerId layer, ElementId id, const Area& a);
    static std::string combine(std::uint64_t head, std::uint64_t elements);
    static std::string hex(std::uint64_t v);

private:
    int version_;
    Digest c_;  // io/digest.h: format 1's one digest, format 2's head
    std::uint64_t sum_ = 0;
    // Format 2: the element being summed next (its layer and id; the kind is the method's).
    std::int64_t layer_ = -1;
    ElementId next_ = 0;
};

}  // namespace lacet
