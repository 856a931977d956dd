// The mapping file's strict checks: every kind of fault is refused with a message naming the
// source, the JSON path of the faulty value and the reason; the default mapping and a valid
// custom one parse.
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <gtest/gtest.h>

#include "io/feature_mapping.h"

namespace lacet {
namespace {

// A valid mapping with one layer of each family and one rule of each geometry; the faults below
// change one part of it.
std::string mappingWith(const std::string& layers, const std::string& rules, const std::string& rest = "") {
    return R"({"layers": )" + layers + R"(, "rules": )" + rules + rest + "}";
}
const std::string kLayers = R"([{"name": "roads", "kind": "roads"}, {"name": "fields", "kind": "fields"}])";
const std::string kLineRule = R"({"geometry": "line", "match": {"highway": ["primary"]}, "layer": "roads", "class": 1, "w": 6, "wf": 12})";
const std::string kAreaRule = R"({"geometry": "area", "match": {"landuse": ["farmland"]}, "layer": "fields", "wf": 2})";
std::string rulesWith(const std::string& rule) { return "[" + kLineRule + ", " + kAreaRule + ", " + rule + "]"; }

struct Fault {
    std::string name;      // of the test
    std::string json;      // the mapping
    std::string path;      // the JSON path the message must name ("" for the whole file)
    std::string reason;    // a part of the reason the message must give
};

std::ostream& operator<<(std::ostream& os, const Fault& f) { return os << f.name; }

class FeatureMappingFault : public testing::TestWithParam<Fault> {};

TEST_P(FeatureMappingFault, IsRefusedNamingThePathAndTheReason) {
    const Fault& f = GetParam();
    try {
        parseMapping(f.json, "mapping.json");
        FAIL() << "accepted: " << f.json;
    } catch (const MappingError& e) {
        const std::string message = e.what();
        const std::string prefix = "mapping.json: " + (f.path.empty() ? "" : f.path + ": ");
        EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
        EXPECT_NE(message.find(f.reason), std::string::npos) << message;
    }
}

const Fault kFaults[] = {
    {"NotJson", R"({"layers": [)", "", "not valid JSON"},
    {"TopLevelNotAnObject", "[1, 2]", "", "must be an object, got an array"},
    {"UnknownTopLevelKey", mappingWith(kLayers, rulesWith(kAreaRule), R"(, "lyers": [])"), "",
     R"(unknown key "lyers" (allowed: layers, rules, keep))"},
    {"MissingRules", R"({"layers": )" + kLayers + "}", "", R"(missing required key "rules")"},
    {"RepeatedKey", mappingWith(kLayers, R"([{"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "w": 5, "w": 7}])"),
     "rules[0].w", "key repeated in its object"},
    {"RepeatedKeyDeepInArrays", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"], "a": ["c"]}, "layer": "roads"})")),
     "rules[2].match.a", "key repeated in its object"},
    {"LayersEmpty", mappingWith("[]", rulesWith(kAreaRule)), "layers", "must be a non-empty array, got an array"},
    {"LayersNotAnArray", mappingWith(R"({"name": "roads"})", rulesWith(kAreaRule)), "layers", "must be a non-empty array, got an object"},
    {"LayerNameNotAString", mappingWith(R"([{"name": "roads", "kind": "roads"}, {"name": 3, "kind": "fields"}])", "[" + kLineRule + "]"),
     "layers[1].name", "must be a string, got 3"},
    {"LayerNameEmpty", mappingWith(R"([{"name": "", "kind": "roads"}])", "[" + kLineRule + "]"), "layers[0].name", "must not be empty"},
    {"LayerMissingKind", mappingWith(R"([{"name": "roads"}])", "[" + kLineRule + "]"), "layers[0]", R"(missing required key "kind")"},
    {"UnknownLayerKind", mappingWith(R"([{"name": "roads", "kind": "motorways"}])", "[" + kLineRule + "]"), "layers[0].kind",
     R"(unknown layer kind "motorways" (allowed: roads, rivers, lakes, fields, forests, other))"},
    {"UnknownLayerKey", mappingWith(R"([{"name": "roads", "kind": "roads", "colour": "red"}])", "[" + kLineRule + "]"), "layers[0]",
     R"(unknown key "colour" (allowed: name, kind))"},
    {"DuplicateLayerName",
     mappingWith(R"([{"name": "roads", "kind": "roads"}, {"name": "fields", "kind": "fields"}, {"name": "roads", "kind": "rivers"}])", "[" + kLineRule + "]"),
     "layers[2].name", R"(duplicate layer name "roads" (also layers[0].name))"},
    {"RulesEmpty", mappingWith(kLayers, "[]"), "rules", "must be a non-empty array"},
    {"RuleNotAnObject", mappingWith(kLayers, rulesWith(R"("line")")), "rules[2]", R"(must be an object, got "line")"},
    {"UnknownRuleKey", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "wdith": 5})")),
     "rules[2]", R"(unknown key "wdith" (allowed: geometry, match, layer, class, w, wf))"},
    {"RuleMissingLayer", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}})")), "rules[2]",
     R"(missing required key "layer")"},
    {"BadGeometry", mappingWith(kLayers, rulesWith(R"({"geometry": "point", "match": {"a": ["b"]}, "layer": "roads"})")),
     "rules[2].geometry", R"(must be "line" or "area", got "point")"},
    {"MatchEmpty", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {}, "layer": "roads"})")), "rules[2].match",
     "must be a non-empty object"},
    {"MatchValueNotAnArray", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"highway": "primary"}, "layer": "roads"})")),
     "rules[2].match.highway", R"(must be a non-empty array of strings, got "primary")"},
    {"MatchValueEmptyArray", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"highway": []}, "layer": "roads"})")),
     "rules[2].match.highway", "must be a non-empty array of strings, got an array"},
    {"MatchValueNotAString", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"highway": ["primary", 2]}, "layer": "roads"})")),
     "rules[2].match.highway[1]", "must be a string, got 2"},
    {"MatchKeyOddCharacters", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"addr street": [""]}, "layer": "roads"})")),
     R"(rules[2].match["addr street"][0])", "must not be empty"},
    {"UnknownLayerInRule", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "road"})")),
     "rules[2].layer", R"(unknown layer "road" (layers: roads, fields))"},
    {"LineRuleToAnAreaLayer", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "fields"})")),
     "rules[2].layer", R"(line features cannot go to layer "fields" of kind fields (line rules need a roads or rivers layer))"},
    {"AreaRuleToALineLayer", mappingWith(kLayers, rulesWith(R"({"geometry": "area", "match": {"a": ["b"]}, "layer": "roads"})")),
     "rules[2].layer", R"(area features cannot go to layer "roads" of kind roads)"},
    {"ClassNotAnInteger", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "class": 3.7})")),
     "rules[2].class", "must be an integer in 0..65535, got 3.7"},
    {"ClassOutOfRange", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "class": 65536})")),
     "rules[2].class", "must be an integer in 0..65535, got 65536"},
    {"ClassNegative", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "class": -1})")),
     "rules[2].class", "must be an integer in 0..65535, got -1"},
    {"ClassAString", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "class": "1"})")),
     "rules[2].class", R"(must be an integer in 0..65535, got "1")"},
    {"WidthNegative", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "w": -2})")),
     "rules[2].w", "must be a number in 0..10000 (metres), got -2"},
    {"WidthTooLarge", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "w": 7e4})")),
     "rules[2].w", "must be a number in 0..10000 (metres), got 70000.0"},
    {"WidthAString", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "w": "7"})")),
     "rules[2].w", R"(must be a number in 0..10000 (metres), got "7")"},
    {"FootprintNarrowerThanWidth", mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "w": 7, "wf": 5})")),
     "rules[2].wf", "must be a number in w (7)..10000 (metres), got 5"},
    {"WidthOnAnAreaRule", mappingWith(kLayers, rulesWith(R"({"geometry": "area", "match": {"a": ["b"]}, "layer": "fields", "w": 3})")),
     "rules[2].w", "area rules take no width w"},
    {"KeepNotAnArray", mappingWith(kLayers, rulesWith(kAreaRule), R"(, "keep": "name")"), "keep", R"(must be an array, got "name")"},
    {"KeepElementNotAString", mappingWith(kLayers, rulesWith(kAreaRule), R"(, "keep": ["name", 1])"), "keep[1]", "must be a string, got 1"},
    {"KeepDuplicate", mappingWith(kLayers, rulesWith(kAreaRule), R"(, "keep": ["name", "bridge", "name"])"), "keep[2]",
     R"(duplicate attribute "name")"},
};

INSTANTIATE_TEST_SUITE_P(FeatureMapping, FeatureMappingFault, testing::ValuesIn(kFaults),
                         [](const testing::TestParamInfo<Fault>& p) { return p.param.name; });

TEST(FeatureMapping, DefaultMappingParses) {
    const FeatureMapping m = defaultMapping();
    EXPECT_EQ(m.layers.size(), 5u);
    EXPECT_EQ(m.rules.size(), 18u);
    EXPECT_EQ(m.keep, (std::vector<std::string>{"bridge", "tunnel", "layer", "name"}));
    // River polygons are areas of the rivers layer; other water polygons are lakes.
    auto areaLayer = [&](const std::map<std::string, std::string>& tags) {
        const auto rule = m.match(tags, GeometryKind::Area);
        return rule ? m.layers[m.rules[*rule].layer].kind : LayerKind::Other;
    };
    EXPECT_EQ(areaLayer({{"natural", "water"}, {"water", "river"}}), LayerKind::Rivers);
    EXPECT_EQ(areaLayer({{"waterway", "riverbank"}}), LayerKind::Rivers);
    EXPECT_EQ(areaLayer({{"natural", "water"}, {"water", "lake"}}), LayerKind::Lakes);
    EXPECT_EQ(areaLayer({{"natural", "water"}}), LayerKind::Lakes);
}

TEST(FeatureMapping, ValidCustomMappingParses) {
    const FeatureMapping m = parseMapping(
        mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"highway": ["*"], "addr:street": ["a", "b"]}, "layer": "roads", "class": 2.0, "w": 3.5})"),
                    R"(, "keep": ["name"])"),
        "custom.json");
    ASSERT_EQ(m.layers.size(), 2u);
    EXPECT_EQ(m.layers[1].name, "fields");
    EXPECT_EQ(m.layers[1].kind, LayerKind::Fields);
    ASSERT_EQ(m.rules.size(), 3u);
    EXPECT_EQ(m.rules[0].cls, 1);
    EXPECT_EQ(m.rules[0].w, 6.0f);
    EXPECT_EQ(m.rules[0].wf, 12.0f);
    EXPECT_EQ(m.rules[1].geometry, GeometryKind::Area);
    EXPECT_EQ(m.rules[1].layer, 1u);
    EXPECT_EQ(m.rules[1].cls, 0);  // the default class
    EXPECT_EQ(m.rules[1].w, 0.0f);
    EXPECT_EQ(m.rules[1].wf, 2.0f);
    EXPECT_EQ(m.rules[2].cls, 2);     // 2.0 is an integer
    EXPECT_EQ(m.rules[2].wf, 3.5f);  // wf defaults to w
    EXPECT_EQ(m.rules[2].match.at("addr:street"), (std::vector<std::string>{"a", "b"}));
    EXPECT_TRUE(m.match({{"highway", "path"}, {"addr:street", "b"}}, GeometryKind::Line));
    EXPECT_EQ(m.keep, std::vector<std::string>{"name"});
}

TEST(FeatureMapping, MissingFileSaysSoWithTheSystemReason) {
    try {
        loadMapping("/nonexistent/mapping.json");
        FAIL();
    } catch (const MappingError& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/mapping.json: cannot open the mapping file: No such file or directory");
    }
}

TEST(FeatureMapping, UnreadableFileSaysWhy) {
    const std::string dir = testing::TempDir();  // a directory opens but cannot be read
    try {
        loadMapping(dir);
        FAIL();
    } catch (const MappingError& e) {
        EXPECT_NE(std::string(e.what()).find(dir + ": cannot "), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("Is a directory"), std::string::npos) << e.what();
    }
}

TEST(FeatureMapping, FileErrorsNameTheFile) {
    const auto path = std::filesystem::path(testing::TempDir()) / ("lacet_mapping_" + std::to_string(::getpid()) + ".json");
    std::ofstream(path) << mappingWith(kLayers, rulesWith(R"({"geometry": "line", "match": {"a": ["b"]}, "layer": "roads", "class": 3.7})"));
    try {
        loadMapping(path.string());
        FAIL();
    } catch (const MappingError& e) {
        EXPECT_EQ(std::string(e.what()), path.string() + ": rules[2].class: must be an integer in 0..65535, got 3.7");
    }
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace lacet
