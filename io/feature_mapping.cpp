#include "io/feature_mapping.h"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace lacet {
namespace {

constexpr const char* kDefaultMapping = R"json({
  "layers": [
    {"name": "roads", "kind": "roads"},
    {"name": "rivers", "kind": "rivers"},
    {"name": "lakes", "kind": "lakes"},
    {"name": "fields", "kind": "fields"},
    {"name": "forests", "kind": "forests"}
  ],
  "rules": [
    {"geometry": "line", "match": {"highway": ["motorway", "trunk", "primary"]}, "layer": "roads", "class": 0, "w": 8, "wf": 16},
    {"geometry": "line", "match": {"highway": ["motorway_link", "trunk_link", "primary_link", "secondary", "secondary_link"]}, "layer": "roads", "class": 0, "w": 7, "wf": 14},
    {"geometry": "line", "match": {"highway": ["tertiary", "tertiary_link"]}, "layer": "roads", "class": 1, "w": 6, "wf": 12},
    {"geometry": "line", "match": {"highway": ["unclassified", "residential", "living_street", "service"]}, "layer": "roads", "class": 1, "w": 5, "wf": 10},
    {"geometry": "line", "match": {"highway": ["track"]}, "layer": "roads", "class": 2, "w": 3, "wf": 6},
    {"geometry": "line", "match": {"waterway": ["river"]}, "layer": "rivers", "class": 0, "w": 10, "wf": 20},
    {"geometry": "line", "match": {"waterway": ["canal"]}, "layer": "rivers", "class": 2, "w": 6, "wf": 12},
    {"geometry": "line", "match": {"waterway": ["stream"]}, "layer": "rivers", "class": 1, "w": 2, "wf": 6},
    {"geometry": "area", "match": {"natural": ["water"]}, "layer": "lakes", "class": 0, "wf": 8},
    {"geometry": "area", "match": {"landuse": ["reservoir"]}, "layer": "lakes", "class": 1, "wf": 8},
    {"geometry": "area", "match": {"landuse": ["farmland"]}, "layer": "fields", "class": 0, "wf": 2},
    {"geometry": "area", "match": {"landuse": ["meadow"]}, "layer": "fields", "class": 3, "wf": 2},
    {"geometry": "area", "match": {"landuse": ["forest"]}, "layer": "forests", "class": 0, "wf": 5},
    {"geometry": "area", "match": {"natural": ["wood"]}, "layer": "forests", "class": 1, "wf": 5}
  ],
  "keep": ["bridge", "tunnel", "layer", "name"]
})json";

LayerKind kindOf(const std::string& s, const std::string& source) {
    static const std::map<std::string, LayerKind> kinds = {{"roads", LayerKind::Roads},   {"rivers", LayerKind::Rivers},
                                                            {"lakes", LayerKind::Lakes},   {"fields", LayerKind::Fields},
                                                            {"forests", LayerKind::Forests}, {"other", LayerKind::Other}};
    const auto it = kinds.find(s);
    if (it == kinds.end()) throw MappingError(source + ": unknown layer kind '" + s + "' (roads, rivers, lakes, fields, forests, other)");
    return it->second;
}

}  // namespace

std::optional<std::size_t> FeatureMapping::match(const std::map<std::string, std::string>& attributes, GeometryKind geometry) const {
    for (std::size_t r = 0; r < rules.size(); ++r) {
        const MappingRule& rule = rules[r];
        if (rule.geometry != geometry) continue;
        bool all = true;
        for (const auto& [key, values] : rule.match) {
            const auto it = attributes.find(key);
            if (it == attributes.end() || it->second.empty()) {
                all = false;
                break;
            }
            bool one = false;
            for (const std::string& v : values) one = one || v == "*" || v == it->second;
            if (!one) {
                all = false;
                break;
            }
        }
        if (all) return r;
    }
    return std::nullopt;
}

FeatureMapping parseMapping(const std::string& text, const std::string& source) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw MappingError(source + ": not valid JSON (" + e.what() + ")");
    }
    FeatureMapping m;
    try {
        if (!j.contains("layers") || !j["layers"].is_array() || j["layers"].empty())
            throw MappingError(source + ": \"layers\" must be a non-empty array");
        for (const auto& l : j["layers"]) m.layers.push_back({l.at("name").get<std::string>(), kindOf(l.at("kind").get<std::string>(), source)});
        if (!j.contains("rules") || !j["rules"].is_array()) throw MappingError(source + ": \"rules\" must be an array");
        for (std::size_t r = 0; r < j["rules"].size(); ++r) {
            const auto& jr = j["rules"][r];
            const std::string where = source + ": rule " + std::to_string(r);
            MappingRule rule;
            const std::string g = jr.at("geometry").get<std::string>();
            if (g != "line" && g != "area") throw MappingError(where + ": geometry must be \"line\" or \"area\"");
            rule.geometry = g == "line" ? GeometryKind::Line : GeometryKind::Area;
            for (const auto& [key, values] : jr.at("match").items()) rule.match[key] = values.get<std::vector<std::string>>();
            if (rule.match.empty()) throw MappingError(where + ": \"match\" is empty");
            const std::string layer = jr.at("layer").get<std::string>();
            const auto it = std::find_if(m.layers.begin(), m.layers.end(), [&](const MappingLayer& ml) { return ml.name == layer; });
            if (it == m.layers.end()) throw MappingError(where + ": unknown layer '" + layer + "'");
            rule.layer = std::size_t(it - m.layers.begin());
            const std::int64_t cls = jr.value("class", std::int64_t(0));
            if (cls < 0 || cls > 0xffff) throw MappingError(where + ": class must be in 0..65535");
            rule.cls = std::uint16_t(cls);
            const double w = jr.value("w", 0.0), wf = jr.value("wf", w);
            constexpr double kMaxWidth = 10000.0;  // metres
            if (!(w >= 0.0) || !(wf >= w) || !(wf <= kMaxWidth))
                throw MappingError(where + ": widths must satisfy 0 <= w <= wf <= 10000 m");
            rule.w = float(w);
            rule.wf = float(wf);
            const LayerKind kind = m.layers[rule.layer].kind;
            const bool curveLayer = kind == LayerKind::Roads || kind == LayerKind::Rivers;
            if (curveLayer != (rule.geometry == GeometryKind::Line))
                throw MappingError(where + ": " + g + " features cannot go to a layer of kind " + std::string(toString(kind)));
            m.rules.push_back(std::move(rule));
        }
        if (j.contains("keep")) m.keep = j["keep"].get<std::vector<std::string>>();
    } catch (const nlohmann::json::exception& e) {
        throw MappingError(source + ": " + e.what());
    }
    return m;
}

FeatureMapping defaultMapping() { return parseMapping(kDefaultMapping, "default mapping"); }

FeatureMapping loadMapping(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw MappingError(path + ": cannot open the mapping file");
    std::stringstream ss;
    ss << in.rdbuf();
    return parseMapping(ss.str(), path);
}

void parseOtherTags(const std::string& tags, std::map<std::string, std::string>& out) {
    // "k"=>"v","k2"=>"v2" with \" escapes inside strings.
    std::size_t i = 0;
    auto quoted = [&](std::string& s) {
        if (i >= tags.size() || tags[i] != '"') return false;
        ++i;
        s.clear();
        while (i < tags.size() && tags[i] != '"') {
            if (tags[i] == '\\' && i + 1 < tags.size()) ++i;
            s += tags[i++];
        }
        if (i >= tags.size()) return false;
        ++i;
        return true;
    };
    while (i < tags.size()) {
        std::string k, v;
        if (!quoted(k)) return;
        if (tags.compare(i, 2, "=>") != 0) return;
        i += 2;
        if (!quoted(v)) return;
        out.emplace(k, v);
        if (i < tags.size() && tags[i] == ',') ++i;
    }
}

}  // namespace lacet
