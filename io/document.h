#pragma once
// What a scene file holds, in memory: the scene (model/graph.h), where it lies on the Earth, its DEM
// and the attributes kept from the source data. The editor, the import and the commands pass it
// around; io/scene_file.h saves and loads it (GeoPackage, SQLite), and this header pulls in neither.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/georeference.h"
#include "model/graph.h"
#include "raster/dem.h"

namespace lacet {

// An attribute kept from the source data on a root element (a road's name, its OSM layer...).
struct ElementAttribute {
    LayerId layer = 0;
    ElementKind kind = ElementKind::Curve;
    ElementId id = 0;
    std::string key, value;
    friend bool operator==(const ElementAttribute&, const ElementAttribute&) = default;
};

class DemLodFile;  // io/dem_lod.h

struct SceneDocument {
    Scene scene;
    Georeference georeference;
    // The DEM held in memory. With demLod, it is derived: the level levelAtMost(layout,
    // kInMemoryDemSide) of the streamed tree (io/dem_lod.h: readDemLevel), so that every command
    // that works on an in-memory DEM works on a coarser one.
    std::optional<Dem> dem;
    // The scene's DEM when it is larger than memory: a non-redundant LOD block tree read from a
    // GeoPackage (a scene file, or an import's output), shared by the copies of the document. A save
    // copies its tiles into the new file (from its path(), before the new file replaces anything).
    std::shared_ptr<const DemLodFile> demLod;
    std::vector<ElementAttribute> attributes;  // each names an existing element slot
};

}  // namespace lacet
