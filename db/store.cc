#include "db/store.h"

#include <ogr_spatialref.h>

#include <algorithm>
#include <atomic>
#include <string>

#include "db/migrations.h"

namespace tinbase {

namespace {

// A DEM block's compressed cells span dozens of overflow pages; through the memory map they are
// read without a system call each.
std::atomic<int64_t> g_memory_map_bytes{Store::kDefaultMemoryMapBytes};

StoreSettings Settings(bool create, Store::Access access) {
  StoreSettings settings;
  settings.create = create;
  settings.writer = access == Store::Access::kReadWrite;
  settings.memory_map_bytes = g_memory_map_bytes.load();
  return settings;
}

// The application_id from migration 0013 on: GeoPackage 1.1's, so GDAL opens the store as a
// GeoPackage by its own name (docs/format.md, "The store as a GeoPackage").
constexpr int32_t kGeoPackage11ApplicationId = 0x47503131;

// A tinbase store: application_id 'TINB' (before migration 0013), or GeoPackage 1.1's 'GP11'
// with meta's application row (from 0013 on, docs/format.md): another GeoPackage is not one.
Status CheckIsStore(Connection& db, const std::string& path) {
  auto app_id = db.ApplicationId();
  // Corruption: the file is not a database of the backend at all; other errors (I/O, permission)
  // say what they are.
  // A database whose pages are damaged (cut short, overwritten) is said to be damaged, not to
  // be something else: it may well be a tinbase store.
  if (!app_id.ok() && app_id.status().code() == StatusCode::kCorruption &&
      app_id.status().message().find("malformed") != std::string::npos)
    return Status::Corruption(path +
                              " is a damaged database (its pages are malformed, e.g. the file was "
                              "cut short): restore it from a backup, or try `sqlite3 " +
                              path + " .recover`");
  if (!app_id.ok() && app_id.status().code() == StatusCode::kCorruption)
    return Status::InvalidArgument(path + " is not a tinbase store (" + app_id.status().message() +
                                   ")");
  if (!app_id.ok()) return app_id.status();
  if (*app_id == kTinbaseApplicationId) return Status::Ok();
  if (*app_id == kGeoPackage11ApplicationId) {
    auto marked = db.QueryInt(
        "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta' AND EXISTS "
        "(SELECT 1 FROM meta WHERE key = 'application' AND value = 'tinbase')");
    // An I/O error reading meta is that error, not a verdict on the file (found by the fault VFS).
    if (!marked.ok()) return marked.status().WithContext(path);
    if (*marked == 1) return Status::Ok();
    return Status::InvalidArgument(path +
                                   " is not a tinbase store (a GeoPackage of another "
                                   "program)");
  }
  return Status::InvalidArgument(path + " is not a tinbase store (application_id " +
                                 std::to_string(*app_id) + ")");
}

// The last ": "-separated part of an SQLite message: the reason without the SQL before it.
std::string LastClause(const std::string& message) {
  const size_t colon = message.rfind(": ");
  return colon == std::string::npos ? message : message.substr(colon + 2);
}

// The schema version (SQLite's user_version) does not describe the file's tables.
Status DamagedSchemaVersion(const std::string& path, int64_t version, const std::string& why) {
  return Status::Corruption(path + ": damaged schema version " + std::to_string(version) +
                            " (SQLite user_version; " + why +
                            "): nothing was changed; if the version was set by hand, set it back "
                            "(PRAGMA user_version) and run `tinbase check --full`");
}

}  // namespace

Store::Store(std::unique_ptr<Connection> db, int version)
    : db_(std::move(db)), schema_version_(version) {}

void Store::SetMemoryMapLimit(int64_t bytes) { g_memory_map_bytes = std::max<int64_t>(bytes, 0); }

namespace {

// A store's x and y are a plane's or the Earth's surface's: a geocentric system (x, y, z through
// the Earth's centre) or a vertical one alone has no such axes, and every DEM warped onto it
// would come out empty.
Status CheckStoreCrs(const Crs& crs) {
  const OGRSpatialReference& srs = crs.ogr();
  if (srs.IsGeocentric())
    return Status::InvalidArgument(crs.Label() +
                                   " is a geocentric CRS: a store needs a projected, geographic "
                                   "or local one (with a vertical CRS or without)");
  if (srs.IsVertical() && !srs.IsProjected() && !srs.IsGeographic() && !srs.IsLocal())
    return Status::InvalidArgument(crs.Label() +
                                   " is a vertical CRS alone: a store needs a projected, "
                                   "geographic or local one (with a vertical CRS or without)");
  return Status::Ok();
}

}  // namespace

Result<std::unique_ptr<Store>> Store::Create(const std::string& path, const std::string& crs_text) {
  std::optional<Crs> crs;
  if (!crs_text.empty()) {
    TB_ASSIGN_OR_RETURN(crs, Crs::FromUserInput(crs_text));
    TB_RETURN_IF_ERROR(CheckStoreCrs(*crs));
  }
  TB_ASSIGN_OR_RETURN(auto db, Connection::Open(path, Connection::Mode::kCreate));
  Status status = db->ConfigureForStore(Settings(/*create=*/true, Access::kReadWrite));
  if (status.ok()) status = db->SetApplicationId(kTinbaseApplicationId);
  if (status.ok()) status = MigrateStore(*db, LatestSchemaVersion());
  std::unique_ptr<Store> store(new Store(std::move(db), LatestSchemaVersion()));
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
      auto db, Connection::Open(path, access == Access::kReadOnly ? Connection::Mode::kReadOnly
                                                                  : Connection::Mode::kReadWrite));
  TB_RETURN_IF_ERROR(CheckIsStore(*db, path));
  TB_RETURN_IF_ERROR(db->ConfigureForStore(Settings(/*create=*/false, access)));
  TB_ASSIGN_OR_RETURN(int64_t version, db->SchemaVersion());
  if (version > LatestSchemaVersion())
    return Status::InvalidArgument(path + " was made by a newer tinbase (schema version " +
                                   std::to_string(version) + "; this tinbase knows up to " +
                                   std::to_string(LatestSchemaVersion()) + "): upgrade tinbase");
  if (version < 1) return DamagedSchemaVersion(path, version, "no store has it");
  if (version < LatestSchemaVersion()) {
    if (access == Access::kReadOnly)
      return Status::InvalidArgument(path + " has schema version " + std::to_string(version) +
                                     " and needs migrating: open it read-write once");
    Status migrated = MigrateStore(*db, LatestSchemaVersion());
    // A migration that finds its tables already there means the version lies, not the SQL.
    if (migrated.code() == StatusCode::kInvalidArgument)
      return DamagedSchemaVersion(path, version, LastClause(migrated.message()));
    TB_RETURN_IF_ERROR(migrated.WithContext(path));
  }
  return std::unique_ptr<Store>(new Store(std::move(db), LatestSchemaVersion()));
}

Result<std::unique_ptr<Store>> Store::Adopt(std::unique_ptr<Connection> db) {
  const std::string label = db->path();
  TB_RETURN_IF_ERROR(CheckIsStore(*db, label));
  TB_ASSIGN_OR_RETURN(int64_t version, db->SchemaVersion());
  if (version != LatestSchemaVersion())
    return Status::InvalidArgument(label + " has schema version " + std::to_string(version) +
                                   " where this tinbase needs " +
                                   std::to_string(LatestSchemaVersion()) +
                                   ": ALTER EXTENSION tinbase UPDATE, or migrate it with the CLI");
  return std::unique_ptr<Store>(new Store(std::move(db), LatestSchemaVersion()));
}

Result<std::unique_ptr<WriteTransaction>> Store::BeginWrite() {
  TB_ASSIGN_OR_RETURN(Transaction tx, Transaction::Begin(*db_));
  return std::make_unique<WriteTransaction>(this, std::move(tx));
}

Result<std::unique_ptr<WriteTransaction>> Store::BeginRegionWrite() {
  TB_ASSIGN_OR_RETURN(Transaction tx, Transaction::BeginRegion(*db_));
  return std::make_unique<WriteTransaction>(this, std::move(tx));
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
  TB_RETURN_IF_ERROR(CheckStoreCrs(crs));
  TB_RETURN_IF_ERROR(SetMeta("crs_wkt", crs.Wkt()));
  TB_RETURN_IF_ERROR(SetMeta("crs_label", crs.Label()));
  return SetMeta("units", crs.IsGeographic() ? "degree" : "metre");
}

Result<std::unique_ptr<ReadSnapshot>> ReadSnapshot::Begin(Store& store) {
  TB_ASSIGN_OR_RETURN(Snapshot snapshot, Snapshot::Begin(store.db()));
  return std::unique_ptr<ReadSnapshot>(new ReadSnapshot(std::move(snapshot)));
}

}  // namespace tinbase
