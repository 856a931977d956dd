#pragma once
// The import's report in a few lines for a person (`lacet import`, and `lacet edit` when it
// imports its sample scene): what was read, kept and fitted, the DEM, the CRS and the problems
// by reason. `lacet import --json` prints the whole report instead (ImportReport::json()).

#include <ostream>
#include <string>

#include "io/scene_import.h"

namespace lacet::app {

void printImportSummary(std::ostream& out, const ImportReport& report, const std::string& file);

}  // namespace lacet::app
