#pragma once
// The mapping from GIS attributes to scene layers (a JSON file, or the default for OSM): which
// features become curves of which layer and class, with which width w and footprint width wf, or
// areas with which class and border width; which attributes are kept.
//
// JSON:
//   { "layers": [ {"name": "roads", "kind": "roads"}, ... ],     // kinds: roads rivers lakes fields forests other
//     "rules": [ {"geometry": "line" | "area",
//                 "match": {"highway": ["primary", "secondary"]},  // every key must match one value ("*": any)
//                 "layer": "roads", "class": 0, "w": 7, "wf": 15}, ... ],
//     "keep": ["bridge", "tunnel", "layer", "name"] }
// The first rule that matches a feature wins; a feature no rule matches is skipped (and counted).
// Attribute values are read from the feature's fields, and for OSM data from its "other_tags"
// field ("key"=>"value" pairs) too. bridge=yes and tunnel=yes set the curve flags.

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/graph.h"

namespace lacet {

class MappingError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

enum class GeometryKind : std::uint8_t { Line, Area };

struct MappingRule {
    GeometryKind geometry = GeometryKind::Line;
    std::map<std::string, std::vector<std::string>> match;
    std::size_t layer = 0;  // index into FeatureMapping::layers
    std::uint16_t cls = 0;
    float w = 0.0f, wf = 0.0f;
};

struct MappingLayer {
    std::string name;
    LayerKind kind = LayerKind::Other;
};

struct FeatureMapping {
    std::vector<MappingLayer> layers;
    std::vector<MappingRule> rules;
    std::vector<std::string> keep;

    // The index of the first rule matching these attributes and geometry, if any.
    std::optional<std::size_t> match(const std::map<std::string, std::string>& attributes, GeometryKind geometry) const;
};

// The default: OSM highway=* (widths by class), waterway=river|stream|canal, natural=water,
// landuse=farmland|meadow|forest, natural=wood.
FeatureMapping defaultMapping();
// Reads a mapping file; MappingError names the file and what is wrong (bad JSON, unknown layer
// kind, a rule naming an unknown layer, wf < w...).
FeatureMapping loadMapping(const std::string& path);
FeatureMapping parseMapping(const std::string& json, const std::string& source);

// Parses OSM's other_tags ("k"=>"v","k2"=>"v2") into `out`; malformed pairs are ignored.
void parseOtherTags(const std::string& tags, std::map<std::string, std::string>& out);

}  // namespace lacet
