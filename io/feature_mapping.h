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
// field ("key"=>"value" pairs) too. bridge=yes and tunnel=yes set the curve flags, and
// junction=roundabout sets kRoundabout (the ring is kept as it is).
//
// The file is checked strictly, since a typo that was silently ignored would import a scene that
// looks right and is not: every object takes only the keys above, and no key twice.
//   layers  required, a non-empty array; each layer: "name" (a non-empty string, unique) and "kind"
//           (one of the kinds above), both required.
//   rules   required, a non-empty array; each rule: "geometry", "match" and "layer" required;
//           "match" a non-empty object whose values are non-empty arrays of non-empty strings;
//           "layer" the name of a layer, of kind roads or rivers for line rules and of any kind
//           but roads for area rules (areas of a rivers layer are large rivers' water, §4.1); "class" an integer in 0..65535 (default 0); "w", line rules only,
//           the width in metres, 0..10000 (default 0); "wf" the footprint width (of a line) or
//           border width (of an area) in metres, w..10000 (default w).
//   keep    optional, an array of distinct non-empty strings.
// Every MappingError names the source, the JSON path of the value and what is wrong with it:
//   mapping.json: rules[3].class: must be an integer in 0..65535, got 3.7

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

// The default: OSM highway=* (widths by class), waterway=river|stream|canal; river areas
// (natural=water with water=river|stream|canal, and waterway=riverbank) in the rivers layer;
// other natural=water and landuse=reservoir as lakes; landuse=farmland|meadow|forest, natural=wood.
FeatureMapping defaultMapping();
// Reads a mapping file; MappingError names the file and what is wrong (it cannot be read, with the
// system's reason; bad JSON; a value breaking the rules above, with its JSON path).
FeatureMapping loadMapping(const std::string& path);
// Parses mapping JSON; `source` (a file name) starts every error message.
FeatureMapping parseMapping(const std::string& json, const std::string& source);

// Parses OSM's other_tags ("k"=>"v","k2"=>"v2") into `out`; malformed pairs are ignored.
void parseOtherTags(const std::string& tags, std::map<std::string, std::string>& out);

}  // namespace lacet
