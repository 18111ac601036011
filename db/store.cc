#include "db/store.h"

#include <algorithm>
#include <atomic>
#include <string>

#include "db/migrations.h"

namespace tinbase {

namespace {

// A DEM block's compressed cells span dozens of overflow pages; through the memory map they are
// read without a pread() each, which made cold window reads 2x faster.
std::atomic<int64_t> g_memory_map_bytes{Store::kDefaultMemoryMapBytes};

Status ConfigureConnection(SqliteDb& db) {
  TB_RETURN_IF_ERROR(db.Exec("PRAGMA foreign_keys = ON"));
  TB_RETURN_IF_ERROR(db.Exec("PRAGMA mmap_size = " + std::to_string(g_memory_map_bytes.load())));
  return db.Exec("PRAGMA synchronous = NORMAL");
}

}  // namespace

Store::Store(std::unique_ptr<SqliteDb> db, int version, Access access)
    : db_(std::move(db)), schema_version_(version) {
  if (access == Access::kReadWrite) checkpointer_ = std::make_unique<WalCheckpointer>(*db_);
}

void Store::SetMemoryMapLimit(int64_t bytes) { g_memory_map_bytes = std::max<int64_t>(bytes, 0); }

Result<std::unique_ptr<Store>> Store::Create(const std::string& path, const std::string& crs_text) {
  std::optional<Crs> crs;
  if (!crs_text.empty()) {
    TB_ASSIGN_OR_RETURN(crs, Crs::FromUserInput(crs_text));
  }
  TB_ASSIGN_OR_RETURN(auto db, SqliteDb::Open(path, SqliteDb::Mode::kCreate));
  Status status = db->Exec("PRAGMA journal_mode = WAL");
  if (status.ok()) status = ConfigureConnection(*db);
  if (status.ok())
    status = db->Exec("PRAGMA application_id = " + std::to_string(kTinbaseApplicationId));
  if (status.ok()) status = MigrateSqlite(*db, LatestSchemaVersion());
  std::unique_ptr<Store> store(new Store(std::move(db), LatestSchemaVersion(), Access::kReadWrite));
  if (status.ok() && crs) {
    auto tx = store->BeginWrite();
    status = tx.ok() ? store->SetCrs(*crs) : tx.status();
    if (status.ok()) status = (*tx)->Commit();
  }
  if (!status.ok()) return status.WithContext("creating store " + path);
  return store;
}

Result<std::unique_ptr<Store>> Store::Open(const std::string& path, Access access) {
  TB_ASSIGN_OR_RETURN(
      auto db, SqliteDb::Open(path, access == Access::kReadOnly ? SqliteDb::Mode::kReadOnly
                                                                : SqliteDb::Mode::kReadWrite));
  auto app_id = db->QueryInt("PRAGMA application_id");
  if (!app_id.ok())
    return Status::InvalidArgument(path + " is not a tinbase store (not an SQLite database)");
  if (*app_id != kTinbaseApplicationId)
    return Status::InvalidArgument(path + " is not a tinbase store (SQLite application_id " +
                                   std::to_string(*app_id) + ")");
  TB_RETURN_IF_ERROR(ConfigureConnection(*db));
  TB_ASSIGN_OR_RETURN(int64_t version, db->QueryInt("PRAGMA user_version"));
  if (version > LatestSchemaVersion())
    return Status::InvalidArgument(path + " was made by a newer tinbase (schema version " +
                                   std::to_string(version) + "; this tinbase knows up to " +
                                   std::to_string(LatestSchemaVersion()) + "): upgrade tinbase");
  if (version < LatestSchemaVersion()) {
    if (access == Access::kReadOnly)
      return Status::InvalidArgument(path + " has schema version " + std::to_string(version) +
                                     " and needs migrating: open it read-write once");
    TB_RETURN_IF_ERROR(MigrateSqlite(*db, LatestSchemaVersion()).WithContext(path));
  }
  return std::unique_ptr<Store>(new Store(std::move(db), LatestSchemaVersion(), access));
}

Result<std::unique_ptr<WriteTransaction>> Store::BeginWrite() {
  TB_RETURN_IF_ERROR(db_->Exec("BEGIN IMMEDIATE"));
  return std::make_unique<WriteTransaction>(this);
}

Result<std::optional<std::string>> Store::GetMeta(const std::string& key) {
  TB_ASSIGN_OR_RETURN(Statement * stmt, db_->Cached("SELECT value FROM meta WHERE key = ?"));
  stmt->Bind(1, key);
  TB_ASSIGN_OR_RETURN(bool row, stmt->Step());
  std::optional<std::string> value;
  if (row) value = stmt->ColumnText(0);
  stmt->Reset();
  return value;
}

Status Store::SetMeta(const std::string& key, const std::string& value) {
  TB_ASSIGN_OR_RETURN(Statement * stmt,
                      db_->Cached("INSERT INTO meta(key, value) VALUES (?, ?) "
                                  "ON CONFLICT(key) DO UPDATE SET value = excluded.value"));
  stmt->Bind(1, key).Bind(2, value);
  return stmt->Run();
}

Result<std::optional<Crs>> Store::GetCrs() {
  TB_ASSIGN_OR_RETURN(auto wkt, GetMeta("crs_wkt"));
  if (!wkt) return std::optional<Crs>();
  TB_ASSIGN_OR_RETURN(Crs crs, Crs::FromWkt(*wkt));
  return std::optional<Crs>(std::move(crs));
}

Status Store::SetCrs(const Crs& crs) {
  TB_RETURN_IF_ERROR(SetMeta("crs_wkt", crs.Wkt()));
  TB_RETURN_IF_ERROR(SetMeta("crs_label", crs.Label()));
  return SetMeta("units", crs.IsGeographic() ? "degree" : "metre");
}

WriteTransaction::~WriteTransaction() {
  if (!done_) (void)store_->db().Exec("ROLLBACK");
}

Status WriteTransaction::Commit() {
  Status s = store_->db().Exec("COMMIT");
  if (!s.ok()) (void)store_->db().Exec("ROLLBACK");
  done_ = true;
  return s;
}

Result<std::unique_ptr<ReadSnapshot>> ReadSnapshot::Begin(Store& store) {
  TB_RETURN_IF_ERROR(store.db().Exec("BEGIN DEFERRED"));
  // A deferred transaction takes its snapshot at the first read; read now so it is pinned.
  TB_RETURN_IF_ERROR(store.db().QueryInt("SELECT count(*) FROM meta").status());
  return std::unique_ptr<ReadSnapshot>(new ReadSnapshot(&store));
}

ReadSnapshot::~ReadSnapshot() { (void)store_->db().Exec("COMMIT"); }

}  // namespace tinbase
