#pragma once
// A 64-bit checksum of a scene document's values, stored in the scene file: SQLite checks the file's
// structure, not the values inside it; the checksum catches damaged coordinates, heights and ids
// that would otherwise load silently. Every field counts, dead slots included, floats and doubles
// by their bits (so -0.0 and NaN payloads too). A streamed DEM (doc.demLod) counts by its layout
// and its digest (io/dem_lod.h), not by doc.dem, which is derived from it.

#include <string>

#include "io/document.h"

namespace lacet {

// 16 lowercase hex digits; the same document always gives the same text, on any host.
std::string sceneChecksumText(const SceneDocument& doc);

}  // namespace lacet
