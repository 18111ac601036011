#include "db/sqlite/sqlite_connection.h"

#include <sqlite3.h>

#include <mutex>

#include "db/sqlite/scoped_page_cache.h"
#include "db/sqlite/store_path.h"
#include "db/sqlite/wal_checkpointer.h"

namespace tinbase {

Status StatusFromSqlite(int rc, sqlite3* db, std::string_view context) {
  if (rc == SQLITE_OK || rc == SQLITE_DONE || rc == SQLITE_ROW) return Status::Ok();
  std::string msg(context);
  msg += ": ";
  msg += db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  // SQLite says "disk I/O error" or "unable to open database file" for a full disk, a denied
  // permission and a read-only file system alike; the operating system's error tells them apart.
  const int system_error = db != nullptr ? sqlite3_system_errno(db) : 0;
  const int primary = rc & 0xff;
  if (system_error != 0 &&
      (primary == SQLITE_IOERR || primary == SQLITE_CANTOPEN || primary == SQLITE_FULL ||
       primary == SQLITE_READONLY || primary == SQLITE_PERM))
    msg += " (" + DescribeSystemError(system_error) + ")";
  switch (rc & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return Status::Busy(msg);
    case SQLITE_CONSTRAINT:
      return Status::Conflict(msg);
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      return Status::Corruption(msg);
    case SQLITE_NOTFOUND:
      return Status::NotFound(msg);
    case SQLITE_MISMATCH:
    case SQLITE_RANGE:
    case SQLITE_TOOBIG:
    case SQLITE_ERROR:
      return Status::InvalidArgument(msg);
    default:
      return Status::IOError(msg);
  }
}

SqliteStatement::SqliteStatement(sqlite3* db, sqlite3_stmt* stmt, std::string sql)
    : Statement(std::move(sql)), db_(db), stmt_(stmt) {}

SqliteStatement::~SqliteStatement() { sqlite3_finalize(stmt_); }

SqliteStatement& SqliteStatement::Bind(int index, int64_t value) {
  sqlite3_bind_int64(stmt_, index, value);
  return *this;
}
SqliteStatement& SqliteStatement::Bind(int index, double value) {
  sqlite3_bind_double(stmt_, index, value);
  return *this;
}
SqliteStatement& SqliteStatement::Bind(int index, std::string_view text) {
  sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  return *this;
}
SqliteStatement& SqliteStatement::BindStaticText(int index, const char* text) {
  sqlite3_bind_text(stmt_, index, text, -1, SQLITE_STATIC);
  return *this;
}
SqliteStatement& SqliteStatement::BindBlob(int index, const void* data, size_t size) {
  sqlite3_bind_blob64(stmt_, index, data, size, SQLITE_TRANSIENT);
  return *this;
}
SqliteStatement& SqliteStatement::BindNull(int index) {
  sqlite3_bind_null(stmt_, index);
  return *this;
}

Result<bool> SqliteStatement::Step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  return StatusFromSqlite(rc, db_, sql().substr(0, 60));
}

Status SqliteStatement::Run() {
  Result<bool> r = Step();
  while (r.ok() && *r) r = Step();
  Reset();
  return r.status();
}

void SqliteStatement::Reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

int SqliteStatement::ColumnCount() const { return sqlite3_column_count(stmt_); }
int64_t SqliteStatement::ColumnInt(int index) const { return sqlite3_column_int64(stmt_, index); }
double SqliteStatement::ColumnDouble(int index) const {
  return sqlite3_column_double(stmt_, index);
}
std::string SqliteStatement::ColumnText(int index) const {
  const auto* text = sqlite3_column_text(stmt_, index);
  return text == nullptr ? std::string()
                         : std::string(reinterpret_cast<const char*>(text),
                                       static_cast<size_t>(sqlite3_column_bytes(stmt_, index)));
}
bool SqliteStatement::ColumnIsNull(int index) const {
  return sqlite3_column_type(stmt_, index) == SQLITE_NULL;
}
const uint8_t* SqliteStatement::ColumnBlob(int index, size_t* size) const {
  const void* data = sqlite3_column_blob(stmt_, index);
  *size = static_cast<size_t>(sqlite3_column_bytes(stmt_, index));
  return static_cast<const uint8_t*>(data);
}

namespace {

// A statement that may fail part way (a multi-row write with foreign keys or CHECKs to enforce)
// keeps the original of every page it changes in a statement journal, in memory only up to
// 64 KiB by default; once one statement of a transaction passed that, the journal is a temporary
// file for the rest of it, and every page a statement changes costs a pwrite. A larger limit
// keeps the journals of more edits in memory, but SQLite spills the journal to its file one
// chunk of the limit's size a call, and the unix VFS writes at most 128 KiB - 1 bytes a call
// (it calls the rest a full disk): the limit is the largest that stays below. The setting is
// process-wide and must come before SQLite initialises: when another user of SQLite in the
// process (GDAL's GeoPackage driver) came first, the default stays, which is only slower.
constexpr int kStatementJournalInMemory = (128 << 10) - 1;

// Set on the thread whose connection found a WAL left by a process that did not close its
// store (SQLite rebuilds the WAL index then and says so through its log): the mark of an
// unclean shutdown, after which a writer checks the file before it writes.
thread_local bool g_recovered_wal = false;

void SqliteLog(void*, int code, const char*) {
  if (code == SQLITE_NOTICE_RECOVER_WAL) g_recovered_wal = true;
}

void ConfigureSqliteOnce() {
  static std::once_flag once;
  std::call_once(once, [] {
    (void)sqlite3_config(SQLITE_CONFIG_STMTJRNL_SPILL, kStatementJournalInMemory);
    (void)sqlite3_config(SQLITE_CONFIG_LOG, SqliteLog, nullptr);
  });
}

}  // namespace

Result<std::unique_ptr<SqliteConnection>> SqliteConnection::Open(const std::string& path,
                                                                 Mode mode) {
  ConfigureSqliteOnce();
  g_recovered_wal = false;
  TB_RETURN_IF_ERROR(StorePathProblem(path, mode));
  int flags = SQLITE_OPEN_NOMUTEX;
  if (mode == Mode::kReadOnly) flags |= SQLITE_OPEN_READONLY;
  if (mode == Mode::kReadWrite) flags |= SQLITE_OPEN_READWRITE;
  if (mode == Mode::kCreate) flags |= SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  if (rc != SQLITE_OK) {
    Status s = StatusFromSqlite(rc, raw, path);
    sqlite3_close(raw);
    return s;
  }
  sqlite3_extended_result_codes(raw, 1);
  sqlite3_busy_timeout(raw, 10000);
  return std::unique_ptr<SqliteConnection>(new SqliteConnection(raw, path));
}

SqliteConnection::SqliteConnection(sqlite3* db, std::string path)
    : db_(db), path_(std::move(path)) {}

SqliteConnection::~SqliteConnection() {
  checkpointer_.reset();
  cache_.clear();
  sqlite3_close(db_);
}

Status SqliteConnection::Exec(std::string_view sql) {
  std::string text(sql);
  char* err = nullptr;
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &err);
  sqlite3_free(err);
  return StatusFromSqlite(rc, db_, text.substr(0, 60));
}

Result<std::unique_ptr<Statement>> SqliteConnection::Prepare(std::string_view sql) {
  sqlite3_stmt* stmt = nullptr;
  const int rc = sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt, nullptr);
  if (rc != SQLITE_OK) {
    Status s =
        StatusFromSqlite(rc, db_, std::string("preparing ") + std::string(sql.substr(0, 60)));
    sqlite3_finalize(stmt);
    return s;
  }
  return std::unique_ptr<Statement>(new SqliteStatement(db_, stmt, std::string(sql)));
}

Result<Statement*> SqliteConnection::Cached(std::string_view sql) {
  auto it = cache_.find(std::string(sql));
  if (it != cache_.end()) {
    it->second->Reset();
    return it->second.get();
  }
  TB_ASSIGN_OR_RETURN(auto stmt, Prepare(sql));
  auto* raw = static_cast<SqliteStatement*>(stmt.release());
  cache_.emplace(std::string(sql), std::unique_ptr<SqliteStatement>(raw));
  return static_cast<Statement*>(raw);
}

int64_t SqliteConnection::Changes() const { return sqlite3_changes64(db_); }
int64_t SqliteConnection::TotalChanges() const { return sqlite3_total_changes64(db_); }
Result<int64_t> SqliteConnection::DataVersion() { return QueryInt("PRAGMA data_version"); }

Status SqliteConnection::BeginWrite() { return Exec("BEGIN IMMEDIATE"); }

Status SqliteConnection::BeginRead() {
  TB_RETURN_IF_ERROR(Exec("BEGIN DEFERRED"));
  Status s = QueryInt("SELECT count(*) FROM sqlite_master").status();
  if (!s.ok()) (void)Exec("ROLLBACK");
  return s;
}

Status SqliteConnection::Commit() { return Exec("COMMIT"); }
Status SqliteConnection::Rollback() { return Exec("ROLLBACK"); }

Status SqliteConnection::BeginSavepoint(std::string_view name) {
  return Exec("SAVEPOINT " + std::string(name));
}
Status SqliteConnection::ReleaseSavepoint(std::string_view name) {
  return Exec("RELEASE SAVEPOINT " + std::string(name));
}
Status SqliteConnection::RollbackToSavepoint(std::string_view name) {
  return Exec("ROLLBACK TO SAVEPOINT " + std::string(name));
}

bool SqliteConnection::InTransaction() const { return sqlite3_get_autocommit(db_) == 0; }

Result<int64_t> SqliteConnection::ApplicationId() { return QueryInt("PRAGMA application_id"); }
Status SqliteConnection::SetApplicationId(int32_t id) {
  return Exec("PRAGMA application_id = " + std::to_string(id));
}
Result<int64_t> SqliteConnection::SchemaVersion() { return QueryInt("PRAGMA user_version"); }
Status SqliteConnection::SetSchemaVersion(int64_t version) {
  return Exec("PRAGMA user_version = " + std::to_string(version));
}

Status SqliteConnection::ConfigureForStore(const StoreSettings& settings) {
  if (settings.create) TB_RETURN_IF_ERROR(Exec("PRAGMA journal_mode = WAL"));
  TB_RETURN_IF_ERROR(Exec("PRAGMA foreign_keys = ON"));
  TB_RETURN_IF_ERROR(Exec("PRAGMA mmap_size = " + std::to_string(settings.memory_map_bytes)));
  TB_RETURN_IF_ERROR(Exec("PRAGMA synchronous = NORMAL"));
  if (settings.writer) TB_RETURN_IF_ERROR(CheckAfterUncleanShutdown());
  if (settings.writer && !checkpointer_) checkpointer_ = std::make_unique<WalCheckpointer>(*this);
  return Status::Ok();
}

Status SqliteConnection::CheckAfterUncleanShutdown() {
  // The first read runs the WAL recovery if there is one to run.
  TB_RETURN_IF_ERROR(Exec("SELECT count(*) FROM sqlite_master"));
  if (!g_recovered_wal) return Status::Ok();
  g_recovered_wal = false;
  TB_ASSIGN_OR_RETURN(Statement * check, Cached("PRAGMA quick_check(1)"));
  TB_ASSIGN_OR_RETURN(bool row, check->Step());
  const std::string verdict = row ? check->ColumnText(0) : "no answer";
  check->Reset();
  if (verdict == "ok") return Status::Ok();
  return Status::Corruption(path_ +
                            ": the store was not closed cleanly and fails SQLite's "
                            "quick_check (" +
                            verdict +
                            "): writes are refused; `tinbase check --full` shows what is damaged; "
                            "restore a backup, or salvage with `sqlite3 STORE .recover`");
}

std::unique_ptr<Connection::Scope> SqliteConnection::BeginLargeWrite(size_t rows) {
  auto cache = std::make_unique<ScopedPageCache>(*this, rows);
  if (!cache->raised()) return nullptr;
  return cache;
}

Result<bool> SqliteConnection::SetForeignKeys(bool on) {
  int was = 0, now = 0;
  int rc = sqlite3_db_config(db_, SQLITE_DBCONFIG_ENABLE_FKEY, -1, &was);
  if (rc == SQLITE_OK) rc = sqlite3_db_config(db_, SQLITE_DBCONFIG_ENABLE_FKEY, on ? 1 : 0, &now);
  if (rc != SQLITE_OK) return StatusFromSqlite(rc, db_, "turning foreign keys on or off");
  return was != 0;
}

}  // namespace tinbase
