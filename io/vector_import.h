#pragma once
// Vector import through OGR (OSM PBF and XML, Shapefile, GeoJSON, GeoPackage: anything OGR reads):
// every feature the mapping (io/feature_mapping.h) accepts, as lon/lat lines and areas, with a
// per-feature problem report. A bad feature is skipped and the rest imports.
//
// Per-feature problems (file, layer, feature id, reason): no geometry; a non-finite coordinate; a
// way of fewer than 2 distinct points (zero length); a ring that is not closed, or has fewer than
// 3 distinct points; a self-intersecting or otherwise invalid polygon (GEOS, when GDAL has it);
// an OpenStreetMap element already read from another file (the same layer and osm_id: overlapping
// extracts). Consecutive duplicate points are removed and reported, and the feature is kept.
// File-level failures, after which the file's contents cannot be trusted, go to `fileErrors`
// (the import fails on them): a read error of the driver (a truncated or malformed file, an XML
// entity bomb), a layer with no CRS or one OGR cannot transform to WGS84, a layer whose every
// coordinate is outside longitude/latitude ranges (projected data that does not say so), an
// empty file. A file OGR cannot open throws VectorImportError naming the file and the reason.

#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include <glm/vec2.hpp>

#include "io/feature_mapping.h"

namespace lacet {

class VectorImportError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SourceRef {
    std::string file, layer;
    std::int64_t fid = -1;
    std::string str() const { return file + (layer.empty() ? "" : " layer '" + layer + "'") + (fid >= 0 ? " feature " + std::to_string(fid) : ""); }
};

struct FeatureProblem {
    SourceRef source;
    std::string reason;
    bool skipped = true;  // false: repaired and kept (duplicate points)
};

struct RawLine {
    std::size_t rule = 0;
    std::vector<glm::dvec2> lonLat;
    bool inMulti = false;     // a part of a multi-line feature (an OSM route or waterway relation)
    std::uint16_t flags = 0;  // CurveFlag
    std::map<std::string, std::string> kept;
    SourceRef source;
};

struct RawArea {
    std::size_t rule = 0;
    std::vector<std::vector<glm::dvec2>> rings;  // [0] outer, others holes; closed (first == last)
    std::map<std::string, std::string> kept;
    SourceRef source;
};

struct VectorData {
    std::vector<RawLine> lines;
    std::vector<RawArea> areas;
    std::vector<FeatureProblem> problems;
    std::vector<std::string> fileErrors;  // "file: reason", each a reason to fail the import
    std::size_t featuresRead = 0;
    std::size_t unmapped = 0;  // features no rule matched (not problems)
    std::size_t duplicateOsmIds = 0;  // OSM elements read before from another file, skipped
    // Set when several files are read into this: then OSM elements are keyed by layer and id
    // ("lines:osm_id:123", kept in osmIds) so that overlapping extracts give each element once.
    bool dedupOsmIds = false;
    std::unordered_set<std::string> osmIds;
    // An import out of core (io/vector_spill.h) sets these: kept features go to the sinks instead
    // of `lines` and `areas`, and the OSM keys of dedupOsmIds to firstOsmKey (true: the first time).
    std::function<void(RawLine&&)> lineSink;
    std::function<void(RawArea&&)> areaSink;
    std::function<bool(const std::string&)> firstOsmKey;
    std::size_t linesKept = 0, areasKept = 0;  // counted either way
    // Problems past maxProblems are counted by reason, not listed (an import out of core keeps its
    // memory bounded on an extract with millions of them).
    std::size_t maxProblems = std::numeric_limits<std::size_t>::max();
    std::map<std::string, std::size_t> problemsNotListed;
};

// Appends the features of one file.
void readVectors(const std::string& path, const FeatureMapping& mapping, VectorData& out);

}  // namespace lacet
