#include "io/feature_mapping.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <memory>
#include <set>
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
    {"geometry": "area", "match": {"natural": ["water"], "water": ["river"]}, "layer": "rivers", "class": 0, "wf": 8},
    {"geometry": "area", "match": {"natural": ["water"], "water": ["stream"]}, "layer": "rivers", "class": 1, "wf": 4},
    {"geometry": "area", "match": {"natural": ["water"], "water": ["canal"]}, "layer": "rivers", "class": 2, "wf": 6},
    {"geometry": "area", "match": {"waterway": ["riverbank"]}, "layer": "rivers", "class": 0, "wf": 8},
    {"geometry": "area", "match": {"natural": ["water"]}, "layer": "lakes", "class": 0, "wf": 8},
    {"geometry": "area", "match": {"landuse": ["reservoir"]}, "layer": "lakes", "class": 1, "wf": 8},
    {"geometry": "area", "match": {"landuse": ["farmland"]}, "layer": "fields", "class": 0, "wf": 2},
    {"geometry": "area", "match": {"landuse": ["meadow"]}, "layer": "fields", "class": 3, "wf": 2},
    {"geometry": "area", "match": {"landuse": ["forest"]}, "layer": "forests", "class": 0, "wf": 5},
    {"geometry": "area", "match": {"natural": ["wood"]}, "layer": "forests", "class": 1, "wf": 5}
  ],
  "keep": ["bridge", "tunnel", "layer", "name"]
})json";

using nlohmann::json;

// The layer kinds a mapping names, in the order messages list them.
const std::vector<std::pair<std::string, LayerKind>>& layerKinds() {
    static const std::vector<std::pair<std::string, LayerKind>> kinds = {
        {"roads", LayerKind::Roads}, {"rivers", LayerKind::Rivers},   {"lakes", LayerKind::Lakes},
        {"fields", LayerKind::Fields}, {"forests", LayerKind::Forests}, {"other", LayerKind::Other}};
    return kinds;
}

constexpr double kMaxWidth = 10000.0;  // metres: wider is a unit mistake (cm, feet...), not a road

// JSON paths as messages write them: rules[3].class, match["addr street"].
std::string member(const std::string& path, const std::string& key) {
    const bool plain = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-';
    });
    if (plain) return path.empty() ? key : path + "." + key;
    return path + "[" + json(key).dump() + "]";
}
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// A value as a message quotes it after "got": scalars as written, containers by their type.
std::string shown(const json& v) {
    if (v.is_object()) return "an object";
    if (v.is_array()) return "an array";
    std::string s = v.dump();
    constexpr std::size_t kMaxShown = 60;
    if (s.size() > kMaxShown) s = s.substr(0, kMaxShown) + "...";
    return s;
}

std::string joined(const std::vector<std::string>& words) {
    std::string s;
    for (const std::string& w : words) s += (s.empty() ? "" : ", ") + w;
    return s;
}

// The checks of the format, each throwing a MappingError that names the source and the path.
class Checker {
public:
    explicit Checker(std::string source) : source_(std::move(source)) {}

    [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
        throw MappingError(source_ + ": " + (path.empty() ? "" : path + ": ") + reason);
    }

    // `v` is an object whose keys are all in `allowed`, holding every key of `required`.
    void object(const json& v, const std::string& path, const std::vector<std::string>& allowed,
                const std::vector<std::string>& required) const {
        if (!v.is_object()) fail(path, "must be an object, got " + shown(v));
        for (const auto& [key, value] : v.items())
            if (std::find(allowed.begin(), allowed.end(), key) == allowed.end())
                fail(path, "unknown key " + json(key).dump() + " (allowed: " + joined(allowed) + ")");
        for (const std::string& key : required)
            if (!v.contains(key)) fail(path, "missing required key \"" + key + "\"");
    }

    void array(const json& v, const std::string& path, bool nonEmpty) const {
        if (!v.is_array() || (nonEmpty && v.empty()))
            fail(path, std::string(nonEmpty ? "must be a non-empty array" : "must be an array") + ", got " + shown(v));
    }

    const std::string& string(const json& v, const std::string& path) const {
        if (!v.is_string()) fail(path, "must be a string, got " + shown(v));
        if (v.get_ref<const std::string&>().empty()) fail(path, "must not be empty");
        return v.get_ref<const std::string&>();
    }

    // A number with no fractional part (as JSON Schema's "integer": 3.0 is one) in lo..hi.
    std::int64_t integer(const json& v, const std::string& path, std::int64_t lo, std::int64_t hi) const {
        const double d = v.is_number() ? v.get<double>() : 0.0;
        if (!v.is_number() || d != std::floor(d) || d < double(lo) || d > double(hi))
            fail(path, "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + shown(v));
        return std::int64_t(d);
    }

    // A finite number in lo..hi; `range` says the range in the user's words.
    double number(const json& v, const std::string& path, double lo, double hi, const std::string& range) const {
        const double d = v.is_number() ? v.get<double>() : 0.0;
        if (!v.is_number() || !std::isfinite(d) || d < lo || d > hi) fail(path, "must be a number in " + range + ", got " + shown(v));
        return d;
    }

private:
    std::string source_;
};

// Parses JSON, refusing an object that repeats a key (the parser would keep the last one and
// silently drop the others).
json parseJson(const std::string& text, const Checker& check) {
    struct Container {
        bool array = false;
        std::size_t index = 0;  // of the element being read, in an array
        std::string key;        // of the member being read, in an object
        std::set<std::string> keys;
    };
    std::vector<Container> open;
    const auto path = [&] {
        std::string p;
        for (const Container& c : open) p = c.array ? element(p, c.index) : member(p, c.key);
        return p;
    };
    const auto valueRead = [&] {
        if (!open.empty() && open.back().array) ++open.back().index;
    };
    const json::parser_callback_t callback = [&](int, json::parse_event_t event, json& parsed) {
        switch (event) {
        case json::parse_event_t::object_start: open.push_back({}); break;
        case json::parse_event_t::array_start: open.push_back({true, 0, {}, {}}); break;
        case json::parse_event_t::key:
            open.back().key = parsed.get<std::string>();
            if (!open.back().keys.insert(open.back().key).second) check.fail(path(), "key repeated in its object (each key may appear once)");
            break;
        case json::parse_event_t::object_end:
        case json::parse_event_t::array_end:
            open.pop_back();
            valueRead();
            break;
        case json::parse_event_t::value: valueRead(); break;
        }
        return true;
    };
    try {
        return json::parse(text, callback);
    } catch (const json::exception& e) {
        check.fail("", std::string("not valid JSON (") + e.what() + ")");
    }
}

MappingLayer parseLayer(const json& v, const std::string& path, const Checker& check) {
    check.object(v, path, {"name", "kind"}, {"name", "kind"});
    MappingLayer layer;
    layer.name = check.string(v["name"], member(path, "name"));
    const std::string& kind = check.string(v["kind"], member(path, "kind"));
    const auto& kinds = layerKinds();
    const auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& k) { return k.first == kind; });
    if (it == kinds.end()) {
        std::vector<std::string> names;
        for (const auto& k : kinds) names.push_back(k.first);
        check.fail(member(path, "kind"), "unknown layer kind " + json(kind).dump() + " (allowed: " + joined(names) + ")");
    }
    layer.kind = it->second;
    return layer;
}

MappingRule parseRule(const json& v, const std::string& path, const std::vector<MappingLayer>& layers, const Checker& check) {
    check.object(v, path, {"geometry", "match", "layer", "class", "w", "wf"}, {"geometry", "match", "layer"});
    MappingRule rule;
    const std::string& geometry = check.string(v["geometry"], member(path, "geometry"));
    if (geometry != "line" && geometry != "area") check.fail(member(path, "geometry"), "must be \"line\" or \"area\", got " + shown(v["geometry"]));
    rule.geometry = geometry == "line" ? GeometryKind::Line : GeometryKind::Area;

    const std::string matchPath = member(path, "match");
    const json& match = v["match"];
    if (!match.is_object() || match.empty())
        check.fail(matchPath, "must be a non-empty object of attribute: [values], got " + shown(match));
    for (const auto& [key, values] : match.items()) {
        const std::string keyPath = member(matchPath, key);
        if (key.empty()) check.fail(keyPath, "an attribute name must not be empty");
        if (!values.is_array() || values.empty()) check.fail(keyPath, "must be a non-empty array of strings, got " + shown(values));
        for (std::size_t i = 0; i < values.size(); ++i) rule.match[key].push_back(check.string(values[i], element(keyPath, i)));
    }

    const std::string layerPath = member(path, "layer");
    const std::string& layer = check.string(v["layer"], layerPath);
    const auto it = std::find_if(layers.begin(), layers.end(), [&](const MappingLayer& l) { return l.name == layer; });
    if (it == layers.end()) {
        std::vector<std::string> names;
        for (const MappingLayer& l : layers) names.push_back(l.name);
        check.fail(layerPath, "unknown layer " + json(layer).dump() + " (layers: " + joined(names) + ")");
    }
    rule.layer = std::size_t(it - layers.begin());
    // Rivers take both: lines (rivers, streams) and areas (a large river's water, §4.1).
    const bool takesLines = it->kind == LayerKind::Roads || it->kind == LayerKind::Rivers;
    const bool takesAreas = it->kind != LayerKind::Roads;
    if (rule.geometry == GeometryKind::Line ? !takesLines : !takesAreas)
        check.fail(layerPath, geometry + " features cannot go to layer " + json(layer).dump() + " of kind " + std::string(toString(it->kind)) +
                                  (rule.geometry == GeometryKind::Area ? " (area rules need a rivers, lakes, fields, forests or other layer)"
                                                                       : " (line rules need a roads or rivers layer)"));

    if (v.contains("class")) rule.cls = std::uint16_t(check.integer(v["class"], member(path, "class"), 0, 0xffff));
    double w = 0.0;
    if (v.contains("w")) {
        if (rule.geometry == GeometryKind::Area) check.fail(member(path, "w"), "area rules take no width w (an area's border width is wf)");
        w = check.number(v["w"], member(path, "w"), 0.0, kMaxWidth, "0..10000 (metres)");
    }
    std::ostringstream wfRange;
    wfRange << (w == 0.0 ? "0" : "w (") << std::setprecision(15);
    if (w != 0.0) wfRange << w << ")";
    wfRange << "..10000 (metres)";
    const double wf = v.contains("wf") ? check.number(v["wf"], member(path, "wf"), w, kMaxWidth, wfRange.str()) : w;
    rule.w = float(w);
    rule.wf = float(wf);
    return rule;
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
    const Checker check(source);
    const json j = parseJson(text, check);
    check.object(j, "", {"layers", "rules", "keep"}, {"layers", "rules"});
    FeatureMapping m;

    check.array(j["layers"], "layers", true);
    for (std::size_t i = 0; i < j["layers"].size(); ++i) {
        const std::string path = element("layers", i);
        MappingLayer layer = parseLayer(j["layers"][i], path, check);
        for (std::size_t k = 0; k < m.layers.size(); ++k)
            if (m.layers[k].name == layer.name)
                check.fail(member(path, "name"), "duplicate layer name " + json(layer.name).dump() + " (also " + member(element("layers", k), "name") + ")");
        m.layers.push_back(std::move(layer));
    }

    check.array(j["rules"], "rules", true);
    for (std::size_t i = 0; i < j["rules"].size(); ++i) m.rules.push_back(parseRule(j["rules"][i], element("rules", i), m.layers, check));

    if (j.contains("keep")) {
        check.array(j["keep"], "keep", false);
        for (std::size_t i = 0; i < j["keep"].size(); ++i) {
            const std::string& key = check.string(j["keep"][i], element("keep", i));
            if (std::find(m.keep.begin(), m.keep.end(), key) != m.keep.end())
                check.fail(element("keep", i), "duplicate attribute " + json(key).dump());
            m.keep.push_back(key);
        }
    }
    return m;
}

FeatureMapping defaultMapping() { return parseMapping(kDefaultMapping, "default mapping"); }

FeatureMapping loadMapping(const std::string& path) {
    // C stdio rather than a stream: errno then says why the file could not be opened or read.
    struct Close {
        void operator()(std::FILE* f) const { std::fclose(f); }
    };
    const std::unique_ptr<std::FILE, Close> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw MappingError(path + ": cannot open the mapping file: " + std::strerror(errno));
    std::string text;
    char buffer[1 << 16];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) text.append(buffer, n);
    if (std::ferror(file.get())) throw MappingError(path + ": cannot read the mapping file: " + std::strerror(errno));
    return parseMapping(text, path);
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
