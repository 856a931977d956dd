#pragma once
// Replacing a file atomically: the new contents are written beside it, flushed, then renamed over
// it, so that a crash or an error at any point leaves the previous file intact. Made for files
// written through SQLite (io/sqlite_db.h): a stale temporary file's journal is removed with it.

#include <functional>
#include <string>

namespace lacet {

// Removes a stale `path` + ".tmp" and its SQLite journal, WAL and shared-memory files; calls
// `write(tmp)`, which creates the temporary file; fsyncs it; renames it over `path`; fsyncs the
// directory (best effort: the contents are already safe). Throws std::runtime_error with the reason
// (or rethrows what `write` threw) after removing the temporary file and its journal; `path` is then
// unchanged.
void replaceFileAtomically(const std::string& path, const std::function<void(const std::string& tmp)>& write);

}  // namespace lacet
