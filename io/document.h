#pragma once
// What a scene file holds, in memory: the scene (model/graph.h), where it lies on the Earth, its DEM
// and the attributes kept from the source data. The editor, the import and the commands pass it
// around; io/scene_file.h saves and loads it (GeoPackage, SQLite), and this header pulls in neither.

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

struct SceneDocument {
    Scene scene;
    Georeference georeference;
    std::optional<Dem> dem;
    std::vector<ElementAttribute> attributes;  // each names an existing element slot
};

}  // namespace lacet
