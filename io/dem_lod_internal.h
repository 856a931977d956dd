#pragma once
// Private to io/dem_lod_*.cpp (the DEM LOD tree of io/dem_lod.h, one job a file: dem_lod_layout.cpp
// the layout math, dem_lod_tables.cpp the GeoPackage tables and exact text, dem_lod_writer.cpp the
// writer, dem_lod_file.cpp the reader and whole levels, dem_lod_copy.cpp the copy into a scene file):
// the helpers more than one of them needs.

#include <string>
#include <string_view>

#include "io/dem_lod.h"

namespace lacet {

class SqliteDb;

namespace dem_lod_detail {

// C hex float ("0x1.f4p+9", "-0x0p+0"), exact and locale-independent; finite values only.
std::string hexText(double v);
// The reverse of hexText; false for anything else or a value that is not finite.
bool parseHex(std::string_view s, double& v);
// "block (level l, column c, row r)", for messages.
std::string blockName(int level, int col, int row);

// CREATE TABLE of kDemLodMetaTable in `schema` ("main", an ATTACH name).
std::string createMetaTableSql(const std::string& schema);
// Whether `schema` of `db` has a table `table`.
bool hasTableIn(SqliteDb& db, const std::string& schema, const std::string& table);

// Whether local sample (m, q) of a block of `level` is inherited from its parent.
inline bool inherited(int level, int m, int q) { return level > 0 && m % 2 == 0 && q % 2 == 0; }

// Throws DemLodError "<path>: DEM LOD tree 'dem_lod': <reason>".
[[noreturn]] void refuse(const std::string& path, const std::string& reason);

}  // namespace dem_lod_detail
}  // namespace lacet
