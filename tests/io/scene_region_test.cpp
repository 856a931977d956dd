// io/scene_region.h: the tiles of any quad of a region, made from the part of the scene file that
// loadSceneRegion reads, are the tiles made from the whole scene, bit for bit (randomized regions
// with fixed seeds, at several levels, over a synthetic scene with bridges, roundabouts, rivers,
// lakes, fields and forests); what is read follows the region; a file without the feature index is
// read whole; a corrupt index is refused by name.
#include "io/scene_region.h"

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/scene_features.h"
#include "io/scene_file.h"
#include "io/scene_overlay.h"
#include "io/sqlite_db.h"
#include "model/curve_data.h"
#include "model/edits.h"
#include "model/graph_step.h"
#include "model/quadtree.h"
#include "model/validate.h"
#include "pyramid/quad_digest.h"
#include "raster/dem_source.h"
#include "raster/parallel_producers.h"
#include "synth/synthetic_dem.h"
#include "synth/synthetic_scene.h"
#include "tests/io/gis_fixtures.h"
#include "tests/sanitized.h"

namespace lacet {
namespace {

void collect(Quadtree& qt, Quad& q, const Box& region, int level, std::vector<const Quad*>& out) {
    if (!q.bounds.intersects(region)) return;
    if (q.level == level) {
        out.push_back(&q);
        return;
    }
    if (q.isLeaf()) qt.subdivide(q);
    for (auto& c : q.children) collect(qt, *c, region, level, out);
}

struct RegionTiles {
    std::vector<AppearanceTile> appearance;
    std::vector<ElevationTile> elevation;
    std::vector<std::uint64_t> digests;  // QuadDigests::of, each quad
    std::size_t bridges = 0, roundaboutRoads = 0;
};

RegionTiles tilesOf(const SceneDocument& doc, const Box& region, int level) {
    GraphStep step(doc.scene);
    Quadtree qt(doc.scene, {}, &step);
    std::vector<const Quad*> quads;
    collect(qt, qt.root(), region, level, quads);
    const InMemoryDem dem(*doc.dem);
    CurveDataCache data(qt, dem.heights());
    RegionTiles t;
    t.appearance = produceAppearanceTiles(quads, qt, data, dem, {});
    t.elevation = produceElevationTiles(quads, qt, data, dem, {});
    const QuadDigests digests(qt, data);
    for (const Quad* q : quads) t.digests.push_back(digests.of(*q));
    for (const Quad* q : quads)
        for (const QuadLayer& l : q->layers)
            for (const auto& [id, pieces] : l.curves)
                if (const ProceduralCurve* p = qt.proceduralCurve(0, id); p && (p->curve.flags & kBridge) && !pieces.empty()) ++t.bridges;
    t.roundaboutRoads = step.counters().roundaboutRoads;
    return t;
}

// `part` holds what was read and nothing else: ids from 0, each element the file's element of its
// Layer::sceneIds (ascending), with its references mapped; it validates and cannot be saved or grown.
void expectCompactPartOf(const SceneDocument& part, const SceneDocument& whole, const SceneRegionStats& stats) {
    std::size_t nodes = 0, curves = 0, areas = 0;
    ASSERT_EQ(part.scene.layers.size(), whole.scene.layers.size());
    EXPECT_TRUE(validate(part.scene).empty());
    for (std::size_t l = 0; l < part.scene.layers.size(); ++l) {
        const Layer& p = part.scene.layers[l];
        const Layer& w = whole.scene.layers[l];
        ASSERT_TRUE(p.isPart());
        nodes += p.nodes.size();
        curves += p.curves.size();
        areas += p.areas.size();
        for (ElementId n = 0; n < p.nodes.size(); ++n) {
            const Node& wn = w.nodes.at(p.sceneNodeId(n));
            EXPECT_EQ(p.nodes[n].p, wn.p);
            for (ElementId c : p.nodes[n].curves)
                EXPECT_NE(std::find(wn.curves.begin(), wn.curves.end(), p.sceneCurveId(c)), wn.curves.end());
        }
        for (ElementId c = 0; c < p.curves.size(); ++c) {
            const Curve& pc = p.curves[c];
            const Curve& wc = w.curves.at(p.sceneCurveId(c));
            EXPECT_EQ(pc.vertices, wc.vertices);
            if (!pc.alive) continue;
            EXPECT_EQ(p.sceneNodeId(pc.start), wc.start);
            EXPECT_EQ(p.sceneNodeId(pc.end), wc.end);
        }
        for (ElementId a = 0; a < p.areas.size(); ++a) {
            const Area& pa = p.areas[a];
            const Area& wa = w.areas.at(p.sceneAreaId(a));
            EXPECT_EQ(p.sceneCurveId(pa.axial), wa.axial);
            ASSERT_EQ(pa.loops.size(), wa.loops.size());
            for (std::size_t k = 0; k < pa.loops.size(); ++k)
                for (std::size_t e = 0; e < pa.loops[k].size(); ++e) EXPECT_EQ(p.sceneCurveId(pa.loops[k][e].curve), wa.loops[k][e].curve);
        }
    }
    EXPECT_EQ(nodes, stats.nodes);  // nothing but what was read
    EXPECT_EQ(curves, stats.curves);
    EXPECT_EQ(areas, stats.areas);
}

class SceneRegion : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new std::filesystem::path(test::scratchDir("scene_region"));
        SceneDocument doc;
        doc.scene = makeSyntheticScene({.seed = 7, .curves = 20000, .roundaboutFraction = 0.3});
        doc.dem = makeSyntheticDem(doc.scene, {.seed = 7, .resolution = 5000});
        path_ = new std::string((*dir_ / "scene.gpkg").string());
        saveScene(*path_, doc);
        whole_ = new SceneDocument(loadScene(*path_));
    }
    static void TearDownTestSuite() {
        std::filesystem::remove_all(*dir_);
        delete whole_;
        delete path_;
        delete dir_;
    }
    static std::filesystem::path* dir_;
    static std::string* path_;
    static SceneDocument* whole_;
};
std::filesystem::path* SceneRegion::dir_ = nullptr;
std::string* SceneRegion::path_ = nullptr;
SceneDocument* SceneRegion::whole_ = nullptr;

TEST_F(SceneRegion, RandomRegionsGiveTheWholeScenesTilesFromWhatTheyRead) {
    const Box extent = whole_->scene.extent;
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const int kRegions = test::sanitizedOr(40, 16);
    std::size_t bridges = 0, roundabouts = 0, partial = 0;
    for (int k = 0; k < kRegions; ++k) {
        const int level = 5 + k % 3;  // quads of 560 m to 140 m over a 17.9 km extent
        const Vec2 size = extent.size();
        const double side = size.x * (0.002 + 0.05 * unit(rng));
        const Vec2 at = extent.min + Vec2(unit(rng), unit(rng)) * (size - side);
        const Box region{at, at + side};
        SceneRegionStats stats;
        const SceneDocument part = loadSceneRegion(*path_, region, {}, level, &stats);
        SCOPED_TRACE("region " + std::to_string(k) + " at level " + std::to_string(level));
        EXPECT_FALSE(stats.wholeScene);
        EXPECT_GT(stats.found, 0u);
        EXPECT_EQ(stats.sceneCurves, [&] {
            std::size_t n = 0;
            for (const Layer& l : whole_->scene.layers) n += l.curves.size();
            return n;
        }());
        if (stats.curves < stats.sceneCurves / 2) ++partial;
        const RegionTiles a = tilesOf(*whole_, region, level), b = tilesOf(part, region, level);
        ASSERT_EQ(a.appearance.size(), b.appearance.size());
        for (std::size_t q = 0; q < a.appearance.size(); ++q) {
            EXPECT_TRUE(a.appearance[q] == b.appearance[q]) << "appearance tile " << q;
            EXPECT_TRUE(a.elevation[q] == b.elevation[q]) << "elevation tile " << q;
            EXPECT_EQ(a.digests[q], b.digests[q]) << "digest of quad " << q;
        }
        expectCompactPartOf(part, *whole_, stats);
        EXPECT_EQ(a.bridges, b.bridges);
        bridges += b.bridges;
        roundabouts += b.roundaboutRoads;
    }
    EXPECT_EQ(partial, std::size_t(kRegions));  // each region read less than half of the scene
    EXPECT_GT(bridges, 0u);      // the regions held bridges...
    EXPECT_GT(roundabouts, 0u);  // ...and roads trimmed at roundabouts
}

TEST_F(SceneRegion, ARegionOnTheQuadBordersAtEveryLevelGivesTheSameTiles) {
    const Vec2 c = whole_->scene.extent.center();
    const Box region{c - 1.0, c + 1.0};  // the corner of the four quads of level 1, and of every level below
    const SceneDocument part = loadSceneRegion(*path_, region, {}, 6);
    const RegionTiles a = tilesOf(*whole_, region, 6), b = tilesOf(part, region, 6);
    ASSERT_EQ(a.appearance.size(), 4u);
    EXPECT_TRUE(a.appearance == b.appearance);
    EXPECT_TRUE(a.elevation == b.elevation);
}

// A wide river area whose water follows its river on through it (raster/elevation_producer.cpp:
// axialRiver): the axial curve A, then B and C, split at confluence nodes inside the area. A
// region at the area's far bank, 280 m from C and farther from everything else the R-trees find,
// needs C: the water level there is C's z-profile at its nearest point.
SceneDocument riverAreaScene() {
    SceneDocument doc;
    doc.scene.extent = {{0.0, 0.0}, {4096.0, 4096.0}};
    Layer rivers;
    rivers.name = "rivers";
    rivers.kind = LayerKind::Rivers;
    auto line = [&](ElementId a, ElementId b, float w, float wf, std::uint16_t cls) {
        Curve c;
        c.vertices = {Vertex{rivers.nodes[a].p}, Vertex{rivers.nodes[b].p}};
        c.start = a, c.end = b, c.w = w, c.wf = wf, c.cls = cls;
        return rivers.addCurve(c);
    };
    const ElementId n0 = rivers.addNode({100.0, 1000.0}), n1 = rivers.addNode({3100.0, 1000.0}), n2 = rivers.addNode({3100.0, 1600.0}),
                    n3 = rivers.addNode({100.0, 1600.0});
    const ElementId banks[4] = {line(n0, n1, 0.0f, 10.0f, 1), line(n1, n2, 0.0f, 10.0f, 1), line(n2, n3, 0.0f, 10.0f, 1),
                                line(n3, n0, 0.0f, 10.0f, 1)};
    const ElementId a0 = rivers.addNode({150.0, 1300.0}), a1 = rivers.addNode({1100.0, 1300.0}), a2 = rivers.addNode({2100.0, 1300.0}),
                    a3 = rivers.addNode({3050.0, 1300.0});
    const ElementId axial = line(a0, a1, 20.0f, 30.0f, 0);
    line(a1, a2, 20.0f, 30.0f, 0);
    line(a2, a3, 20.0f, 30.0f, 0);
    Area area;
    area.loops = {{{banks[0]}, {banks[1]}, {banks[2]}, {banks[3]}}};
    area.wf = 10.0f;
    area.axial = axial;
    rivers.addArea(area);
    doc.scene.layers.push_back(std::move(rivers));
    // Ground falling 30 m a km to the east: the river's z-profile falls with it.
    constexpr int kSide = 257;
    std::vector<float> z(std::size_t(kSide) * kSide);
    for (int j = 0; j < kSide; ++j)
        for (int i = 0; i < kSide; ++i) z[std::size_t(j) * kSide + std::size_t(i)] = float(500.0 - 0.03 * 16.0 * i);
    doc.dem.emplace(doc.scene.extent, kSide, kSide, std::move(z));
    return doc;
}

TEST_F(SceneRegion, ARiverAreasWaterFollowsItsRiverOnThroughTheAreaWhereverTheRegionIs) {
    const std::string path = (*dir_ / "river_area.gpkg").string();
    saveScene(path, riverAreaScene());
    const SceneDocument whole = loadScene(path);
    for (const Box region : {Box{{2590.0, 1570.0}, {2610.0, 1590.0}}, Box{{600.0, 1020.0}, {640.0, 1040.0}}}) {
        SceneRegionStats stats;
        const SceneDocument part = loadSceneRegion(path, region, {}, 7, &stats);
        const RegionTiles a = tilesOf(whole, region, 7), b = tilesOf(part, region, 7);
        ASSERT_FALSE(a.elevation.empty());
        EXPECT_TRUE(a.elevation == b.elevation) << "region at " << region.min.x << ", " << region.min.y << ": " << stats.curves
                                                << " of " << stats.sceneCurves << " curves read";
        EXPECT_TRUE(a.appearance == b.appearance);
        // The river through the area is read whole: its three curves and the banks.
        EXPECT_EQ(stats.curves, 7u);
    }
}

TEST_F(SceneRegion, AFileWithoutTheFeatureIndexIsReadWhole) {
    const std::string copy = (*dir_ / "old.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(copy, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("DROP TABLE ") + kFeatureIndexTable);
    }
    const Vec2 c = whole_->scene.extent.center();
    SceneRegionStats stats;
    const SceneDocument part = loadSceneRegion(copy, {c - 100.0, c + 100.0}, {}, 6, &stats);
    EXPECT_TRUE(stats.wholeScene);
    EXPECT_EQ(stats.curves, stats.sceneCurves);
    EXPECT_TRUE(part.scene.layers.size() == whole_->scene.layers.size());
}

TEST_F(SceneRegion, ACorruptIndexIsRefusedNamingTheFileAndTable) {
    const std::string copy = (*dir_ / "corrupt.gpkg").string();
    std::filesystem::copy_file(*path_, copy, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(copy, SqliteDb::Mode::ReadWrite);
        db.exec(std::string("UPDATE ") + kFeatureIndexTable + " SET max_curve_wf = -1");
    }
    const Vec2 c = whole_->scene.extent.center();
    try {
        loadSceneRegion(copy, {c - 100.0, c + 100.0}, {}, 6);
        FAIL() << "a corrupt index was read";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find(copy), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(kFeatureIndexTable), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadSceneRegion(*path_, {c + 1.0, c - 1.0}, {}, 6), std::invalid_argument);
    EXPECT_THROW(loadSceneRegion(*path_, {c - 1.0, c + 1.0}, {}, 31), std::invalid_argument);
}

TEST_F(SceneRegion, APartIsNeverSavedNorGrown) {
    const Box extent = whole_->scene.extent;
    const Box region{extent.min + extent.size() * 0.4, extent.min + extent.size() * 0.45};
    SceneDocument part = loadSceneRegion(*path_, region, {}, 6);
    const std::string out = (*dir_ / "part.gpkg").string();
    try {
        saveScene(out, part);
        FAIL() << "a part was saved";
    } catch (const SceneFileError& e) {
        EXPECT_NE(std::string(e.what()).find("the rest of it would be lost"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(out));
    Layer& roads = part.scene.layers[0];
    ASSERT_FALSE(roads.nodes.empty());
    EXPECT_THROW(roads.addNode({0.0, 0.0}), std::logic_error);
    // File ids out of order are a problem validate() names.
    ASSERT_GE(roads.nodes.size(), 2u);
    std::swap(roads.sceneIds.nodes[0], roads.sceneIds.nodes[1]);
    EXPECT_FALSE(validate(part.scene).empty());
    roads.sceneIds.nodes.pop_back();
    EXPECT_FALSE(validate(part.scene).empty());
}

// SceneRegionOptions::budgetMiB: a read within it is the same document, holding what it counted
// (SceneRegionStats::bytes, model/graph.h's memoryBytes); a byte less is refused by name with the
// budget, not read past it.
TEST_F(SceneRegion, AReadOverItsBudgetIsRefusedWithTheFigure) {
    const Box extent = whole_->scene.extent;
    const Box region{extent.min + extent.size() * 0.3, extent.min + extent.size() * 0.5};
    SceneRegionStats free;
    const SceneDocument a = loadSceneRegion(*path_, region, {}, 6, &free);
    EXPECT_EQ(free.bytes, memoryBytes(a.scene));
    ASSERT_GT(free.bytes, 100000u);
    SceneRegionOptions within;
    within.budgetMiB = double(free.bytes) / 1048576.0;
    SceneRegionStats st;
    const SceneDocument b = loadSceneRegion(*path_, region, {}, 6, &st, within);
    EXPECT_EQ(st.bytes, free.bytes);
    EXPECT_EQ(st.curves, free.curves);
    EXPECT_EQ(b.scene.layers.size(), a.scene.layers.size());
    SceneRegionOptions tight;  // a byte less than the document holds: what is counted is what is held
    tight.budgetMiB = double(free.bytes - 1) / 1048576.0;
    try {
        loadSceneRegion(*path_, region, {}, 6, nullptr, tight);
        FAIL() << "a read over its budget was not refused";
    } catch (const SceneBudgetError& e) {
        EXPECT_NE(std::string(e.what()).find(*path_), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("passes the budget"), std::string::npos) << e.what();
    }
    SceneRegionOptions none;
    none.budgetMiB = 0.0;
    EXPECT_THROW(loadSceneRegion(*path_, region, {}, 6, nullptr, none), std::invalid_argument);
}

// The outline (the default pyramid shard level reads it): the extent, and the curves and areas of
// every layer counted by their ids, deleted ones included.
TEST_F(SceneRegion, TheOutlineCountsEveryLayersCurvesAndAreas) {
    const SceneOutline o = loadSceneOutline(*path_);
    EXPECT_EQ(o.extent.min, whole_->scene.extent.min);
    EXPECT_EQ(o.extent.max, whole_->scene.extent.max);
    std::size_t elements = 0;
    for (const Layer& l : whole_->scene.layers) elements += l.curves.size() + l.areas.size();
    EXPECT_GT(elements, 20000u);
    EXPECT_EQ(o.elements, elements);
    EXPECT_THROW(loadSceneOutline((*dir_ / "missing.gpkg").string()), SceneFileError);
}

// A region's attributes are those of the elements it read, in the file's order, whether read through
// lacet_attributes' (layer, kind, id) index or, in a file written before it, by a scan; the region
// reader's two lookups use their indexes (the query plans name them), not scans of the whole file.
TEST_F(SceneRegion, AttributesOfWhatWasReadComeThroughTheIndexInTheFilesOrder) {
    SceneDocument doc = *whole_;
    std::mt19937_64 rng(23);
    for (int k = 0; k < 3000; ++k) {  // random elements, in no order: the file's order is the list's
        const LayerId l = LayerId(rng() % doc.scene.layers.size());
        const Layer& layer = doc.scene.layers[l];
        const ElementKind kind = ElementKind(rng() % 3);
        const std::size_t n = kind == ElementKind::Node ? layer.nodes.size() : kind == ElementKind::Curve ? layer.curves.size() : layer.areas.size();
        if (n == 0) continue;
        std::string key = "k", value = "v";  // (not "k" + ...: GCC 12's -Wrestrict misfires on it)
        key += std::to_string(k % 7);
        value += std::to_string(k);
        doc.attributes.push_back({l, kind, ElementId(rng() % n), std::move(key), std::move(value)});
    }
    const std::string path = (*dir_ / "attributes.gpkg").string();
    saveScene(path, doc);
    const std::string old = (*dir_ / "attributes-old.gpkg").string();
    std::filesystem::copy_file(path, old, std::filesystem::copy_options::overwrite_existing);
    {
        SqliteDb db(old, SqliteDb::Mode::ReadWrite);
        db.exec("DROP INDEX lacet_attributes_element");
        db.exec("DROP INDEX lacet_nodes_roundabout");
    }
    {
        SqliteDb db(path, SqliteDb::Mode::ReadOnly);
        const auto plan = [&](const std::string& sql) {
            std::string all;
            auto s = db.prepare("EXPLAIN QUERY PLAN " + sql);
            while (s.step()) {
                all += s.text(3);
                all += '\n';
            }
            return all;
        };
        EXPECT_NE(plan("SELECT fid, key, value FROM lacet_attributes WHERE layer = 0 AND kind = 1 AND id = 5")
                      .find("lacet_attributes_element"),
                  std::string::npos);
        EXPECT_NE(plan("SELECT max(roundabout) FROM lacet_nodes WHERE alive AND roundabout > 0").find("lacet_nodes_roundabout"),
                  std::string::npos);
    }
    const Box extent = doc.scene.extent;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t seen = 0;
    for (int r = 0; r < 8; ++r) {
        const Vec2 c = extent.min + extent.size() * Vec2(unit(rng), unit(rng));
        const Box region{c - extent.size() * 0.05, c + extent.size() * 0.05};
        const SceneDocument part = loadSceneRegion(path, region, {}, 6);
        std::vector<ElementAttribute> expected;
        for (const ElementAttribute& a : doc.attributes) {
            const Layer::SceneIds& ids = part.scene.layers[a.layer].sceneIds;
            const auto& of = a.kind == ElementKind::Node ? ids.nodes : a.kind == ElementKind::Curve ? ids.curves : ids.areas;
            const auto it = std::lower_bound(of.begin(), of.end(), a.id);
            if (it == of.end() || *it != a.id) continue;
            ElementAttribute local = a;
            local.id = ElementId(it - of.begin());
            expected.push_back(std::move(local));
        }
        EXPECT_EQ(part.attributes, expected) << "region " << r;
        EXPECT_EQ(loadSceneRegion(old, region, {}, 6).attributes, expected) << "region " << r << ", a file without the index";
        seen += expected.size();
    }
    EXPECT_GT(seen, 50u);
}

// Edits not saved, read over the file (io/scene_overlay.h): random edits of every kind the editor
// makes (moves of vertices and nodes far enough to enter other regions, widths, flags, rings,
// deleted curves) on the whole scene, kept as an overlay of the changed elements; random regions
// read with the overlay give the tiles and digests of the edited whole scene, bit for bit, and hold
// its values.
// A connection kept open (io/scene_file.h) reads the file at its path: a file saved over it
// (renamed over, as saveScene does) is read afresh, not the old one the connection had open.
TEST_F(SceneRegion, AKeptConnectionReadsTheFileSavedOverItSince) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({.seed = 3, .curves = 400});
    doc.dem = makeSyntheticDem(doc.scene, {.seed = 3, .resolution = 200});
    const std::string path = (*dir_ / "kept.gpkg").string();
    saveScene(path, doc);
    const ElementRef node{kRoadsLayer, ElementKind::Node, 0};
    const Vec2 was = doc.scene.layers[kRoadsLayer].nodes[0].p;
    SceneFileConnection connection(path);
    EXPECT_EQ(loadSceneElementBox(connection, node).min, was);
    EXPECT_EQ(loadSceneElementBox(connection, node).min, was);  // the same connection, read again
    moveNode(doc.scene, kRoadsLayer, 0, was + Vec2(12.5, -3.0));
    saveScene(path, doc);
    EXPECT_EQ(loadSceneElementBox(connection, node).min, was + Vec2(12.5, -3.0));
    std::filesystem::remove(path);
    EXPECT_THROW(loadSceneElementBox(connection, node), SceneFileError);  // gone: refused by name, as by path
}

TEST_F(SceneRegion, EditsReadOverTheFileGiveTheEditedScenesTiles) {
    SceneDocument edited = *whole_;
    Scene& scene = edited.scene;
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const auto pick = [&](std::size_t n) { return std::size_t(unit(rng) * double(n)) % n; };
    const Vec2 size = scene.extent.size();
    Changeset all;
    std::size_t applied = 0;
    for (int k = 0; k < 300; ++k) {
        const LayerId l = LayerId(pick(scene.layers.size()));
        Layer& layer = scene.layers[l];
        if (layer.curves.empty()) continue;
        const ElementId c = ElementId(pick(layer.curves.size()));
        if (!layer.curves[c].alive) continue;
        const Vec2 shift = (Vec2(unit(rng), unit(rng)) - 0.5) * size * 0.02;  // up to 180 m each way
        try {
            Changeset cs;
            switch (k % 6) {
            case 0:
            case 1: {
                const std::size_t n = layer.curves[c].vertices.size();
                if (n < 3) continue;
                const std::size_t i = 1 + pick(n - 2);
                cs = moveVertex(scene, l, c, i, layer.curves[c].vertices[i].p + shift);
                break;
            }
            case 2: {
                const ElementId node = unit(rng) < 0.5 ? layer.curves[c].start : layer.curves[c].end;
                cs = moveNode(scene, l, node, layer.nodes[node].p + shift);
                break;
            }
            case 3: {
                const float w = float(2.0 + 20.0 * unit(rng));
                cs = setCurveWidth(scene, l, c, w, w * float(1.5 + 2.0 * unit(rng)));
                break;
            }
            case 4:
                if (layer.kind == LayerKind::Roads && unit(rng) < 0.5)
                    cs = setNodeRoundabout(scene, l, layer.curves[c].start, float(8.0 + 20.0 * unit(rng)));
                else
                    cs = setCurveFlags(scene, l, c, std::uint16_t(layer.curves[c].flags ^ kBridge));
                break;
            default:
                cs = deleteCurve(scene, l, c);
                break;
            }
            all.append(cs);
            ++applied;
        } catch (const EditError&) {  // a ring that does not fit, a curve of an area: not made
        }
    }
    all.normalize();
    ASSERT_GT(applied, 150u);
    const double tolerance = FeatureTableParams{}.tolerance;
    SceneOverlay overlay;
    for (const std::vector<ElementRef>* refs : {&all.removed, &all.added})
        for (const ElementRef& r : *refs) overlay.elements[r] = overlayElement(scene.layers[r.layer], r.kind, r.id, tolerance);
    const Box extent = scene.extent;
    SceneFileConnection connection(*path_);  // every other read through one kept connection
    // The river search through the R-trees with the edits: the rivers whose feature boxes meet a
    // box, as the edited scene saved would give them; around every river edited (where it is now)
    // and around others, untouched.
    std::size_t riversFound = 0, riversEdited = 0;
    for (LayerId l = 0; l < scene.layers.size(); ++l) {
        const Layer& layer = scene.layers[l];
        if (layer.kind != LayerKind::Rivers) continue;
        for (ElementId c = 0; c < layer.curves.size(); ++c) {
            const bool changed = overlay.find({l, ElementKind::Curve, c}) != nullptr;
            const auto at = featureBox(layer, layer.curves[c], tolerance);
            if (!at || !(changed || c % 7 == 0)) continue;
            riversEdited += changed;
            const Box box = Box{at->center(), at->center()}.dilated(40.0);
            std::vector<ElementRef> rivers;
            for (LayerId m = 0; m < scene.layers.size(); ++m) {
                const Layer& other = scene.layers[m];
                if (other.kind != LayerKind::Rivers) continue;
                for (ElementId d = 0; d < other.curves.size(); ++d)
                    if (const auto b = featureBox(other, other.curves[d], tolerance); b && b->intersects(box)) rivers.push_back({m, ElementKind::Curve, d});
                for (ElementId a = 0; a < other.areas.size(); ++a)
                    if (const auto b = featureBox(other, other.areas[a], tolerance); b && b->intersects(box)) rivers.push_back({m, ElementKind::Area, a});
            }
            std::sort(rivers.begin(), rivers.end());
            EXPECT_EQ(loadSceneFeaturesIn(connection, box, LayerKind::Rivers, &overlay), rivers) << "around river " << c;
            riversFound += rivers.size();
        }
    }
    EXPECT_GT(riversEdited, 3u);
    EXPECT_GT(riversFound, 30u);
    for (int k = 0; k < test::sanitizedOr(24, 8); ++k) {
        const int level = 5 + k % 3;
        const double side = size.x * (0.002 + 0.05 * unit(rng));
        const Vec2 at = extent.min + Vec2(unit(rng), unit(rng)) * (size - side);
        const Box region{at, at + side};
        SceneRegionStats stats;
        SceneRegionOptions options;
        options.overlay = &overlay;
        const SceneDocument part = k % 2 ? loadSceneRegion(connection, region, {}, level, &stats, options)
                                         : loadSceneRegion(*path_, region, {}, level, &stats, options);

        SCOPED_TRACE("region " + std::to_string(k) + " at level " + std::to_string(level));
        EXPECT_EQ(stats.tolerance, tolerance);
        const RegionTiles a = tilesOf(edited, region, level), b = tilesOf(part, region, level);
        ASSERT_EQ(a.appearance.size(), b.appearance.size());
        for (std::size_t q = 0; q < a.appearance.size(); ++q) {
            EXPECT_TRUE(a.appearance[q] == b.appearance[q]) << "appearance tile " << q;
            EXPECT_TRUE(a.elevation[q] == b.elevation[q]) << "elevation tile " << q;
            EXPECT_EQ(a.digests[q], b.digests[q]) << "digest of quad " << q;
        }
        EXPECT_EQ(a.bridges, b.bridges);
        expectCompactPartOf(part, edited, stats);
    }
    // What the overlay keeps is what the feature tables would write: its boxes are the R-tree's of
    // the edited scene saved.
    const std::string saved = (*dir_ / "edited.gpkg").string();
    saveScene(saved, edited);
    SqliteDb db(saved, SqliteDb::Mode::ReadOnly);
    std::size_t boxes = 0;
    auto tables = db.prepare(std::string("SELECT table_name, layer, polygons FROM ") + kFeatureIndexTable);
    while (tables.step()) {
        const std::string name = tables.text(0);
        const LayerId l = LayerId(tables.integer(1));
        const ElementKind kind = tables.integer(2) != 0 ? ElementKind::Area : ElementKind::Curve;
        auto rows = db.prepare("SELECT f.lacet_id, r.minx, r.maxx, r.miny, r.maxy FROM \"" + name + "\" f JOIN \"" +
                               featureRtreeName(name) + "\" r ON r.id = f.fid");
        while (rows.step()) {
            const OverlayElement* e = overlay.find({l, kind, ElementId(rows.integer(0))});
            if (!e) continue;
            ASSERT_TRUE(e->box.has_value());
            EXPECT_EQ(e->box->min.x, rows.real(1));
            EXPECT_EQ(e->box->max.x, rows.real(2));
            EXPECT_EQ(e->box->min.y, rows.real(3));
            EXPECT_EQ(e->box->max.y, rows.real(4));
            ++boxes;
        }
    }
    EXPECT_GT(boxes, 100u);
}

}  // namespace
}  // namespace lacet
