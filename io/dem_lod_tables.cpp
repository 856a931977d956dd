// The GeoPackage side of the DEM LOD tree (io/dem_lod.h) that the writer, the reader and the copy
// share: the meta table, the exact text of doubles in kDemLodMetaTable, the messages (the coverage's
// tables are io/gpkg_coverage.h's).
#include <charconv>
#include <cmath>

#include "io/dem_lod_internal.h"
#include "io/sqlite_db.h"

namespace lacet::dem_lod_detail {

// C hex float ("0x1.f4p+9", "-0x0p+0"), exact and locale-independent; finite values only.
std::string hexText(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, std::fabs(v), std::chars_format::hex);
    return std::string(std::signbit(v) ? "-0x" : "0x") + std::string(buf, r.ptr);
}

bool parseHex(std::string_view s, double& v) {
    const bool negative = s.starts_with("-");
    if (negative) s.remove_prefix(1);
    if (!s.starts_with("0x") || s.size() < 3) return false;
    const auto r = std::from_chars(s.data() + 2, s.data() + s.size(), v, std::chars_format::hex);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v)) return false;
    if (negative) v = -v;
    return true;
}

std::string blockName(int level, int col, int row) {
    return "block (level " + std::to_string(level) + ", column " + std::to_string(col) + ", row " + std::to_string(row) + ")";
}

std::string createMetaTableSql(const std::string& schema) {
    return "CREATE TABLE " + schema + "." + kDemLodMetaTable + " (key TEXT PRIMARY KEY NOT NULL, value TEXT NOT NULL)";
}

bool hasTableIn(SqliteDb& db, const std::string& schema, const std::string& table) {
    auto s = db.prepare("SELECT 1 FROM " + schema + ".sqlite_master WHERE type = 'table' AND name = ?");
    s.bindText(1, table);
    return s.step();
}

void refuse(const std::string& path, const std::string& reason) {
    throw DemLodError(path + ": DEM LOD tree '" + kDemLodTable + "': " + reason);
}

}  // namespace lacet::dem_lod_detail
