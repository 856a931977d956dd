#pragma once
// A thin RAII wrapper of SQLite for the scene file: one connection, prepared statements, errors as
// exceptions carrying SQLite's message. No SQL of its own beyond what the caller passes.

#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace lacet {

// Reason only (SQLite's message and the failing step); callers add the file name.
class SqliteError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class SqliteStatement {
public:
    SqliteStatement(sqlite3* db, std::string_view sql);  // throws SqliteError
    SqliteStatement(const SqliteStatement&) = delete;
    SqliteStatement& operator=(const SqliteStatement&) = delete;
    ~SqliteStatement();

    // Parameters are numbered from 1. Text and blobs are copied by SQLite.
    void bind(int i, std::int64_t v);
    void bind(int i, double v);
    void bindText(int i, std::string_view v);
    void bindBlob(int i, std::span<const std::uint8_t> v);
    void bindNull(int i);

    // Runs one step: true when a row is available, false when done. Throws SqliteError.
    bool step();
    // Ready to run again with new bindings (previous bindings are cleared).
    void reset();

    // Columns are numbered from 0. `type` is SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT, SQLITE_BLOB
    // or SQLITE_NULL: the stored type of the value in the current row.
    int type(int col) const;
    std::int64_t integer(int col) const;
    double real(int col) const;
    std::string text(int col) const;
    // Valid until the next step, reset or destruction.
    std::span<const std::uint8_t> blob(int col) const;

private:
    sqlite3* db_;
    sqlite3_stmt* stmt_ = nullptr;
};

class SqliteDb {
public:
    static constexpr int kDefaultBusyTimeoutMs = 10000;
    // ReadWrite does not create a missing file. ReadOnly first lets SQLite roll back the hot
    // journal a crash in the middle of a write left beside the file (a read-only connection cannot),
    // through a connection that may write, opened for that alone where the file is writable.
    enum class Mode { ReadOnly, ReadWrite };
    SqliteDb(const std::string& path, Mode mode);  // throws SqliteError
    SqliteDb(const SqliteDb&) = delete;
    SqliteDb& operator=(const SqliteDb&) = delete;
    ~SqliteDb();  // closes quietly; call close() to see errors

    // How long a statement waits for a lock another connection holds before failing with
    // "database is locked" (milliseconds; 0: fail at once). kDefaultBusyTimeoutMs from the open:
    // a read waits for a writer's commit (a save in place of the scene it reads) instead of failing.
    void busyTimeout(int ms);
    // Runs one or more statements that return nothing the caller needs.
    void exec(std::string_view sql);
    SqliteStatement prepare(std::string_view sql) { return SqliteStatement(db_, sql); }
    // The same, on the heap, to keep (statements are neither copied nor moved).
    std::unique_ptr<SqliteStatement> prepareKept(std::string_view sql) { return std::make_unique<SqliteStatement>(db_, sql); }
    // The single value of a one-row, one-column query, as text (empty for NULL).
    std::string queryText(std::string_view sql);
    std::int64_t queryInteger(std::string_view sql);
    bool hasTable(const std::string& name);
    // Closes the connection; throws SqliteError if SQLite cannot (e.g. unfinalized statements).
    void close();
    // The connection, for what this wrapper does not do (SQL functions of the caller's).
    sqlite3* handle() { return db_; }

private:
    sqlite3* db_ = nullptr;
};

}  // namespace lacet
