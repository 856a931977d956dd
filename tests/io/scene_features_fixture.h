#pragma once
// What tests/io/scene_features_test.cpp uses: a fresh directory per test, a hand-made scene, OGR
// readers of the feature tables, and the distances between a feature and its spline.
#include "io/scene_features.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gdal_priv.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include "io/gpkg_dem.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"
#include "synth/synthetic_scene.h"
#include "tests/io/scene_identical.h"
#include "tests/io/test_crs.h"

namespace lacet {
namespace {

namespace fs = std::filesystem;

// Spacing (metres) of the samples of each Bezier piece compared with its feature's polyline: finer
// than the shortest flat sub-piece a 0.1 m tolerance makes on these curves (metres long).
constexpr double kSampleSpacing = 0.25;
// What distanceTo() may overestimate by (metres), and rounding of coordinates near 1e4 m.
constexpr double kDistanceAccuracy = 1e-6;
constexpr double kRounding = 1e-9;

class SceneFeatures : public ::testing::Test {
protected:
    void SetUp() override {
        GDALAllRegister();
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("lacet_scene_features_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string file(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

// ---- scenes ----

inline ElementId addCurve(Layer& layer, ElementId start, ElementId end, std::vector<Vertex> inner, float w, float wf,
                   std::uint16_t cls = 0, std::uint16_t flags = 0) {
    Curve c;
    c.vertices.push_back({layer.nodes[start].p});
    c.vertices.insert(c.vertices.end(), inner.begin(), inner.end());
    c.vertices.push_back({layer.nodes[end].p});
    c.start = start;
    c.end = end;
    c.w = w;
    c.wf = wf;
    c.cls = cls;
    c.flags = flags;
    return layer.addCurve(std::move(c));
}

inline Vertex control(double x, double y) { return {{x, y}, false}; }
inline Vertex on(double x, double y) { return {{x, y}, true}; }

// A closed loop of cubic curves through `points` (a smooth blob), as one loop of edges.
inline std::vector<AreaEdge> blobLoop(Layer& layer, const std::vector<Vec2>& points, double bulge) {
    std::vector<ElementId> nodes;
    for (Vec2 p : points) nodes.push_back(layer.addNode(p));
    std::vector<AreaEdge> loop;
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Vec2 a = points[k], b = points[(k + 1) % points.size()];
        const Vec2 d = b - a, n{d.y, -d.x};  // to the right of a -> b
        const Vec2 c1 = a + d / 3.0 + n * bulge, c2 = a + d * (2.0 / 3.0) + n * bulge;
        loop.push_back({addCurve(layer, nodes[k], nodes[(k + 1) % points.size()], {control(c1.x, c1.y), control(c2.x, c2.y)}, 0.0f, 0.0f), false});
    }
    return loop;
}

// Layers of every kind: line, quadratic, cubic and mixed pieces, a closed curve, bridge and tunnel
// flags, a lake whose hole is loops[0], an axial curve, fields sharing a border, a forest with a
// clearing, dead elements, names that clash ("dem", a second "Roads", a name with spaces and '&').
inline SceneDocument handDocument(bool withDem, bool withGeoreference) {
    SceneDocument doc;
    Scene& s = doc.scene;
    s.extent = {{0.0, 0.0}, {2000.0, 2000.0}};
    s.layers.resize(6);

    Layer& roads = s.layers[0];
    roads.name = "Roads";
    roads.kind = LayerKind::Roads;
    const ElementId a = roads.addNode({10.0, 20.0}), b = roads.addNode({300.0, 50.0}), c = roads.addNode({600.0, 400.0}),
                    d = roads.addNode({900.0, 900.0});
    const ElementId r0 = addCurve(roads, a, b, {}, 6.0f, 12.0f, 1, kBridge);
    const ElementId r1 = addCurve(roads, b, c, {control(500.0, 0.0)}, 4.0f, 9.0f, 2, kTunnel);
    const ElementId r2 = addCurve(roads, c, d,
                                  {control(700.0, 600.0), control(650.0, 700.0), on(800.0, 700.0), control(900.0, 600.0),
                                   on(880.0, 850.0)},
                                  3.5f, 7.25f, 3, kBridge | kTunnel);
    const ElementId dead = addCurve(roads, a, d, {control(0.0, 900.0)}, 1.0f, 2.0f);
    roads.curves[dead].alive = false;
    std::erase(roads.nodes[a].curves, dead);
    std::erase(roads.nodes[d].curves, dead);
    const ElementId r4 = addCurve(roads, d, d, {control(1000.0, 1000.0), control(800.0, 1000.0)}, 8.0f, 16.0f, 0);
    doc.attributes.push_back({0, ElementKind::Curve, r0, "name", "Avinguda Meritxell"});
    doc.attributes.push_back({0, ElementKind::Curve, r0, "bridge", "yes"});
    doc.attributes.push_back({0, ElementKind::Curve, r0, "name:en", "Meritxell Avenue"});
    doc.attributes.push_back({0, ElementKind::Curve, r1, "name", "Carrer d'Anna \"la\" \xc3\xa9s"});
    doc.attributes.push_back({0, ElementKind::Curve, r1, "layer", "-1"});
    doc.attributes.push_back({0, ElementKind::Curve, r4, "junction", "roundabout"});
    doc.attributes.push_back({0, ElementKind::Curve, dead, "name", "gone"});
    doc.attributes.push_back({0, ElementKind::Node, a, "highway", "traffic_signals"});
    (void)r2;

    Layer& rivers = s.layers[1];
    rivers.name = "rivers";
    rivers.kind = LayerKind::Rivers;
    const ElementId s0 = rivers.addNode({1500.0, 1900.0}), s1 = rivers.addNode({1400.0, 1200.0}),
                    s2 = rivers.addNode({1800.0, 300.0});
    const ElementId v0 = addCurve(rivers, s0, s1, {control(1700.0, 1600.0), control(1200.0, 1500.0)}, 5.0f, 10.0f);
    addCurve(rivers, s1, s2, {control(1600.0, 900.0), control(1300.0, 500.0)}, 9.0f, 18.0f, 1);
    doc.attributes.push_back({1, ElementKind::Curve, v0, "name", "Gran Valira"});

    Layer& lakes = s.layers[2];
    lakes.name = "Lakes & ponds";
    lakes.kind = LayerKind::Lakes;
    const auto shore = blobLoop(lakes, {{100.0, 1100.0}, {500.0, 1050.0}, {550.0, 1450.0}, {150.0, 1500.0}}, 0.1);
    const auto island = blobLoop(lakes, {{250.0, 1250.0}, {300.0, 1350.0}, {380.0, 1260.0}}, 0.15);
    Area lake;
    lake.loops = {island, shore};  // the hole first: the outer ring is the one of largest area
    lake.wf = 4.0f;
    lake.cls = 2;
    const ElementId lakeId = lakes.addArea(lake);
    const ElementId x0 = lakes.addNode({160.0, 1200.0}), x1 = lakes.addNode({480.0, 1400.0});
    addCurve(lakes, x0, x1, {}, 0.0f, 0.0f);  // an axial curve: no area
    doc.attributes.push_back({2, ElementKind::Area, lakeId, "name", "Estany"});
    doc.attributes.push_back({2, ElementKind::Area, lakeId, "3d", "x"});

    Layer& fields = s.layers[3];
    fields.name = "dem";
    fields.kind = LayerKind::Fields;
    const ElementId f00 = fields.addNode({1000.0, 100.0}), f10 = fields.addNode({1100.0, 100.0}),
                    f20 = fields.addNode({1250.0, 100.0}), f01 = fields.addNode({1000.0, 200.0}),
                    f11 = fields.addNode({1100.0, 200.0}), f21 = fields.addNode({1250.0, 200.0});
    const ElementId south0 = addCurve(fields, f00, f10, {}, 0.0f, 0.0f), south1 = addCurve(fields, f10, f20, {}, 0.0f, 0.0f);
    const ElementId shared = addCurve(fields, f10, f11, {control(1120.0, 150.0)}, 0.0f, 0.0f);
    const ElementId east = addCurve(fields, f20, f21, {}, 0.0f, 0.0f), west = addCurve(fields, f00, f01, {}, 0.0f, 0.0f);
    const ElementId north0 = addCurve(fields, f01, f11, {}, 0.0f, 0.0f), north1 = addCurve(fields, f11, f21, {}, 0.0f, 0.0f);
    Area left;
    left.loops = {{{south0, false}, {shared, false}, {north0, true}, {west, true}}};
    left.cls = 3;
    left.wf = 1.0f;
    const ElementId leftId = fields.addArea(left);
    Area right;
    right.loops = {{{south1, false}, {east, false}, {north1, true}, {shared, true}}};
    right.cls = 4;
    const ElementId rightId = fields.addArea(right);
    Area goneField;  // deleted: its curves no longer list it
    goneField.loops = {{{south0, false}, {shared, false}, {north0, true}, {west, true}}};
    goneField.alive = false;
    fields.areas.push_back(goneField);
    doc.attributes.push_back({3, ElementKind::Area, leftId, "crop", "wheat"});
    doc.attributes.push_back({3, ElementKind::Area, rightId, "crop", "maize"});
    doc.attributes.push_back({3, ElementKind::Area, rightId, "crop", "second value, ignored"});

    Layer& forests = s.layers[4];
    forests.name = "forests";
    forests.kind = LayerKind::Forests;
    Area forest;
    forest.loops = {blobLoop(forests, {{1300.0, 1000.0}, {1900.0, 1000.0}, {1900.0, 1600.0}, {1300.0, 1600.0}}, -0.05),
                    blobLoop(forests, {{1500.0, 1200.0}, {1600.0, 1400.0}, {1700.0, 1200.0}}, 0.1)};
    forest.wf = 2.0f;
    forests.addArea(forest);

    s.layers[5].name = "Roads";  // empty, and its name taken
    s.layers[5].kind = LayerKind::Roads;

    if (withGeoreference) {
        doc.georeference.valid = true;
        doc.georeference.lon0 = 1.5;
        doc.georeference.lat0 = 42.5;
        doc.georeference.crsWkt = kWkt;
    }
    if (withDem) {
        const int w = 40, h = 30;
        std::vector<float> z(std::size_t(w * h));
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) z[std::size_t(j * w + i)] = float(1000.0 + 20.0 * std::sin(0.2 * i) + 3.0 * j);
        doc.dem.emplace(s.extent, w, h, std::move(z));
    }
    return doc;
}

// ---- reading back through OGR ----

// GDAL warnings and errors while alive.
class GdalMessages {
public:
    GdalMessages() { CPLPushErrorHandlerEx(&GdalMessages::handle, this); }
    ~GdalMessages() { CPLPopErrorHandler(); }
    const std::vector<std::string>& list() const { return list_; }

private:
    static void CPL_STDCALL handle(CPLErr level, CPLErrorNum, const char* message) {
        if (level >= CE_Warning) static_cast<GdalMessages*>(CPLGetErrorHandlerUserData())->list_.push_back(message);
    }
    std::vector<std::string> list_;
};

struct DatasetCloser {
    void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

inline Dataset openVector(const std::string& path) {
    return Dataset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
}

inline std::vector<Vec2> points(const OGRSimpleCurve& line) {
    std::vector<Vec2> out;
    for (int i = 0; i < line.getNumPoints(); ++i) out.push_back({line.getX(i), line.getY(i)});
    return out;
}

inline std::vector<BezierPiece> pieces(std::span<const Vertex> chain) {
    std::vector<BezierPiece> out;
    forEachPiece(chain, [&](const BezierPiece& b, std::size_t) { out.push_back(b); });
    return out;
}

// Largest distance from a polyline vertex to the spline.
inline double verticesToSpline(const std::vector<Vec2>& line, const std::vector<BezierPiece>& spline, double tolerance) {
    double worst = 0.0;
    for (Vec2 q : line) {
        double best = HUGE_VAL;
        for (const BezierPiece& b : spline)
            if (controlBounds(b).dilated(std::min(best, 10.0 * tolerance)).contains(q) || best == HUGE_VAL)
                best = std::min(best, distanceTo(b, q, kDistanceAccuracy));
        worst = std::max(worst, best);
    }
    return worst;
}

// Distance from q to the polyline, searched first near segment `hint` (samples come in order
// along the curve), over every segment when none there is within `tolerance`.
inline double distanceToPolyline(const std::vector<Vec2>& line, Vec2 q, std::size_t& hint, double tolerance) {
    const std::size_t segments = line.size() - 1;
    auto scan = [&](std::size_t from, std::size_t to) {
        double best = HUGE_VAL;
        for (std::size_t k = from; k < to; ++k)
            if (const double d = distanceToSegment(q, line[k], line[k + 1]); d < best) {
                best = d;
                hint = k;
            }
        return best;
    };
    const std::size_t window = 8;
    const double nearby = scan(hint > window ? hint - window : 0, std::min(segments, hint + window + 1));
    return nearby <= tolerance ? nearby : scan(0, segments);
}

// Largest distance from a dense sample of the spline to the polyline.
inline double splineToPolyline(const std::vector<BezierPiece>& spline, const std::vector<Vec2>& line, double tolerance) {
    double worst = 0.0;
    std::size_t hint = 0;
    for (const BezierPiece& b : spline) {
        double length = 0.0;
        for (int k = 0; k < b.degree; ++k) length += glm::length(b.p[std::size_t(k + 1)] - b.p[std::size_t(k)]);
        const int n = std::max(64, int(std::ceil(length / kSampleSpacing)));
        for (int i = 0; i <= n; ++i)
            worst = std::max(worst, distanceToPolyline(line, evaluate(b, double(i) / n), hint, tolerance));
    }
    return worst;
}

// Both ways within the tolerance (Hausdorff).
::testing::AssertionResult withinTolerance(const std::vector<Vec2>& line, std::span<const Vertex> chain,
                                           double tolerance) {
    const auto spline = pieces(chain);
    const double there = verticesToSpline(line, spline, tolerance), back = splineToPolyline(spline, line, tolerance);
    const double allowed = tolerance + kDistanceAccuracy + kRounding;
    if (there <= allowed && back <= allowed) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "polyline to spline " << there << " m, spline to polyline " << back
                                         << " m, tolerance " << tolerance << " m";
}

// Twice the signed area of a closed chain, from a dense sample.
inline double chainArea(std::span<const Vertex> chain) {
    std::vector<Vec2> ring;
    for (const BezierPiece& b : pieces(chain))
        for (int i = 0; i < 64; ++i) ring.push_back(evaluate(b, i / 64.0));
    double sum = 0.0;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        const Vec2 p = ring[i], q = ring[(i + 1) % ring.size()];
        sum += p.x * q.y - q.x * p.y;
    }
    return sum;
}

inline std::string fieldText(OGRFeature& f, const char* name) {
    const int i = f.GetFieldIndex(name);
    return i >= 0 && f.IsFieldSetAndNotNull(i) ? f.GetFieldAsString(i) : std::string("<null>");
}

// The feature tables the file should hold, independent of how they are named: every alive curve
// that borders no alive area, every alive area, each once.
struct Expected {
    std::size_t curves = 0, areas = 0;
};
inline Expected expectedCounts(const Scene& scene) {
    Expected e;
    for (const Layer& layer : scene.layers) {
        for (const Area& a : layer.areas) e.areas += a.alive;
        for (const Curve& c : layer.curves) {
            bool borders = false;
            for (ElementId a : c.areas) borders = borders || layer.areas[a].alive;
            e.curves += c.alive && !borders;
        }
    }
    return e;
}

inline std::int64_t srsIdOf(const std::string& path, const std::string& table) {
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    auto s = db.prepare("SELECT srs_id FROM gpkg_geometry_columns WHERE table_name = ?");
    s.bindText(1, table);
    return s.step() ? s.integer(0) : -999;
}

// Checks every table of `tables` in the file through OGR against `doc`: type, SRS (when `srs` is
// given), counts, geometry both ways within the tolerance, rings, fixed columns and attribute values;
// and that GDAL said nothing while reading.
inline void checkTables(const std::string& path, const SceneDocument& doc, const std::vector<FeatureTable>& tables,
                 const OGRSpatialReference* srs, double tolerance) {
    GdalMessages messages;
    Dataset ds = openVector(path);
    ASSERT_TRUE(ds) << path;
    Expected seen;
    for (const FeatureTable& t : tables) {
        SCOPED_TRACE("table " + t.name);
        OGRLayer* l = ds->GetLayerByName(t.name.c_str());
        ASSERT_NE(l, nullptr);
        EXPECT_EQ(l->GetGeomType(), t.polygons ? wkbPolygon : wkbLineString);
        if (srs) {
            ASSERT_NE(l->GetSpatialRef(), nullptr);
            EXPECT_TRUE(l->GetSpatialRef()->IsSame(srs));
        }
        EXPECT_EQ(l->GetFeatureCount(TRUE), GIntBig(t.elements.size()));
        const Layer& layer = doc.scene.layers[t.layer];
        const ElementKind kind = t.polygons ? ElementKind::Area : ElementKind::Curve;
        std::vector<ElementId> ids;
        l->ResetReading();
        for (auto& f : *l) {
            const auto id = ElementId(f->GetFieldAsInteger64("lacet_id"));
            ids.push_back(id);
            SCOPED_TRACE("element " + std::to_string(id));
            const OGRGeometry* g = f->GetGeometryRef();
            ASSERT_NE(g, nullptr);
            if (t.polygons) {
                ASSERT_LT(id, layer.areas.size());
                const Area& a = layer.areas[id];
                ASSERT_TRUE(a.alive);
                EXPECT_EQ(f->GetFieldAsInteger("class"), a.cls);
                EXPECT_EQ(f->GetFieldAsDouble("wf"), double(a.wf));
                ASSERT_EQ(wkbFlatten(g->getGeometryType()), wkbPolygon);
                const auto* p = g->toPolygon();
                ASSERT_EQ(std::size_t(p->getNumInteriorRings()) + 1, a.loops.size());
                if (OGRGeometryFactory::haveGEOS()) {
                    EXPECT_TRUE(p->IsValid());
                }
                // The exterior ring follows the loop of largest area, each hole another loop.
                std::size_t outer = 0;
                std::vector<std::vector<Vertex>> chains;
                for (const auto& loop : a.loops) chains.push_back(loopVertices(layer, loop));
                for (std::size_t k = 1; k < chains.size(); ++k)
                    if (std::abs(chainArea(chains[k])) > std::abs(chainArea(chains[outer]))) outer = k;
                const OGRLinearRing* exterior = p->getExteriorRing();
                EXPECT_TRUE(withinTolerance(points(*exterior), chains[outer], tolerance));
                EXPECT_FALSE(exterior->isClockwise());
                EXPECT_TRUE(exterior->get_IsClosed());
                std::vector<bool> used(chains.size(), false);
                used[outer] = true;
                for (int r = 0; r < p->getNumInteriorRings(); ++r) {
                    const OGRLinearRing* hole = p->getInteriorRing(r);
                    EXPECT_TRUE(hole->isClockwise());
                    EXPECT_TRUE(hole->get_IsClosed());
                    bool matched = false;
                    for (std::size_t k = 0; k < chains.size() && !matched; ++k)
                        if (!used[k] && withinTolerance(points(*hole), chains[k], tolerance)) used[k] = matched = true;
                    EXPECT_TRUE(matched) << "interior ring " << r << " follows no hole loop";
                }
            } else {
                ASSERT_LT(id, layer.curves.size());
                const Curve& c = layer.curves[id];
                ASSERT_TRUE(c.alive);
                EXPECT_EQ(f->GetFieldAsInteger("class"), c.cls);
                EXPECT_EQ(f->GetFieldAsDouble("w"), double(c.w));
                EXPECT_EQ(f->GetFieldAsDouble("wf"), double(c.wf));
                EXPECT_EQ(f->GetFieldAsInteger("bridge"), (c.flags & kBridge) ? 1 : 0);
                EXPECT_EQ(f->GetFieldAsInteger("tunnel"), (c.flags & kTunnel) ? 1 : 0);
                ASSERT_EQ(wkbFlatten(g->getGeometryType()), wkbLineString);
                const auto line = points(*g->toLineString());
                EXPECT_EQ(line.front(), c.vertices.front().p);
                EXPECT_EQ(line.back(), c.vertices.back().p);
                EXPECT_TRUE(withinTolerance(line, c.vertices, tolerance));
            }
            // Every kept source attribute, its first value, under the column named after its key.
            std::map<std::string, std::string> first;
            for (const ElementAttribute& at : doc.attributes)
                if (at.layer == t.layer && at.kind == kind && at.id == id) first.emplace(at.key, at.value);
            std::size_t found = 0;
            for (int i = 0; i < f->GetFieldCount(); ++i) {
                const std::string name = f->GetFieldDefnRef(i)->GetNameRef();
                if (f->GetFieldDefnRef(i)->GetType() != OFTString || !f->IsFieldSetAndNotNull(i)) continue;
                bool matches = false;
                for (const auto& [key, value] : first) matches = matches || value == f->GetFieldAsString(i);
                EXPECT_TRUE(matches) << "column " << name << " holds '" << f->GetFieldAsString(i) << "'";
                ++found;
            }
            EXPECT_EQ(found, first.size());
        }
        std::vector<ElementId> expected = t.elements;
        std::sort(ids.begin(), ids.end());
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(ids, expected);
        (t.polygons ? seen.areas : seen.curves) += ids.size();
    }
    const Expected all = expectedCounts(doc.scene);
    EXPECT_EQ(seen.curves, all.curves);
    EXPECT_EQ(seen.areas, all.areas);
    EXPECT_TRUE(messages.list().empty()) << messages.list().front();
}

inline std::vector<std::string> tableNames(const std::string& path) {
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    std::vector<std::string> names;
    auto s = db.prepare("SELECT table_name FROM gpkg_contents WHERE data_type = 'features' ORDER BY table_name");
    while (s.step()) names.push_back(s.text(0));
    return names;
}

inline OGRSpatialReference sceneSrs() {
    OGRSpatialReference srs;
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    EXPECT_EQ(srs.importFromWkt(kWkt), OGRERR_NONE);
    return srs;
}

// ---- tests ----

}  // namespace
}  // namespace lacet
