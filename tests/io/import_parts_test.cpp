// An import out of core (io/scene_import.h: importSceneToFile with a vector budget or a part
// level): one part gives the scene the import in memory gives, bit for bit; more parts keep every
// junction and area of it and trace the same lines within the fit tolerance, their extra nodes only
// where a way crosses a part border; refusals and failures leave no file behind. The extracts are
// made at test time by scripts/synthetic_osm.py (and Andorra's is used where ../shared has it). The
// spill file of the features (io/vector_spill.h) and the part grid are tested alone too.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <tuple>

#include <cpl_conv.h>
#include <gtest/gtest.h>

#include "io/network_builder.h"
#include "io/scene_file.h"
#include "io/scene_import.h"
#include "io/vector_spill.h"
#include "model/graph.h"
#include "tests/io/gis_fixtures.h"
#include "tests/io/scene_identical.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

// scripts/synthetic_osm.py's extract of `blocks` x `blocks` blocks.
std::string syntheticOsm(const std::filesystem::path& dir, int blocks, int seed) {
    const std::string out = (dir / ("synthetic_" + std::to_string(blocks) + "_" + std::to_string(seed) + ".osm")).string();
    const std::string command = "python3 " + std::string(LACET_SOURCE_DIR) + "/scripts/synthetic_osm.py --blocks " + std::to_string(blocks) +
                                " --seed " + std::to_string(seed) + " --out " + out;
    if (std::system(command.c_str()) != 0) throw std::runtime_error("cannot run: " + command);
    return out;
}

ImportOptions optionsFor(const std::string& vectors) {
    ImportOptions o;
    o.vectors = {vectors};
    return o;
}

std::string andorraPbf() { return std::string(LACET_SOURCE_DIR) + "/../shared/data/andorra/andorra-2021-04-14.osm.pbf"; }

using PointBits = std::pair<std::uint64_t, std::uint64_t>;
PointBits bitsOf(Vec2 p) { return {std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y)}; }

bool isRingCurve(const Layer& l, ElementId c) { return !l.curves[c].areas.empty(); }

// The nodes of a layer's lines (not areas' rings), by point: how many curve ends meet there. Two
// nodes at one point (border nodes of two parts the save did not join) fail the test.
std::map<PointBits, std::size_t> lineNodes(const Layer& l) {
    std::map<PointBits, std::size_t> out;
    for (const Node& n : l.nodes) {
        if (!n.alive || n.curves.empty() || std::all_of(n.curves.begin(), n.curves.end(), [&](ElementId c) { return isRingCurve(l, c); }))
            continue;
        const auto [it, added] = out.emplace(bitsOf(n.p), n.curves.size());
        EXPECT_TRUE(added) << "two nodes at (" << n.p.x << ", " << n.p.y << ")";
    }
    return out;
}

// Points along a layer's line curves (not areas' rings): 16 per Bezier piece.
std::vector<Vec2> linePoints(const Layer& l) {
    std::vector<Vec2> out;
    for (std::size_t c = 0; c < l.curves.size(); ++c) {
        if (!l.curves[c].alive || isRingCurve(l, ElementId(c))) continue;
        out.push_back(l.curves[c].vertices.front().p);
        forEachPiece(l.curves[c].vertices, [&](const BezierPiece& b, std::size_t) {
            for (int i = 1; i <= 16; ++i) out.push_back(evaluate(b, i / 16.0));
        });
    }
    return out;
}

// The largest distance from a point of `from` to the polyline of consecutive points of `to`'s
// curves, through a grid of `cell` metres (both are dense: 16 points a piece).
double largestDistance(const Layer& from, const Layer& to, double cell) {
    std::map<std::pair<long, long>, std::vector<std::pair<Vec2, Vec2>>> grid;
    for (std::size_t c = 0; c < to.curves.size(); ++c) {
        if (!to.curves[c].alive || isRingCurve(to, ElementId(c))) continue;
        Vec2 prev = to.curves[c].vertices.front().p;
        forEachPiece(to.curves[c].vertices, [&](const BezierPiece& b, std::size_t) {
            for (int i = 1; i <= 16; ++i) {
                const Vec2 q = evaluate(b, i / 16.0);
                const Vec2 lo = glm::min(prev, q), hi = glm::max(prev, q);
                for (long y = long(std::floor(lo.y / cell)); y <= long(std::floor(hi.y / cell)); ++y)
                    for (long x = long(std::floor(lo.x / cell)); x <= long(std::floor(hi.x / cell)); ++x) grid[{x, y}].push_back({prev, q});
                prev = q;
            }
        });
    }
    double largest = 0.0;
    for (const Vec2 p : linePoints(from)) {
        double best = 1e300;
        const long cx = long(std::floor(p.x / cell)), cy = long(std::floor(p.y / cell));
        for (long y = cy - 1; y <= cy + 1; ++y)
            for (long x = cx - 1; x <= cx + 1; ++x) {
                const auto it = grid.find({x, y});
                if (it == grid.end()) continue;
                for (const auto& [a, b] : it->second) {
                    const Vec2 d = b - a;
                    const double t = glm::dot(d, d) > 0.0 ? std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0) : 0.0;
                    best = std::min(best, glm::length(p - (a + t * d)));
                }
            }
        largest = std::max(largest, best);
    }
    return largest;
}

// An area as its class, width and the vertices of its loops' curves, for a comparison whatever
// the order of the areas.
using AreaKey = std::tuple<std::uint16_t, std::uint32_t, std::vector<std::vector<PointBits>>>;
std::multiset<AreaKey> areaKeys(const Layer& l) {
    std::multiset<AreaKey> out;
    for (const Area& a : l.areas) {
        if (!a.alive) continue;
        std::vector<std::vector<PointBits>> loops;
        for (const auto& loop : a.loops)
            for (const AreaEdge& e : loop) {
                loops.emplace_back();
                for (const Vertex& v : l.curves[e.curve].vertices) loops.back().push_back(bitsOf(v.p));
            }
        out.insert({a.cls, std::bit_cast<std::uint32_t>(a.wf), loops});
    }
    return out;
}

// Every (key, value) pair the kept attributes give a layer's curves or its areas.
std::set<std::tuple<LayerId, ElementKind, std::string, std::string>> attributePairs(const SceneDocument& d) {
    std::set<std::tuple<LayerId, ElementKind, std::string, std::string>> out;
    for (const ElementAttribute& a : d.attributes) out.insert({a.layer, a.kind, a.key, a.value});
    return out;
}

// The scene of an import in parts against the import in memory: the same areas and attributes,
// every junction kept with its curves, extra nodes only where curves continue (two curves), at
// most the border nodes the import reported, and the same lines within twice the fit tolerance.
void expectSameNetwork(const SceneDocument& memory, const SceneDocument& parts, const ImportReport& report, double tolerance) {
    ASSERT_EQ(memory.scene.layers.size(), parts.scene.layers.size());
    EXPECT_EQ(attributePairs(memory), attributePairs(parts));
    std::size_t extra = 0;
    for (std::size_t l = 0; l < memory.scene.layers.size(); ++l) {
        const Layer& m = memory.scene.layers[l];
        const Layer& p = parts.scene.layers[l];
        SCOPED_TRACE("layer " + m.name);
        EXPECT_EQ(areaKeys(m), areaKeys(p));
        const auto mNodes = lineNodes(m), pNodes = lineNodes(p);
        for (const auto& [point, ends] : mNodes) {
            const auto it = pNodes.find(point);
            ASSERT_NE(it, pNodes.end()) << "a node of the import in memory is missing";
            EXPECT_EQ(it->second, ends) << "a node's curve ends differ";
        }
        for (const auto& [point, ends] : pNodes)
            if (!mNodes.contains(point)) {
                ++extra;
                EXPECT_EQ(ends, 2u) << "a node the import in memory has not, where no chain continues";
            }
        EXPECT_LE(largestDistance(p, m, 100.0), 2.0 * tolerance + 1e-6);
        EXPECT_LE(largestDistance(m, p, 100.0), 2.0 * tolerance + 1e-6);
    }
    EXPECT_LE(extra, report.borderNodes);
    EXPECT_LE(report.network.maxFitError, tolerance);
}

TEST(ImportOutOfCore, OnePartIsTheImportInMemoryBitForBit) {
    const auto dir = test::scratchDir("import_parts");
    std::vector<std::string> inputs = {syntheticOsm(dir, 8, 1)};
    if (std::filesystem::exists(andorraPbf())) inputs.push_back(andorraPbf());
    for (const std::string& input : inputs) {
        SCOPED_TRACE(input);
        ImportOptions o = optionsFor(input);
        ImportReport memoryReport, partsReport;
        importSceneToFile(o, (dir / "memory.gpkg").string(), memoryReport);
        o.vectorPartLevel = 0;
        importSceneToFile(o, (dir / "parts.gpkg").string(), partsReport);
        EXPECT_EQ(partsReport.vectorParts, 1u);
        EXPECT_EQ(partsReport.borderNodes, 0u);
        std::string memorySum, partsSum;
        const SceneDocument memory = loadScene((dir / "memory.gpkg").string(), memorySum);
        const SceneDocument parts = loadScene((dir / "parts.gpkg").string(), partsSum);
        EXPECT_TRUE(identical(memory, parts));
        EXPECT_EQ(memorySum, partsSum);
        EXPECT_EQ(memoryReport.network.maxFitError, partsReport.network.maxFitError);
        EXPECT_EQ(memoryReport.problems.size(), partsReport.problems.size());
    }
    std::filesystem::remove_all(dir);
}

// Seeds and part levels drawn once: the invariants hold for every extract and every grid.
TEST(ImportOutOfCore, PartsKeepTheJunctionsAreasAndLinesOfTheImportInMemory) {
    const auto dir = test::scratchDir("import_parts");
    // Under the sanitizers, the first two (each import is several times slower there).
    const std::vector<std::tuple<int, int, int>> runs = {{1, 10, 1}, {2, 10, 2}, {3, 12, 3}, {4, 9, 4}};
    for (std::size_t k = 0; k < (test::kSanitized ? 2u : runs.size()); ++k) {
        const auto [seed, blocks, level] = runs[k];
        SCOPED_TRACE("seed " + std::to_string(seed) + ", level " + std::to_string(level));
        ImportOptions o = optionsFor(syntheticOsm(dir, blocks, seed));
        ImportReport memoryReport, partsReport;
        importSceneToFile(o, (dir / "memory.gpkg").string(), memoryReport);
        o.vectorPartLevel = level;
        importSceneToFile(o, (dir / "parts.gpkg").string(), partsReport);
        EXPECT_EQ(partsReport.vectorPartLevel, level);
        EXPECT_GT(partsReport.vectorParts, 1u);
        EXPECT_GT(partsReport.borderNodes, 0u);
        const SceneDocument memory = loadScene((dir / "memory.gpkg").string());
        const SceneDocument parts = loadScene((dir / "parts.gpkg").string());
        expectSameNetwork(memory, parts, partsReport, o.fitTolerance);
    }
    if (std::filesystem::exists(andorraPbf())) {
        SCOPED_TRACE("Andorra, level 3");
        ImportOptions o = optionsFor(andorraPbf());
        ImportReport memoryReport, partsReport;
        importSceneToFile(o, (dir / "memory.gpkg").string(), memoryReport);
        o.vectorPartLevel = 3;
        importSceneToFile(o, (dir / "parts.gpkg").string(), partsReport);
        expectSameNetwork(loadScene((dir / "memory.gpkg").string()), loadScene((dir / "parts.gpkg").string()), partsReport, o.fitTolerance);
    }
    std::filesystem::remove_all(dir);
}

// The extract as a PBF (the format users download), written by osmium-tool: GDAL's PBF reader is
// held to its bounds under a budget (one block at a time, its node index on disk beside --out),
// which changes neither what it reads nor GDAL's own settings after the import.
TEST(ImportOutOfCore, APbfExtractGivesTheFeaturesOfItsXmlAndThePartsKeepItsNetwork) {
    if (std::system("osmium --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "osmium-tool is not installed (scripts/install_deps.sh installs it)";
    const auto dir = test::scratchDir("import_parts");
    const std::string xml = syntheticOsm(dir, 10, 6);
    const std::string pbf = (dir / "synthetic.osm.pbf").string();
    ASSERT_EQ(std::system(("osmium cat " + xml + " -o " + pbf + " --overwrite").c_str()), 0);
    // GDAL's options as they are before the imports (the environment may set them).
    const std::vector<const char*> options = {"OSM_MAX_TMPFILE_SIZE", "CPL_TMPDIR", "GDAL_NUM_THREADS"};
    std::vector<std::string> before;
    for (const char* option : options) before.push_back(CPLGetConfigOption(option, "(unset)"));
    ImportOptions o = optionsFor(xml);
    ImportReport xmlReport, memoryReport, partsReport;
    importSceneToFile(o, (dir / "xml.gpkg").string(), xmlReport);
    o = optionsFor(pbf);
    importSceneToFile(o, (dir / "memory.gpkg").string(), memoryReport);
    o.vectorBudgetMiB = 4.0;
    o.vectorPartLevel = 2;
    importSceneToFile(o, (dir / "parts.gpkg").string(), partsReport);
    EXPECT_EQ(memoryReport.featuresRead, xmlReport.featuresRead);
    EXPECT_EQ(memoryReport.linesKept, xmlReport.linesKept);
    EXPECT_EQ(memoryReport.areasKept, xmlReport.areasKept);
    EXPECT_EQ(partsReport.featuresRead, xmlReport.featuresRead);
    EXPECT_EQ(partsReport.spilledFeatures, xmlReport.linesKept + xmlReport.areasKept);
    expectSameNetwork(loadScene((dir / "memory.gpkg").string()), loadScene((dir / "parts.gpkg").string()), partsReport, o.fitTolerance);
    for (std::size_t i = 0; i < options.size(); ++i)
        EXPECT_EQ(std::string(CPLGetConfigOption(options[i], "(unset)")), before[i]) << options[i] << " changed by the import";
    std::filesystem::remove_all(dir);
}

TEST(ImportOutOfCore, TheBudgetChoosesTheCoarsestPartsThatFit) {
    const auto dir = test::scratchDir("import_parts");
    ImportOptions o = optionsFor(syntheticOsm(dir, 12, 5));
    o.vectorBudgetMiB = 1024.0;
    ImportReport large;
    importSceneToFile(o, (dir / "large.gpkg").string(), large);
    EXPECT_EQ(large.vectorPartLevel, 0);
    // A budget of a tenth of what the whole takes while built: finer parts, each within it.
    o.vectorBudgetMiB = double(large.densestPartBytes) * kVectorMemoryPerSpillByte / 10.0 / 1048576.0;
    ImportReport small;
    importSceneToFile(o, (dir / "small.gpkg").string(), small);
    EXPECT_GT(small.vectorPartLevel, 0);
    EXPECT_LE(double(small.densestPartBytes) * kVectorMemoryPerSpillByte, o.vectorBudgetMiB * 1048576.0);
    EXPECT_EQ(small.spilledBytes, large.spilledBytes);
    EXPECT_EQ(small.spilledFeatures, large.spilledFeatures);
    std::filesystem::remove_all(dir);
}

// What is in the folder but the inputs: no spill file or other temporary left behind.
std::set<std::string> filesIn(const std::filesystem::path& dir) {
    std::set<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(dir)) out.insert(e.path().filename().string());
    return out;
}

TEST(ImportOutOfCore, ABudgetSmallerThanTheDensestPartIsRefusedWithTheFigures) {
    const auto dir = test::scratchDir("import_parts");
    ImportOptions o = optionsFor(syntheticOsm(dir, 6, 1));
    const auto before = filesIn(dir);
    o.vectorBudgetMiB = 1e-4;
    ImportReport report;
    try {
        importSceneToFile(o, (dir / "scene.gpkg").string(), report);
        ADD_FAILURE() << "a budget of 100 bytes was accepted";
    } catch (const ImportError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("scene.gpkg: cannot import within a vector budget of"), std::string::npos) << what;
        EXPECT_NE(what.find("MiB of features"), std::string::npos) << what;
    }
    EXPECT_EQ(filesIn(dir), before);
    std::filesystem::remove_all(dir);
}

TEST(ImportOutOfCore, AFailedImportLeavesTheFileItWouldReplaceAndNoTemporary) {
    const auto dir = test::scratchDir("import_parts");
    ImportOptions o = optionsFor(syntheticOsm(dir, 6, 1));
    const std::string out = (dir / "scene.gpkg").string();
    o.vectorPartLevel = 2;
    ImportReport report;
    importSceneToFile(o, out, report);
    const std::string sum = storedSceneChecksum(out);
    const auto before = filesIn(dir);
    // The parts are built and written, then the kept count refuses: the save is abandoned.
    o.minKept = 1000000;
    o.vectorPartLevel = 3;
    EXPECT_THROW(importSceneToFile(o, out, report), ImportError);
    EXPECT_EQ(filesIn(dir), before);
    EXPECT_EQ(storedSceneChecksum(out), sum);
    std::filesystem::remove_all(dir);
}

TEST(ImportOutOfCore, KnobsOutOfRangeAreRefused) {
    const auto dir = test::scratchDir("import_parts");
    ImportOptions o = optionsFor(syntheticOsm(dir, 2, 1));
    ImportReport report;
    o.vectorPartLevel = 9;
    EXPECT_THROW(importSceneToFile(o, (dir / "a.gpkg").string(), report), ImportError);
    o.vectorPartLevel = -1;
    o.vectorBudgetMiB = -1.0;
    EXPECT_THROW(importSceneToFile(o, (dir / "a.gpkg").string(), report), ImportError);
    o.vectorBudgetMiB = std::nan("");
    EXPECT_THROW(importSceneToFile(o, (dir / "a.gpkg").string(), report), ImportError);
    EXPECT_FALSE(std::filesystem::exists(dir / "a.gpkg"));
    std::filesystem::remove_all(dir);
}

// The spill gives back what it was given, by box, in the order added: geometry, rule, flags and
// attributes (an empty value too), and counts bytes per cell of its grids.
TEST(VectorSpill, GivesBackTheFeaturesABoxMeetsInTheOrderAdded) {
    const auto dir = test::scratchDir("vector_spill");
    const std::string path = (dir / "spill.tmp").string();
    {
        VectorSpill spill(path, 8.0);
        RawLine west{.rule = 2, .lonLat = {{0.0, 0.0}, {1.0, 1.0}}, .inMulti = true, .flags = kBridge,
                     .kept = {{"name", "Pont"}, {"layer", ""}}, .source = {"a.osm", "lines", 7}};
        RawArea east{.rule = 5, .rings = {{{8.0, 8.0}, {9.0, 8.0}, {9.0, 9.0}, {8.0, 8.0}}}, .kept = {}, .source = {"b.osm", "multipolygons", 9}};
        RawLine middle{.rule = 1, .lonLat = {{4.0, 4.0}, {6.0, 6.0}}, .inMulti = false, .flags = 0, .kept = {}, .source = {"a.osm", "lines", 8}};
        spill.add(west);
        spill.add(east);
        spill.add(middle);
        EXPECT_TRUE(spill.firstOsmKey("lines:osm_id:1"));
        EXPECT_FALSE(spill.firstOsmKey("lines:osm_id:1"));
        // Scene metres: lon/lat times 100, over a square of 1000 m.
        spill.index([](glm::dvec2 p) { return Vec2(p * 100.0); }, {{0.0, 0.0}, {1000.0, 1000.0}});
        EXPECT_EQ(spill.features(), 3u);
        EXPECT_EQ(spill.largestCellBytes(0), spill.bytes());
        EXPECT_LT(spill.largestCellBytes(3), spill.bytes());
        VectorData got;
        spill.read({{0.0, 0.0}, {650.0, 650.0}}, got);
        ASSERT_EQ(got.lines.size(), 2u);
        EXPECT_TRUE(got.areas.empty());
        EXPECT_EQ(got.lines[0].lonLat, west.lonLat);
        EXPECT_EQ(got.lines[0].rule, 2u);
        EXPECT_EQ(got.lines[0].flags, kBridge);
        EXPECT_TRUE(got.lines[0].inMulti);
        EXPECT_EQ(got.lines[0].kept, west.kept);
        EXPECT_EQ(got.lines[0].source.str(), west.source.str());
        EXPECT_EQ(got.lines[1].lonLat, middle.lonLat);
        VectorData far;
        spill.read({{790.0, 790.0}, {1000.0, 1000.0}}, far);
        ASSERT_EQ(far.areas.size(), 1u);
        EXPECT_EQ(far.areas[0].rings, east.rings);
        EXPECT_EQ(far.areas[0].source.str(), east.source.str());
        EXPECT_TRUE(far.lines.empty());
        EXPECT_TRUE(std::filesystem::exists(path));
    }
    EXPECT_FALSE(std::filesystem::exists(path)) << "the spill outlived its import";
    // A spill that cannot be made is refused naming its file, and an existing file is not taken.
    try {
        VectorSpill spill((dir / "missing" / "spill.tmp").string(), 8.0);
        ADD_FAILURE() << "a spill in a missing folder was made";
    } catch (const VectorImportError& e) {
        EXPECT_NE(std::string(e.what()).find("missing/spill.tmp: cannot create the import's spill file"), std::string::npos) << e.what();
    }
    { std::ofstream(dir / "mine.tmp") << "mine"; }
    EXPECT_THROW(VectorSpill((dir / "mine.tmp").string(), 8.0), VectorImportError);
    EXPECT_TRUE(std::filesystem::exists(dir / "mine.tmp"));
    std::filesystem::remove_all(dir);
}

TEST(PartGrid, EveryPointHasOnePartAndTheFarEdgesBelongToTheLastRowAndColumn) {
    const PartGrid grid{{{0.0, 0.0}, {800.0, 800.0}}, 4};
    EXPECT_EQ(grid.partOf({0.0, 0.0}), 0);
    EXPECT_EQ(grid.partOf({199.999, 0.0}), 0);
    EXPECT_EQ(grid.partOf({200.0, 0.0}), 1);
    EXPECT_EQ(grid.partOf({0.0, 200.0}), 4);
    EXPECT_EQ(grid.partOf({800.0, 800.0}), 15);
    EXPECT_EQ(grid.partOf({-5.0, 900.0}), 12);
    EXPECT_EQ(grid.partOf({std::nan(""), 0.0}), 0);
    EXPECT_EQ(grid.partOf({1e300, -1e300}), 3);  // far outside: clamped, no overflow
    for (int part = 0; part < 16; ++part) {
        const Box b = grid.partBox(part);
        EXPECT_EQ(grid.partOf(b.center()), part);
        EXPECT_EQ(grid.partOf(b.min), part);
    }
}

}  // namespace
}  // namespace lacet
