#include "io/sqlite_db.h"

#include <sqlite3.h>
#include <sys/stat.h>

#include <cstring>

namespace lacet {
namespace {

// SQLite's message, with the system's reason when a read or write of the file failed (a file size
// limit or a lost device: SQLite says only "disk I/O error"; a full disk is its SQLITE_FULL).
std::string reasonOf(sqlite3* db, const char* message) {
    std::string reason = message ? message : db ? sqlite3_errmsg(db) : "out of memory";
    if (!db) return reason;
    const int primary = sqlite3_extended_errcode(db) & 0xff;
    const int error = sqlite3_system_errno(db);
    if ((primary == SQLITE_IOERR || primary == SQLITE_FULL || primary == SQLITE_CANTOPEN) && error != 0)
        reason += std::string(": ") + std::strerror(error);
    else if (sqlite3_extended_errcode(db) == SQLITE_IOERR_WRITE)  // SQLite keeps no errno of a failed write
        reason += ": a write failed (a full disk, a file size limit or a device error)";
    return reason;
}

[[noreturn]] void fail(sqlite3* db, std::string_view what) {
    throw SqliteError(std::string(what) + " (SQLite: " + reasonOf(db, nullptr) + ")");
}

}  // namespace

SqliteStatement::SqliteStatement(sqlite3* db, std::string_view sql) : db_(db) {
    if (sqlite3_prepare_v2(db_, sql.data(), int(sql.size()), &stmt_, nullptr) != SQLITE_OK)
        fail(db_, "cannot prepare '" + std::string(sql.substr(0, 60)) + "'");
}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(stmt_); }

void SqliteStatement::bind(int i, std::int64_t v) {
    if (sqlite3_bind_int64(stmt_, i, v) != SQLITE_OK) fail(db_, "cannot bind an integer");
}

void SqliteStatement::bind(int i, double v) {
    if (sqlite3_bind_double(stmt_, i, v) != SQLITE_OK) fail(db_, "cannot bind a real");
}

void SqliteStatement::bindText(int i, std::string_view v) {
    if (sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT, SQLITE_UTF8) != SQLITE_OK)
        fail(db_, "cannot bind a text");
}

void SqliteStatement::bindBlob(int i, std::span<const std::uint8_t> v) {
    // A zero-length blob (not NULL) for an empty span: SQLite treats a null pointer as NULL.
    static const std::uint8_t empty = 0;
    if (sqlite3_bind_blob64(stmt_, i, v.empty() ? &empty : v.data(), v.size(), SQLITE_TRANSIENT) != SQLITE_OK)
        fail(db_, "cannot bind a blob");
}

void SqliteStatement::bindNull(int i) {
    if (sqlite3_bind_null(stmt_, i) != SQLITE_OK) fail(db_, "cannot bind a null");
}

bool SqliteStatement::step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db_, "cannot run '" + std::string(std::string_view(sqlite3_sql(stmt_)).substr(0, 60)) + "'");
}

void SqliteStatement::reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
}

int SqliteStatement::type(int col) const { return sqlite3_column_type(stmt_, col); }
std::int64_t SqliteStatement::integer(int col) const { return sqlite3_column_int64(stmt_, col); }
double SqliteStatement::real(int col) const { return sqlite3_column_double(stmt_, col); }

std::string SqliteStatement::text(int col) const {
    const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, col));
    const int n = sqlite3_column_bytes(stmt_, col);
    return p ? std::string(p, std::size_t(n)) : std::string();
}

std::span<const std::uint8_t> SqliteStatement::blob(int col) const {
    const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, col));
    const int n = sqlite3_column_bytes(stmt_, col);
    return p ? std::span<const std::uint8_t>(p, std::size_t(n)) : std::span<const std::uint8_t>();
}

namespace {

// A write interrupted by a crash (a save in place, io/scene_save_edits.h) leaves a hot rollback
// journal beside the file, which only a connection that may write can roll back: a read-only
// connection fails ("attempt to write a readonly database"). One is opened for that first, when
// the journal is there, and SQLite rolls it back on its first read if it is hot (a journal a live
// writer holds is not hot, and is left to it). Where the file cannot be written, nothing is done:
// the read-only open reports the problem.
void rollBackHotJournal(const std::string& path) {
    struct stat st {};
    if (::stat((path + "-journal").c_str(), &st) != 0 || st.st_size == 0) return;
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) == SQLITE_OK) {
        sqlite3_busy_timeout(db, 2000);
        sqlite3_exec(db, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
    }
    sqlite3_close_v2(db);
}

}  // namespace

SqliteDb::SqliteDb(const std::string& path, Mode mode) {
    if (mode == Mode::ReadOnly) rollBackHotJournal(path);
    const int flags = mode == Mode::ReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
    if (sqlite3_open_v2(path.c_str(), &db_, flags, nullptr) != SQLITE_OK) {
        const std::string reason = reasonOf(db_, nullptr);
        sqlite3_close(db_);
        db_ = nullptr;
        throw SqliteError("cannot open (SQLite: " + reason + ")");
    }
    sqlite3_extended_result_codes(db_, 1);
    sqlite3_busy_timeout(db_, kDefaultBusyTimeoutMs);
}

SqliteDb::~SqliteDb() { sqlite3_close_v2(db_); }

void SqliteDb::busyTimeout(int ms) { sqlite3_busy_timeout(db_, ms); }

void SqliteDb::exec(std::string_view sql) {
    char* message = nullptr;
    if (sqlite3_exec(db_, std::string(sql).c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
        const std::string reason = reasonOf(db_, message);
        sqlite3_free(message);
        throw SqliteError("cannot run '" + std::string(sql.substr(0, 60)) + "' (SQLite: " + reason + ")");
    }
}

std::string SqliteDb::queryText(std::string_view sql) {
    SqliteStatement s(db_, sql);
    if (!s.step()) throw SqliteError("'" + std::string(sql.substr(0, 60)) + "' returned no row");
    return s.text(0);
}

std::int64_t SqliteDb::queryInteger(std::string_view sql) {
    SqliteStatement s(db_, sql);
    if (!s.step()) throw SqliteError("'" + std::string(sql.substr(0, 60)) + "' returned no row");
    return s.integer(0);
}

bool SqliteDb::hasTable(const std::string& name) {
    SqliteStatement s(db_, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
    s.bindText(1, name);
    return s.step();
}

void SqliteDb::close() {
    if (db_ && sqlite3_close(db_) != SQLITE_OK) fail(db_, "cannot close");
    db_ = nullptr;
}

}  // namespace lacet
