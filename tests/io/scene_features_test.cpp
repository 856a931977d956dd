// The feature tables of the scene file (io/scene_features.h), read back through GDAL/OGR as a GIS
// tool would: tables, geometry types, SRS, counts, attributes, holes, the spatial index, and the
// distance between each feature and its exact Bezier spline measured both ways by dense sampling.
#include "tests/io/scene_features_fixture.h"

namespace lacet {
namespace {

TEST_F(SceneFeatures, EveryLayerIsAFeatureTableWithinTheToleranceOfItsSplines) {
    const std::string path = file("scene.gpkg");
    const SceneDocument doc = handDocument(true, true);
    saveScene(path, doc);
    EXPECT_EQ(tableNames(path), (std::vector<std::string>{"forests", "lakes_ponds", "lakes_ponds_lines", "layer_dem",
                                                           "rivers", "roads", "roads_2"}));
    const auto tables = planFeatureTables(doc, {"dem"});
    ASSERT_EQ(tables.size(), 7u);
    const OGRSpatialReference srs = sceneSrs();
    checkTables(path, doc, tables, &srs, FeatureTableParams{}.tolerance);
    // The DEM's CRS, reused.
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    const std::int64_t demSrs = db.queryInteger("SELECT srs_id FROM gpkg_contents WHERE table_name = 'dem'");
    EXPECT_GT(demSrs, 0);
    for (const FeatureTable& t : tables) EXPECT_EQ(srsIdOf(path, t.name), demSrs) << t.name;
    EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_spatial_ref_sys WHERE srs_id >= 100000 AND srs_id != " +
                              std::to_string(demSrs)),
              0);
}

TEST_F(SceneFeatures, AttributesAndFlagsRoundTripUnderSanitizedColumns) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true, true));
    Dataset ds = openVector(path);
    ASSERT_TRUE(ds);
    OGRLayer* roads = ds->GetLayerByName("roads");
    ASSERT_NE(roads, nullptr);
    std::map<std::int64_t, OGRFeatureUniquePtr> byId;
    for (auto& f : *roads) byId[f->GetFieldAsInteger64("lacet_id")] = std::move(f);
    ASSERT_EQ(byId.size(), 4u);  // the dead curve is left out
    EXPECT_FALSE(byId.contains(3));
    OGRFeature& r0 = *byId.at(0);
    EXPECT_EQ(fieldText(r0, "name"), "Avinguda Meritxell");
    EXPECT_EQ(fieldText(r0, "attr_bridge"), "yes");  // "bridge" is the flag column
    EXPECT_EQ(fieldText(r0, "name_en"), "Meritxell Avenue");
    EXPECT_EQ(fieldText(r0, "layer"), "<null>");
    EXPECT_EQ(r0.GetFieldAsInteger("bridge"), 1);
    EXPECT_EQ(r0.GetFieldAsInteger("tunnel"), 0);
    EXPECT_EQ(r0.GetFieldDefnRef(r0.GetFieldIndex("bridge"))->GetSubType(), OFSTBoolean);
    OGRFeature& r1 = *byId.at(1);
    EXPECT_EQ(fieldText(r1, "name"), "Carrer d'Anna \"la\" \xc3\xa9s");
    EXPECT_EQ(fieldText(r1, "layer"), "-1");
    EXPECT_EQ(r1.GetFieldAsInteger("tunnel"), 1);
    EXPECT_EQ(fieldText(*byId.at(4), "junction"), "roundabout");
    EXPECT_EQ(r1.GetFieldAsDouble("w"), 4.0);
    EXPECT_EQ(byId.at(2)->GetFieldAsDouble("wf"), 7.25);
    EXPECT_EQ(byId.at(2)->GetFieldAsInteger("class"), 3);

    OGRLayer* lakes = ds->GetLayerByName("lakes_ponds");
    ASSERT_NE(lakes, nullptr);
    OGRFeatureUniquePtr lake(lakes->GetNextFeature());
    ASSERT_TRUE(lake);
    EXPECT_EQ(fieldText(*lake, "name"), "Estany");
    EXPECT_EQ(fieldText(*lake, "attr_3d"), "x");  // a column name starts with a letter

    OGRLayer* fields = ds->GetLayerByName("layer_dem");
    ASSERT_NE(fields, nullptr);
    std::map<std::string, std::string> crops;
    for (auto& f : *fields) crops[std::to_string(f->GetFieldAsInteger64("lacet_id"))] = fieldText(*f, "crop");
    EXPECT_EQ(crops, (std::map<std::string, std::string>{{"0", "wheat"}, {"1", "maize"}}));  // the first value
    OGRLayer* empty = ds->GetLayerByName("roads_2");
    ASSERT_NE(empty, nullptr);
    EXPECT_EQ(empty->GetFeatureCount(TRUE), 0);
}

TEST_F(SceneFeatures, TheFileStillLoadsBitForBitAndGdalStillReadsTheDem) {
    const std::string path = file("scene.gpkg");
    const SceneDocument doc = handDocument(true, true);
    saveScene(path, doc);
    EXPECT_TRUE(identical(loadScene(path), doc));
    Dataset raster(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    ASSERT_TRUE(raster);
    EXPECT_EQ(raster->GetRasterXSize(), doc.dem->width());
    EXPECT_EQ(raster->GetRasterYSize(), doc.dem->height());
    float corner = 0.0f;  // raster row 0 is the top: Dem row height - 1
    ASSERT_EQ(raster->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 1, 1, &corner, 1, 1, GDT_Float32, 0, 0, nullptr), CE_None);
    EXPECT_EQ(corner, doc.dem->heights()[std::size_t(doc.dem->height() - 1) * std::size_t(doc.dem->width())]);
    // Saved again over itself, the file is whole, its feature tables rewritten, not doubled.
    saveScene(path, doc);
    EXPECT_TRUE(identical(loadScene(path), doc));
    EXPECT_EQ(tableNames(path).size(), 7u);
}

TEST_F(SceneFeatures, TheSpatialIndexHoldsTheFeaturesEnvelopes) {
    const std::string path = file("scene.gpkg");
    saveScene(path, handDocument(true, true));
    Dataset ds = openVector(path);
    ASSERT_TRUE(ds);
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    const double boxes[][4] = {{0, 0, 400, 400}, {1000, 0, 1110, 150}, {1450, 1150, 1750, 1450}, {-10, -10, 2010, 2010}};
    for (const std::string table : {"roads", "rivers", "layer_dem", "forests", "lakes_ponds", "lakes_ponds_lines"}) {
        SCOPED_TRACE(table);
        OGRLayer* l = ds->GetLayerByName(table.c_str());
        ASSERT_NE(l, nullptr);
        OGRLayer* has = ds->ExecuteSQL(("SELECT HasSpatialIndex('" + table + "', 'geom')").c_str(), nullptr, nullptr);
        ASSERT_NE(has, nullptr);
        OGRFeatureUniquePtr row(has->GetNextFeature());
        ASSERT_TRUE(row);
        EXPECT_EQ(row->GetFieldAsInteger(0), 1);
        row.reset();
        ds->ReleaseResultSet(has);
        for (const auto& b : boxes) {
            OGRPolygon rect;
            OGRLinearRing ring;
            for (const auto& [x, y] : {std::pair{b[0], b[1]}, {b[2], b[1]}, {b[2], b[3]}, {b[0], b[3]}, {b[0], b[1]}})
                ring.addPoint(x, y);
            rect.addRing(&ring);
            // The R-tree (its float boxes hold the double ones) against the envelopes OGR reads.
            std::vector<GIntBig> byEnvelope, byRtree, intersecting, filtered;
            l->SetSpatialFilter(nullptr);
            for (auto& f : *l) {
                OGREnvelope e;
                f->GetGeometryRef()->getEnvelope(&e);
                if (e.MinX <= b[2] && b[0] <= e.MaxX && e.MinY <= b[3] && b[1] <= e.MaxY) byEnvelope.push_back(f->GetFID());
                if (OGRGeometryFactory::haveGEOS() && f->GetGeometryRef()->Intersects(&rect))
                    intersecting.push_back(f->GetFID());
            }
            auto s = db.prepare("SELECT id FROM \"rtree_" + table +
                                "_geom\" WHERE minx <= ? AND maxx >= ? AND miny <= ? AND maxy >= ? ORDER BY id");
            s.bind(1, b[2]);
            s.bind(2, b[0]);
            s.bind(3, b[3]);
            s.bind(4, b[1]);
            while (s.step()) byRtree.push_back(s.integer(0));
            EXPECT_EQ(byRtree, byEnvelope);
            // OGR's spatial filter, which goes through the index.
            if (OGRGeometryFactory::haveGEOS()) {
                l->SetSpatialFilter(&rect);
                for (auto& f : *l) filtered.push_back(f->GetFID());
                l->SetSpatialFilter(nullptr);
                EXPECT_EQ(filtered, intersecting);
            }
        }
    }
    EXPECT_EQ(db.queryInteger("SELECT count(*) FROM rtree_roads_geom"), 4);
    EXPECT_EQ(db.queryInteger("SELECT count(*) FROM gpkg_extensions WHERE extension_name = 'gpkg_rtree_index'"), 7);
    EXPECT_EQ(db.queryInteger("SELECT feature_count FROM gpkg_ogr_contents WHERE table_name = 'roads'"), 4);
}

TEST_F(SceneFeatures, TheIndexNamesEachTablesLayerAndLargestWidths) {
    const std::string path = file("scene.gpkg");
    const SceneDocument doc = handDocument(true, true);
    saveScene(path, doc);
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    std::vector<std::string> taken;  // planFeatureTables() as if the file held no feature table
    for (const char* t : {"dem", "lacet_meta", "lacet_layers", "lacet_nodes", "lacet_curves", "lacet_areas", "lacet_attributes"})
        taken.push_back(t);
    const auto planned = planFeatureTables(doc, taken);
    EXPECT_EQ(db.queryInteger(std::string("SELECT count(*) FROM ") + kFeatureIndexTable), std::int64_t(planned.size()));
    for (const FeatureTable& t : planned) {
        SCOPED_TRACE(t.name);
        const Layer& layer = doc.scene.layers[t.layer];
        double curveWf = 0.0, areaWf = 0.0;
        for (ElementId id : t.elements) {
            if (!t.polygons) {
                curveWf = std::max(curveWf, double(layer.curves[id].wf));
                continue;
            }
            areaWf = std::max(areaWf, double(layer.areas[id].wf));
            for (const auto& loop : layer.areas[id].loops)
                for (const AreaEdge& e : loop) curveWf = std::max(curveWf, double(layer.curves[e.curve].wf));
        }
        auto s = db.prepare(std::string("SELECT layer, polygons, tolerance, max_curve_wf, max_area_wf FROM ") + kFeatureIndexTable +
                            " WHERE table_name = ?");
        s.bindText(1, t.name);
        ASSERT_TRUE(s.step());
        EXPECT_EQ(s.integer(0), std::int64_t(t.layer));
        EXPECT_EQ(s.integer(1) != 0, t.polygons);
        EXPECT_EQ(s.real(2), FeatureTableParams{}.tolerance);
        EXPECT_EQ(s.real(3), curveWf);
        EXPECT_EQ(s.real(4), areaWf);
        EXPECT_TRUE(db.hasTable(featureRtreeName(t.name)));
    }
}

TEST_F(SceneFeatures, WithoutADemTheGeoreferenceIsANewSrsRow) {
    const std::string path = file("nodem.gpkg");
    const SceneDocument doc = handDocument(false, true);
    saveScene(path, doc);
    const OGRSpatialReference srs = sceneSrs();
    checkTables(path, doc, planFeatureTables(doc, {}), &srs, FeatureTableParams{}.tolerance);
    const std::int64_t id = srsIdOf(path, "roads");
    EXPECT_GE(id, 100000);
    SqliteDb db(path, SqliteDb::Mode::ReadOnly);
    EXPECT_EQ(db.queryText("SELECT definition FROM gpkg_spatial_ref_sys WHERE srs_id = " + std::to_string(id)), kWkt);
    EXPECT_EQ(db.queryInteger("SELECT srs_id FROM gpkg_contents WHERE table_name = 'forests'"), id);
    EXPECT_TRUE(identical(loadScene(path), doc));
}

TEST_F(SceneFeatures, WithoutAGeoreferenceTheSrsIsUndefinedCartesian) {
    for (const bool withDem : {true, false}) {
        SCOPED_TRACE(withDem ? "with a DEM" : "without a DEM");
        const std::string path = file(withDem ? "dem.gpkg" : "nodem.gpkg");
        const SceneDocument doc = handDocument(withDem, false);
        saveScene(path, doc);
        checkTables(path, doc, planFeatureTables(doc, {}), nullptr, FeatureTableParams{}.tolerance);
        for (const FeatureTable& t : planFeatureTables(doc, {})) EXPECT_EQ(srsIdOf(path, t.name), -1) << t.name;
        EXPECT_TRUE(identical(loadScene(path), doc));
    }
}

TEST_F(SceneFeatures, ASyntheticSceneWithHolesIsWithinTheTolerance) {
    SceneDocument doc;
    doc.scene = makeSyntheticScene({3, 3000});
    doc.georeference.valid = true;
    doc.georeference.crsWkt = kWkt;
    const Box& e = doc.scene.extent;
    std::vector<float> z(std::size_t(60 * 50));
    for (std::size_t k = 0; k < z.size(); ++k) z[k] = float(200.0 + 10.0 * std::sin(0.1 * double(k)));
    doc.dem.emplace(e, 60, 50, std::move(z));
    std::size_t holes = 0;
    for (const Layer& layer : doc.scene.layers)
        for (const Area& a : layer.areas) holes += a.alive && a.loops.size() > 1;
    ASSERT_GT(holes, 0u);
    const std::string path = file("synthetic.gpkg");
    saveScene(path, doc);
    const auto tables = planFeatureTables(doc, {"dem"});
    const OGRSpatialReference srs = sceneSrs();
    checkTables(path, doc, tables, &srs, FeatureTableParams{}.tolerance);
    EXPECT_TRUE(identical(loadScene(path), doc));
}

TEST_F(SceneFeatures, NamesAreSanitizedAndNeverClash) {
    SceneDocument doc;
    doc.scene.extent = {{0.0, 0.0}, {10.0, 10.0}};
    for (const char* name : {"Roads", "roads", "", "2nd", "gpkg_contents", "rtree_x", "lacet_meta", "Dem", "Rivers",
                             "\xc3\xa9t\xc3\xa9 / river", "roads_2"}) {
        Layer l;
        l.name = name;
        l.kind = LayerKind::Roads;
        doc.scene.layers.push_back(std::move(l));
    }
    std::vector<std::string> names;
    for (const FeatureTable& t : planFeatureTables(doc, {"dem", "rivers"})) names.push_back(t.name);
    EXPECT_EQ(names, (std::vector<std::string>{"roads", "roads_2", "layer", "layer_2nd", "layer_gpkg_contents",
                                               "layer_rtree_x", "layer_lacet_meta", "layer_dem", "rivers_2",
                                               "t_river", "roads_2_2"}));
}

TEST_F(SceneFeatures, FlatteningMeetsEachToleranceWithFewerPointsWhenLooser) {
    const std::vector<Vertex> chain = {on(0.0, 0.0),     control(300.0, 500.0), control(700.0, -400.0), on(1000.0, 0.0),
                                       control(1200.0, 300.0), on(1300.0, 100.0), on(1400.0, 100.0)};
    std::size_t previous = SIZE_MAX;
    for (const double tolerance : {0.001, 0.01, 0.1, 1.0, 10.0}) {
        SCOPED_TRACE(tolerance);
        const std::vector<Vec2> line = flattenSpline(chain, tolerance);
        EXPECT_TRUE(withinTolerance(line, chain, tolerance));
        EXPECT_LT(line.size(), previous);
        previous = line.size();
    }
    // A straight piece is its chord; a point-like chain still gives a line string of two points.
    EXPECT_EQ(flattenSpline(std::vector<Vertex>{on(0.0, 0.0), control(1.0, 1.0), on(2.0, 2.0)}, 0.1).size(), 2u);
    EXPECT_EQ(flattenSpline(std::vector<Vertex>{on(5.0, 5.0), on(5.0, 5.0)}, 0.1).size(), 2u);
    EXPECT_THROW(flattenSpline(chain, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace lacet
