#include "app/import_summary.h"

#include <nlohmann/json.hpp>

namespace lacet::app {

void printImportSummary(std::ostream& out, const ImportReport& r, const std::string& file) {
    const nlohmann::json j = r.json();
    out << "Imported into " << file << " in " << r.ms / 1000.0 << " s: " << r.featuresRead << " features read, " << r.unmapped
        << " not mapped, " << r.problemCount() << " problems\n";
    for (const auto& l : j["layers"])
        out << "  " << l["name"].get<std::string>() << ": curves by class " << l["curves_by_class"].dump() << ", areas by class "
            << l["areas_by_class"].dump() << ", nodes " << l["nodes"] << ", junctions " << l["junctions"] << ", bridges " << l["bridges"]
            << "\n";
    out << "  fit: " << j["fit"].dump() << "\n  duplicates: " << j["duplicates"].dump() << "\n  dem: " << j["dem"].dump()
        << "\n  crs: " << j["crs"].dump() << "\n  river nodes below their surroundings: " << r.riverNodesBelowSurroundings * 100.0
        << " % of " << r.riverNodesChecked << "\n  river areas: " << r.network.riverAreas << ", " << r.network.riverAreasWithAxial
        << " with an axial curve (following its profile), " << r.network.riverAreas - r.network.riverAreasWithAxial
        << " without (flat at their lowest border height, as lakes)\n  problems by reason: " << j["problems_by_reason"].dump() << "\n";
    if (r.vectorPartLevel >= 0)
        out << "  vectors out of core: " << j["vectors_out_of_core"].dump() << "\n";
}

}  // namespace lacet::app
