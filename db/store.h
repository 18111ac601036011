// Store: one tinbase store (today an SQLite file), the only way into its tables.
//
// A Store owns one connection to it, through the seam of db/sql/connection.h; nothing here knows
// the backend. Create() makes a new store from the migrations; Open() checks that the target is a
// tinbase store, refuses one made by a newer tinbase and migrates an older one forward. Every
// write goes through a WriteTransaction (one writer at a time; readers keep their snapshot), which
// rolls back in its destructor unless committed.
// Thread-safety: one Store per thread; several processes may open the same file.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "db/sql/connection.h"
#include "db/sql/transaction.h"

namespace tinbase {

// 'TINB': marks a database as a tinbase store (Connection::ApplicationId).
inline constexpr int32_t kTinbaseApplicationId = 0x54494E42;

class WriteTransaction;

class Store {
 public:
  enum class Access { kReadOnly, kReadWrite };

  // Creates a new store at `path` with the latest schema. `crs` may be empty: the first DEM
  // imported then sets it. Fails with InvalidArgument if a file exists at `path`.
  static Result<std::unique_ptr<Store>> Create(const std::string& path, const std::string& crs);
  // Opens an existing store; migrates an older schema forward (needs kReadWrite).
  static Result<std::unique_ptr<Store>> Open(const std::string& path,
                                             Access access = Access::kReadWrite);
  // A Store over a connection opened elsewhere (the PostgreSQL extension's, inside its caller's
  // transaction; extensions/postgresql/spi_connection.h): checks that it is a tinbase store of
  // exactly this tinbase's schema version (InvalidArgument otherwise) and never migrates.
  static Result<std::unique_ptr<Store>> Adopt(std::unique_ptr<Connection> db);

  // How much of a store file each connection opened after this call reads through a memory map
  // (StoreSettings::memory_map_bytes; default kDefaultMemoryMapBytes, 0 = none). The map saves a
  // system call per page of every DEM block read; its pages are file cache the kernel may drop at
  // will, but they count as the process's resident memory. Process-wide; safe from any thread.
  static void SetMemoryMapLimit(int64_t bytes);
  static constexpr int64_t kDefaultMemoryMapBytes = int64_t{1} << 30;

  // Starts the single write transaction; Busy if another writer holds the store for too long.
  Result<std::unique_ptr<WriteTransaction>> BeginWrite();
  // Starts the write transaction of an edit of one region of a surface: on a backend with
  // concurrent writers (PostgreSQL) other region edits go on, and the edit locks its region
  // (Connection::LockRegion); elsewhere the same as BeginWrite.
  Result<std::unique_ptr<WriteTransaction>> BeginRegionWrite();

  // The store's CRS, or nullopt before the first DEM has set it.
  Result<std::optional<Crs>> GetCrs();
  // Records the store's CRS. REQUIRES: inside a WriteTransaction.
  Status SetCrs(const Crs& crs);
  Result<std::optional<std::string>> GetMeta(const std::string& key);
  // REQUIRES: inside a WriteTransaction.
  Status SetMeta(const std::string& key, const std::string& value);

  int SchemaVersion() const { return schema_version_; }
  const std::string& path() const { return db_->path(); }
  Connection& db() { return *db_; }

 private:
  Store(std::unique_ptr<Connection> db, int version);
  std::unique_ptr<Connection> db_;
  int schema_version_;
};

// The store's write transaction (a Transaction of db/sql/transaction.h): rolls back in its
// destructor unless committed.
class WriteTransaction {
 public:
  WriteTransaction(Store* store, Transaction tx) : store_(store), tx_(std::move(tx)) {}
  WriteTransaction(const WriteTransaction&) = delete;
  WriteTransaction& operator=(const WriteTransaction&) = delete;

  // Makes every change since BeginWrite() durable; after a failure nothing of it is kept.
  // REQUIRES: called at most once.
  Status Commit() { return tx_.Commit(); }
  Store& store() { return *store_; }

 private:
  Store* store_;
  Transaction tx_;
};

// A consistent read snapshot across several queries (a Snapshot of db/sql/transaction.h).
class ReadSnapshot {
 public:
  static Result<std::unique_ptr<ReadSnapshot>> Begin(Store& store);
  ReadSnapshot(const ReadSnapshot&) = delete;
  ReadSnapshot& operator=(const ReadSnapshot&) = delete;

 private:
  explicit ReadSnapshot(Snapshot snapshot) : snapshot_(std::move(snapshot)) {}
  Snapshot snapshot_;
};

}  // namespace tinbase
