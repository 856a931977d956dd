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

#include "io/document.h"

namespace lacet {

// 16 lowercase hex digits; the same document always gives the same text, on any host.
std::string sceneChecksumText(const SceneDocument& doc);

}  // namespace lacet
