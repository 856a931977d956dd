#pragma once
// The editor's read-only view of a scene's tile pyramid (§7, Fig. 10): the appearance tiles of the
// levels below the pyramid's first vector level L (PyramidInfo::vectorLevel; they were mipmapped
// from level L's tiles, made from vector data), given to the live loop as editor tiles in place of
// producing them from the vector data of coarse quads, whose cost grows with the data they hold.
// Levels L and deeper, and every elevation tile, are produced live (editor/edit_session.h).
//
// Order of calls: construct (opens the file read-only and checks that the pyramid is complete and
// made for the scene's extent and CRS; throws PyramidError, a std::runtime_error, with the reason
// otherwise), then serves() / appearance() from any thread.
//
// A tile the pyramid cannot give (missing, a blob that does not decode, of the wrong size, or a
// read that fails because a `lacet pyramid update` holds the file) gives nullopt and is counted:
// the caller produces it live instead, so garbage is never shown.
//
// Thread safety: appearance() may run on many threads at once: the SQLite read (tens of
// microseconds) is done under a mutex on one connection, the decode (most of the ~1 ms) outside it.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "io/document.h"
#include "model/quadtree.h"
#include "model/types.h"
#include "raster/appearance_tile.h"

namespace lacet {

// What the reader gave so far (thread-safe counters).
struct PyramidReadStats {
    std::size_t read = 0;        // tiles given
    std::size_t corrupt = 0;     // blobs that did not decode, or decoded to the wrong size or channels
    std::size_t missing = 0;     // tiles the pyramid should hold and does not
    std::size_t unreadable = 0;  // reads SQLite refused (the file locked by an update, an I/O error)
    double readMs = 0.0, decodeMs = 0.0;  // summed over threads
};

class PyramidReader {
public:
    // Opens `path` for a scene of `extent` (m, scene CRS) and CRS `crsWkt` (empty: none, as
    // synthetic scenes). Throws PyramidError naming the file and the reason when it holds no
    // pyramid, an incomplete one, one without appearance, or one of another extent or CRS.
    PyramidReader(const std::string& path, const Box& extent, const std::string& crsWkt);
    // The same for the scene of `doc` (its extent and georeference's CRS), and refuses a pyramid
    // made from another state of that scene (PyramidInfo::sceneChecksum: edited or imported again
    // without `lacet pyramid update`), whose tiles would show what is no longer there.
    PyramidReader(const std::string& path, const SceneDocument& doc);
    // The same for a scene known by its extent, CRS and checksum text (io/scene_checksum.h: a
    // scene file's stored one, for a scene never whole in memory).
    PyramidReader(const std::string& path, const Box& extent, const std::string& crsWkt, const std::string& sceneChecksum);
    ~PyramidReader();
    PyramidReader(const PyramidReader&) = delete;
    PyramidReader& operator=(const PyramidReader&) = delete;

    const std::string& path() const;
    int minLevel() const;
    int maxLevel() const;
    // L: the first level whose appearance the pyramid made from vector data.
    int vectorLevel() const;
    int tileSize() const;          // appearance texels per tile side
    const std::string& encoding() const;
    // The scene checksum the pyramid records (PyramidInfo::sceneChecksum; empty: none).
    const std::string& sceneChecksum() const;
    // Whether the editor reads `level`'s appearance here: minLevel <= level < vectorLevel (and
    // level <= maxLevel).
    bool serves(int level) const;

    // The editor's appearance tile of `q` (its texels, `border` texels around repeating the edge
    // ones); nullopt when the pyramid does not serve its level or cannot give the tile (counted).
    std::optional<AppearanceTile> appearance(const Quad& q, int border);

    PyramidReadStats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace lacet
