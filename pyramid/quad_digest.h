#pragma once
// What a quad's tiles are made from, as one 64-bit digest per quad: `lacet pyramid update` remakes
// the tiles of a quad whose digest changed since the pyramid was built, and only those (and the
// mipmapped ancestors of its appearance). It is computed from the scene as it is, so it stays
// right however the scene was changed (the editor, a re-import, another program).
//
// A quad's digest covers everything its producers read (raster/elevation_producer.h,
// raster/appearance_producer.h) besides the DEM and the knobs, which a pyramid digests once as a
// whole (pyramid/pyramid_build.h):
// - its clipped graph: per layer, each ancestor's pieces (vertices, parameters s, node ends),
//   each area's clipped loops, each kept node's position, in id order;
// - for each ancestor curve it holds, the curve's own digest: its geometry and attributes, its
//   procedural data (the root part, spans, rings), its computed z-profile (which sums up the
//   terrain under it, the rivers upstream, the water a bridge spans), and for each end node
//   the node and every curve meeting there (stop lines and junction radii read them);
// - for each area: its loops' curves, attributes and axial curve; a lake's computed level; a
//   river area, the digests of the river curves its water follows through it (raster/
//   elevation_producer.h: axialRiver).
// With QuadDigestScope::Elevation (a quad whose appearance is mipmapped, not made from vector
// data: only its elevation tile follows from its digest), only what the elevation producer reads:
// the road and river curves it draws (not bridges or tunnels, at least two elevation samples
// wide) and the lakes and river areas; so that the digest is the same whether the thinner curves
// and the other layers are loaded or not (pyramid/pyramid_build.h builds the levels above the
// shards from a scene file without them).
// These are conservative: an edit of a curve changes the digest of the quads of its neighbours at
// its nodes too, never fewer quads than the tiles that changed.
//
// Thread safety: of() may run for many quads at once (ancestor digests are computed once, under a
// lock, and the CurveDataCache is thread-safe).

#include <cstdint>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "model/curve_data.h"
#include "model/quadtree.h"

namespace lacet {

// The version of what a digest covers: a pyramid's inputs digest (pyramid/pyramid_build.h) includes
// it, so that an update by a program that digests differently remakes everything instead of
// remaking whatever happens to differ. Raise it with every change of the formula below.
inline constexpr int kQuadDigestVersion = 4;

enum class QuadDigestScope { All, Elevation };

class QuadDigests {
public:
    QuadDigests(const Quadtree& quadtree, const CurveDataCache& curveData);
    std::uint64_t of(const Quad& quad, QuadDigestScope scope = QuadDigestScope::All) const;

    std::uint64_t curve(LayerId layer, AncestorId id) const;
    std::uint64_t area(LayerId layer, ElementId id) const;
    std::uint64_t node(LayerId layer, ElementId id) const;

private:
    std::uint64_t computeCurve(LayerId layer, AncestorId id) const;
    std::uint64_t computeArea(LayerId layer, ElementId id) const;
    std::uint64_t computeNode(LayerId layer, ElementId id) const;

    const Quadtree& qt_;
    const CurveDataCache& data_;
    mutable std::mutex mutex_;
    mutable std::vector<std::unordered_map<AncestorId, std::uint64_t>> curves_, areas_, nodes_;
};

}  // namespace lacet
