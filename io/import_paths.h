#pragma once
// The paths of an import, checked before any work (issue 12: a failed import must neither run for
// minutes first nor destroy anything): every input exists and is readable, no input is given
// twice, the output's directory exists and is writable, the output is none of the inputs, and an
// existing output is replaced only when it is a Lacet scene (io/scene_file.h isLacetScene) or
// when forced. GDAL virtual paths (/vsizip/archive.zip/inner, /vsigzip/...) are checked through
// GDAL and compared by the real file they live in.
//
// Throws ImportPathError naming the path and the reason (with the system's message, e.g. "No such
// file or directory").

#include <stdexcept>
#include <string>
#include <vector>

namespace lacet {

class ImportPathError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ImportPaths {
    std::vector<std::string> dems;     // rasters, VRTs or directories (io/dem_import.h)
    std::vector<std::string> vectors;  // vector files or directories (Shapefile folders)
    std::string mapping;               // empty: the default mapping
    std::string out;                   // the scene file to write
    bool force = false;                // replace `out` even when it is not a Lacet scene
};

void checkImportPaths(const ImportPaths& paths);

}  // namespace lacet
