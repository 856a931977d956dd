#pragma once
// A 64-bit checksum of a scene document's values, stored in the scene file: SQLite checks the file's
// structure, not the values inside it; the checksum catches damaged coordinates, heights and ids
// that would otherwise load silently. Every field counts, dead slots included, floats and doubles
// by their bits (so -0.0 and NaN payloads too).
//
// A streamed DEM (doc.demLod) counts by its layout (width, height, cell, origin, block side, levels)
// and the digest stored with the tree (kDemLodMetaTable's 'digest', io/dem_lod.h), not by its
// samples nor by doc.dem, which is derived from them: loading a scene never reads the whole tree, so
// no checksum over the samples could be checked there, and the stored digest is what the writer
// computed, not recomputed at load. A damaged tile is caught instead when it is decoded
// (DemLodFile::readStored: a tile that does not decode or has the wrong size, a value where the null
// belongs, a null or non-finite value where a height belongs), and loadScene checks that every tile
// the layout needs is there; a tile whose heights changed to other plausible heights passes both.

#include <string>

#include "io/digest.h"
#include "io/document.h"

namespace lacet {

// 16 lowercase hex digits; the same document always gives the same text, on any host.
std::string sceneChecksumText(const SceneDocument& doc);

// The same sum fed a piece at a time, for a document never whole in memory (saveSceneStreamed):
// construct with the scene (its extent and layer count), then for each layer in order either
// layer() or layerHead(), count(nodes), node()..., count(curves), curve()..., count(areas), area()...;
// then finish() with the document's attributes, georeference and DEM.
class SceneChecksum {
public:
    explicit SceneChecksum(const Scene& scene);
    void layer(const Layer& layer);
    void layerHead(const Layer& layer);  // name and kind
    void count(std::size_t n);
    void node(const Node& n);
    void curve(const Curve& c);
    void area(const Area& a);
    std::string finish(const SceneDocument& doc);

private:
    Digest c_;  // io/digest.h: this checksum's rounds, unchanged (files written before load the same)
};

}  // namespace lacet
