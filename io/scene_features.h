#pragma once
// The feature tables of the scene file: the scene's layers as GeoPackage vector features, so that
// QGIS, ogrinfo and gdal_rasterize see the roads, rivers and areas. They are derived data, written
// by saveScene (io/scene_file.h) beside the exact Bezier tables (lacet_*), which stay the truth:
// loadScene ignores them and the checksum does not cover them.
//
// Order of calls: saveScene opens its SQLite transaction, writes the lacet_* tables, then calls
// writeFeatureTables on the same connection, inside the same transaction.
//
// What is written, per layer (only alive elements):
//   - a LINESTRING table of its curves that belong to no alive area (every curve of a road or river
//     layer; an axial curve or a loose curve of an area layer), one feature per curve;
//   - a POLYGON table of its alive areas, one feature per area: the loop of largest absolute area is
//     the exterior ring (counter-clockwise), the others interior rings (clockwise), each ring closed.
// Roads and rivers layers always get their LINESTRING table and a POLYGON table only when they hold
// areas; the other kinds the reverse. Each feature's geometry is the exact Bezier spline flattened
// by de Casteljau halving until each piece's control points lie within `tolerance` of its chord,
// so the polyline and the spline are within `tolerance` of each other (Hausdorff).
//
// Columns: fid, geom, lacet_id (the element id), class (cls), w (curves only), wf, bridge and tunnel
// (curves only, booleans from CurveFlag), then one TEXT column per source attribute key present on
// the table's elements (SceneDocument::attributes; NULL where an element lacks it; the first value
// when an element has a key twice). Column names are the key in lowercase ASCII letters, digits and
// '_' (every run of other characters becomes one '_', none at the ends), prefixed with "attr_" when
// that clashes with a fixed column or does not start with a letter ("attr" when empty), then
// suffixed "_2", "_3"... until unique.
//
// Table names are the layer name made the same way ("layer" when empty; prefixed "layer_" when not
// starting with a letter, or equal to "dem" or starting with "lacet_", "gpkg_", "rtree_" or "sqlite_"), the
// second table of a layer suffixed "_areas" (roads, rivers) or "_lines" (other kinds), then "_2",
// "_3"... until the name is free in the file. gpkg_contents.description starts with
// "Lacet <kind> layer" (kind as toString(LayerKind)), so scripts can pick tables by kind.
//
// Coordinates are scene CRS metres. The SRS (gpkg_spatial_ref_sys) is the DEM raster's when the
// georeference is valid and GDAL registered one for the DEM (or the streamed DEM tree's, which
// saveScene gives the scene's CRS: featureSrsId below); else, with a valid georeference, its
// WKT in a new row (srs_id 100000 or above, as GDAL numbers CRSs it cannot identify); without a
// georeference, -1 ("undefined Cartesian coordinate reference system").
//
// Table kFeatureIndexTable (table_name, layer, polygons, tolerance, max_curve_wf, max_area_wf) lists
// the tables written, with the largest wf of their curves (a polygon table's: of its areas' loops and
// axial curves) and of their areas, so that io/scene_region.h finds a layer's curves and areas by
// bounding box through their R-trees, and knows how far around a region they may reach.
//
// Each table gets an R-tree spatial index (GeoPackage extension gpkg_rtree_index, with the standard
// triggers, which call the ST_* functions GIS tools register) and, when the file has GDAL's
// gpkg_ogr_contents table, its feature count and GDAL's count triggers, as GDAL writes them.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <set>
#include <string>
#include <vector>

#include "io/document.h"
#include "io/sqlite_db.h"
#include "model/changeset.h"

namespace lacet {

inline constexpr const char* kFeatureIndexTable = "lacet_feature_tables";
// The name of the R-tree of feature table `table`.
inline std::string featureRtreeName(const std::string& table) { return "rtree_" + table + "_geom"; }

struct FeatureTableParams {
    // Largest distance (metres, > 0) between a feature's polyline and its Bezier spline, both ways.
    // 0.1 m is a tenth of the finest DEM cells Lacet imports and below what GIS data states.
    double tolerance = 0.1;
};

// One feature table, as planned and written.
struct FeatureTable {
    std::string name;         // SQLite table name
    LayerId layer = 0;
    bool polygons = false;    // POLYGON of areas, else LINESTRING of curves
    std::vector<ElementId> elements;  // the features' element ids, in fid order (fid = index + 1)
};

// The tables writeFeatureTables makes for `doc`, with their names as if `takenNames` (lowercase
// table names already in the file) were all the file holds. Pure: no database.
std::vector<FeatureTable> planFeatureTables(const SceneDocument& doc, const std::vector<std::string>& takenNames);

// Writes the feature tables of `doc` (above) into `db`, a GeoPackage with its required tables
// (gpkg_contents, gpkg_spatial_ref_sys), inside the caller's open transaction; `doc.scene` passes
// validate() (model/validate.h), as saveScene checks first. Throws SqliteError
// when SQLite fails and std::invalid_argument for a tolerance that is not > 0. Returns the tables.
std::vector<FeatureTable> writeFeatureTables(SqliteDb& db, const SceneDocument& doc,
                                             const FeatureTableParams& params = {});

// writeFeatureTables a part at a time, for a scene written before it is whole (saveSceneStreamed,
// io/scene_file.h): the constructor plans the tables from `head` (the document as far as it is
// known: every layer's name and kind, the attributes) and creates them with their R-trees; add()
// writes the features of one part of a layer (model/graph.h: its references local, its ids `o` more
// than their index), parts of a layer in id order; finish() registers the tables (extent, triggers,
// GDAL's counts) and writes kFeatureIndexTable. A part whose features need a table the plan left
// out (curves outside areas in a fields layer planned empty) is refused with std::invalid_argument.
// Parts carry no attributes: the feature's attribute columns are those of `head`'s elements.
//
// A scene written in parts of every layer (saveSceneInParts) plans its tables from `kinds` instead:
// per layer, whether it has line features and areas, and the attribute keys of each; add() then
// takes the part's attributes (ids local to the part).
struct FeatureKindsPlan {
    bool lines = false, areas = false;
    std::set<std::string> lineKeys, areaKeys;
};
class FeatureTablesWriter {
public:
    FeatureTablesWriter(SqliteDb& db, const SceneDocument& head, const FeatureTableParams& params = {},
                        const std::vector<FeatureKindsPlan>* kinds = nullptr);
    ~FeatureTablesWriter();
    void add(LayerId layer, const Layer& part, const ElementOffsets& o, const std::vector<ElementAttribute>* partAttributes = nullptr);
    std::vector<FeatureTable> finish();

private:
    struct Table;
    struct State;
    SqliteDb& db_;
    const SceneDocument& head_;
    FeatureTableParams params_;
    std::unique_ptr<State> state_;
};

// The feature tables of a scene file edited in place (io/scene_save_edits.h: a lazy session's edits
// saved), inside the caller's open transaction, after the element tables hold the edited rows:
// set() gives each changed curve or area the feature writeFeatureTables would give it now, in
// the file's ids. A feature found is updated (geometry and fixed columns; its attribute columns
// stay, as attributes are never edited), a feature gone is deleted, a new one is inserted with
// its attributes from lacet_attributes (a column added for a key its table has none for; a key's
// column is found by the naming rule above before its suffix, so where two keys make the same
// name, "Name" and "name", the first in byte order fills it and the other is left out, where a
// whole save would give it "name_2"), into a table made when its layer has none of that kind
// (named as above). Its R-tree follows through the GeoPackage triggers, for which the
// connection gets the ST_* functions they call; GDAL's counts through its own. finish()
// enlarges the tables' extents in gpkg_contents and their largest wf in kFeatureIndexTable (an
// upper bound: never lowered, what io/scene_region.h needs). Throws SqliteError, and
// std::invalid_argument for a file without kFeatureIndexTable.
class FeatureTablesEditor {
public:
    FeatureTablesEditor(SqliteDb& db, const SceneDocument& head);
    ~FeatureTablesEditor();
    struct Counts {
        std::size_t updated = 0, inserted = 0, deleted = 0, tablesMade = 0;
    };
    // Curve or area `ref` (layer, kind, file id) now: `local` holds it at `id` with what its
    // feature needs, in ids of `local` (a curve's areas; an area's loop curves and axial curve).
    // `before`: a box its feature before the edits meets (none: it had none).
    void set(const ElementRef& ref, const std::optional<Box>& before, const Layer& local, ElementId id);
    Counts finish();

private:
    struct Table;
    Table& table(LayerId layer, bool polygons);  // made when missing
    void insert(Table& t, const ElementRef& ref);
    SqliteDb& db_;
    const SceneDocument& head_;
    std::vector<std::unique_ptr<Table>> tables_;
    Counts counts_;
};

// The gpkg_spatial_ref_sys row of the scene's CRS in `db` (the SRS above): -1 without a valid
// georeference; else the DEM raster's row when GDAL registered one (srs_id > 0), else the row of a
// streamed DEM's tree (kDemLodTable's gpkg_contents srs_id > 0) when `doc.demLod`, else a new row
// of the georeference's WKT. saveScene calls it before it copies a streamed DEM's tree (copyDemLod,
// io/dem_lod.h) so that the tree and the feature tables share one row. Throws SqliteError.
std::int64_t featureSrsId(SqliteDb& db, const SceneDocument& doc);

// The polyline of a vertex chain (on-curve, 0..2 controls, on-curve...): its first point, then the
// end of each flat sub-piece of each Bezier piece, halved until flatness() <= tolerance (metres,
// > 0); a point equal to the one before it is left out, except that a chain gives two points at least.
std::vector<Vec2> flattenSpline(std::span<const Vertex> vertices, double tolerance);

// The box the feature of curve `c` (of `layer`) or area `a` has in its table's R-tree, as
// writeFeatureTables writes it with `tolerance`: its polyline's envelope, rounded outward to
// floats as SQLite's R-tree stores it; none where the element has no feature (dead, or a curve of
// an alive area's loop). An area's loops and a curve's areas name elements of `layer`.
std::optional<Box> featureBox(const Layer& layer, const Curve& c, double tolerance);
std::optional<Box> featureBox(const Layer& layer, const Area& a, double tolerance);

}  // namespace lacet
