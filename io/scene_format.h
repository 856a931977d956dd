#pragma once
// Internals of the scene file (io/scene_file.h), shared by its parts and by nothing else:
//   scene_schema.cpp    the format's tables and their gpkg_contents entries, lacet_meta (doubles as
//                       exact hex text), the checks made on opening a file
//   scene_elements.cpp  the element tables: lacet_layers, lacet_nodes, lacet_curves, lacet_areas,
//                       lacet_attributes, written and read back
//   scene_file.cpp      saveScene (atomically, io/atomic_file.h), loadScene (with its DEM), isLacetScene
//   scene_region.cpp    loadSceneRegion (io/scene_region.h): the part of a scene a region needs
// Order of calls. Save: writeSceneTables (one transaction: the schema, lacet_meta, ElementTablesWriter,
// the feature tables). Load: openSceneTables (returns lacet_meta), readElementTables, then the DEM.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/document.h"
#include "io/scene_checksum.h"
#include "io/scene_file.h"
#include "io/sqlite_db.h"

namespace lacet {
struct SceneOverlay;
}  // namespace lacet

namespace lacet::scene_format {

inline constexpr const char* kFormatName = "lacet-scene";
inline constexpr std::int64_t kGpkgApplicationId = 0x47504B47;  // 'GPKG'
inline constexpr std::size_t kMaxLayers = 65536;                // LayerId is 16 bits
inline constexpr std::int64_t kMaxId = 0xffffffffLL;            // ElementId is 32 bits

// A problem with the file's contents (reason only); loadScene adds the file name.
class FormatError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// ---- scene_schema.cpp ----

// A layer whose elements are made while the file is written (saveSceneStreamed): `produce` calls
// its argument with each part (model/graph.h) in id order.
struct StreamedLayer {
    LayerId layer = 0;
    std::function<void(const std::function<void(Layer&& part)>& sink)> produce;
};
// The parts of every layer of a scene written in parts (saveSceneInParts).
struct StreamedParts {
    const std::vector<FeatureKindsPlan>* kinds = nullptr;
    std::function<std::size_t(Vec2)> lastPartAt;
    std::function<void(const std::function<void(ScenePart&& part)>& sink)> produce;
};

// Adds the lacet_* tables (and the feature tables, io/scene_features.h) to the GeoPackage at `path`,
// in one transaction. With `streamed`, that layer's elements are doc's followed by the parts
// `streamed->produce` makes, each checked by validate() on its own (a FormatError names the part),
// and the checksum is that of the rows written, read back in order.
// With `parts`, the parts saveSceneInParts describes after doc's elements, checked the same way.
void writeSceneTables(const std::string& path, const SceneDocument& doc, const StreamedLayer* streamed = nullptr,
                      const StreamedParts* parts = nullptr);

// The checksum (io/scene_checksum.h) of `doc` with the layers `fromRows` names summed from their
// rows in `db` as they are now (decoded and checked as readElementTables does), not from doc's
// (whose heads, name and kind, still count); doc gives the rest: attributes, georeference, DEM.
// Writes `checksum` and its parts into lacet_meta (the keys a format-1 file lacks added).
void writeChecksum(SqliteDb& db, const SceneChecksumParts& checksum);
SceneChecksumParts checksumOfRows(SqliteDb& db, const SceneDocument& doc, const std::function<bool(LayerId)>& fromRows);
// The same with every layer and the attributes from their rows (a scene written in parts).
SceneChecksumParts checksumOfAllRows(SqliteDb& db, const SceneDocument& doc);

using Meta = std::map<std::string, std::string>;

// Checks that `db` is an intact GeoPackage holding a Lacet scene of a known version (its size is
// `fileSize` bytes; with `wholeFileCheck`, every page read by SQLite's quick_check, O(file); a
// reader of a small part of a large file leaves it to SQLite's checks of the pages it reads);
// returns its lacet_meta. Throws FormatError.
Meta openSceneTables(SqliteDb& db, std::int64_t fileSize, bool wholeFileCheck = true);

// Values of lacet_meta; each throws FormatError naming the key when it is missing or malformed.
const std::string& metaValue(const Meta& meta, const std::string& key);
double metaDouble(const Meta& meta, const std::string& key);
std::int64_t metaInteger(const Meta& meta, const std::string& key, std::int64_t lo, std::int64_t hi);
Box metaBox(const Meta& meta, const std::string& prefix);  // prefix_min_x ... prefix_max_y

// ---- scene_elements.cpp ----

// Writes lacet_layers, lacet_nodes, lacet_curves, lacet_areas and lacet_attributes (created empty),
// a layer part at a time: layers(), then the elements of each layer in (layer, id) order, a part's
// rows with ids `o` more than their index in the part and its references written as they are
// (offsetElementIds first), then attributes().
// With `replace`, a row replaces the one of the same (layer, id) (a scene's edits saved in place).
class ElementTablesWriter {
public:
    explicit ElementTablesWriter(SqliteDb& db, bool replace = false);
    ~ElementTablesWriter();
    void layers(const Scene& scene);
    void elements(LayerId layer, const Layer& part, const ElementOffsets& o);
    void attributes(const SceneDocument& doc);

private:
    SqliteDb& db_;
    std::unique_ptr<SqliteStatement> node_, curve_, area_;
};

// Layer `layer`'s rows of one element table, in id order, decoded and checked as readElementTables
// does (FormatError naming the row); the count of the layer's rows first. For a checksum of what a
// streamed save wrote, without the layer in memory.
void forEachNodeRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t count)>& counted,
                    const std::function<void(const Node&)>& each);
void forEachCurveRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t count)>& counted,
                     const std::function<void(const Curve&)>& each);
void forEachAreaRow(SqliteDb& db, LayerId layer, const std::function<void(std::size_t count)>& counted,
                    const std::function<void(const Area&)>& each);

// Reads them back into doc.scene's layers and doc.attributes; throws FormatError naming the row.
void readElementTables(SqliteDb& db, SceneDocument& doc);

// For partial loads (io/scene_region.h): lacet_layers alone; the rows of single elements, each
// checked as readElementTables checks it (FormatError naming the row, also when it is missing);
// the attributes `wanted` keeps, of elements whose slots doc.scene's layers hold.
void readLayerTable(SqliteDb& db, Scene& scene);
class ElementRows {
public:
    explicit ElementRows(SqliteDb& db);
    ~ElementRows();
    Node node(LayerId layer, ElementId id);
    Curve curve(LayerId layer, ElementId id);
    Area area(LayerId layer, ElementId id);

private:
    std::unique_ptr<SqliteStatement> node_, curve_, area_;
};
// Reads lacet_attributes. Each must name an id below `slots(layer, kind)` (the file's count of that
// kind); `idIn(a)` is the id `a` names in `doc` (a part of the file read, io/scene_region.h), or
// kNoElement to skip it.
void readAttributesOf(SqliteDb& db, SceneDocument& doc, const std::function<std::size_t(LayerId, ElementKind)>& slots,
                      const std::function<ElementId(const ElementAttribute&)>& idIn);
// Reads the attributes of the elements of `doc`, a part of the file (Layer::sceneIds: each element's
// id in the file), through lacet_attributes' (layer, kind, id) index: a lookup per element, not a
// scan of the table, in the table's order as readAttributesOf gives them. Returns false, reading
// nothing, for a file written before the index (the caller scans it instead).
bool readPartAttributes(SqliteDb& db, SceneDocument& doc);

// ---- scene_feature_index.cpp: the feature tables as reads of parts of the file find them ----

// One read transaction over a read's statements: the file's shared lock taken once, not at each
// of many single-row statements (per statement, SQLite locks and checks for a hot journal: most of
// a small region's time). A read changes nothing: the end is a plain COMMIT.
class ReadTransaction {
public:
    explicit ReadTransaction(SqliteDb& db) : db_(db) { db_.exec("BEGIN"); }
    ~ReadTransaction() {
        try {
            db_.exec("COMMIT");
        } catch (...) {
        }
    }
    ReadTransaction(const ReadTransaction&) = delete;
    ReadTransaction& operator=(const ReadTransaction&) = delete;

private:
    SqliteDb& db_;
};

// A feature table of kFeatureIndexTable, or of the edits.
struct FeatureTableRef {
    std::string name;  // empty: a layer's features the file has no table for (the edits' alone)
    LayerId layer = 0;
    bool polygons = false;
};

// The file's feature tables (kFeatureIndexTable), with their largest tolerance and wf.
struct FeatureIndex {
    std::vector<FeatureTableRef> tables;
    double tolerance = 0.0, curveWf = 0.0, areaWf = 0.0;
};

// Reads kFeatureIndexTable; FormatError for a table row naming no layer, table or R-tree.
FeatureIndex readFeatureIndex(SqliteDb& db, const Scene& scene);

// Each of `layers` layers' ids in the element table `table`: its largest id + 1, through the
// (layer, id) index, not a scan of the table.
std::vector<std::size_t> fileIdCounts(SqliteDb& db, const char* table, std::size_t layers);

// The tables of the layers' features the file has none for and the edits add (name empty): found
// in the overlay alone. Throws FormatError for an edit of a layer the file has not.
void addOverlayTables(std::vector<FeatureTableRef>& tables, const SceneOverlay& overlay, std::size_t layers);

// The features of table `t` whose boxes meet `box` (their ids, below `count`): the file's R-tree's,
// except those `overlay` (nullptr: none) changed, found by their boxes now.
std::vector<ElementId> featuresIn(SqliteDb& db, const FeatureTableRef& t, const Box& box, std::size_t count, const SceneOverlay* overlay);

// ---- scene_file.cpp ----

// What loadScene does but the checksum: opens and checks `path`, reads lacet_meta, calls
// `readElements`, reads the DEM (unless `readDem` is false: the caller has it), validates the
// model; returns lacet_meta's checksum text, and in `formatVersion` the file's format version (the
// checksum's form). `wholeFileCheck`: openSceneTables'. Throws SceneFileError naming the file.
std::string loadSceneParts(const std::string& path, SceneDocument& doc,
                           const std::function<void(SqliteDb&, SceneDocument&)>& readElements, bool readDem = true,
                           bool wholeFileCheck = true, int* formatVersion = nullptr);
// The same over `connection`'s file, kept open.
std::string loadSceneParts(SceneFileConnection& connection, SceneDocument& doc,
                           const std::function<void(SqliteDb&, SceneDocument&)>& readElements, bool readDem = true,
                           bool wholeFileCheck = true, int* formatVersion = nullptr);

}  // namespace lacet::scene_format
