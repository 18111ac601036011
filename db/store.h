// Store: one tinbase store (an SQLite file), the only way into its tables.
//
// A Store owns one connection (and, when it may write, a WalCheckpointer that keeps log
// checkpoints out of its commits). Create() makes a new store from the migrations; Open() checks
// that the file is a tinbase store, refuses one made by a newer tinbase and migrates an older one
// forward. Every write goes through a WriteTransaction (BEGIN IMMEDIATE: one writer at a time,
// readers keep their WAL snapshot), which rolls back in its destructor unless committed.
// Thread-safety: one Store per thread; several processes may open the same file.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "db/sqlite/sqlite_db.h"
#include "db/sqlite/wal_checkpointer.h"

namespace tinbase {

// 'TINB': marks an SQLite file as a tinbase store (PRAGMA application_id).
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

  // How much of a store file each connection opened after this call reads through a memory map
  // (SQLite's mmap_size; default kDefaultMemoryMapBytes, 0 = none). The map saves a system call
  // per page of every DEM block read; its pages are file cache the kernel may drop at will, but
  // they count as the process's resident memory. Process-wide; safe from any thread.
  static void SetMemoryMapLimit(int64_t bytes);
  static constexpr int64_t kDefaultMemoryMapBytes = int64_t{1} << 30;

  // Starts the single write transaction; Busy if another writer holds the store for too long.
  Result<std::unique_ptr<WriteTransaction>> BeginWrite();

  // The store's CRS, or nullopt before the first DEM has set it.
  Result<std::optional<Crs>> GetCrs();
  // Records the store's CRS. REQUIRES: inside a WriteTransaction.
  Status SetCrs(const Crs& crs);
  Result<std::optional<std::string>> GetMeta(const std::string& key);
  // REQUIRES: inside a WriteTransaction.
  Status SetMeta(const std::string& key, const std::string& value);

  int SchemaVersion() const { return schema_version_; }
  const std::string& path() const { return db_->path(); }
  SqliteDb& db() { return *db_; }

 private:
  Store(std::unique_ptr<SqliteDb> db, int version, Access access);
  std::unique_ptr<SqliteDb> db_;
  // After db_: destroyed first, while the connection it hooks is still open.
  std::unique_ptr<WalCheckpointer> checkpointer_;
  int schema_version_;
};

class WriteTransaction {
 public:
  explicit WriteTransaction(Store* store) : store_(store) {}
  ~WriteTransaction();
  WriteTransaction(const WriteTransaction&) = delete;
  WriteTransaction& operator=(const WriteTransaction&) = delete;

  // Makes every change since BeginWrite() durable; after a failure nothing of it is kept.
  Status Commit();
  Store& store() { return *store_; }

 private:
  Store* store_;
  bool done_ = false;
};

// A consistent read snapshot across several queries (a deferred SQLite read transaction).
class ReadSnapshot {
 public:
  static Result<std::unique_ptr<ReadSnapshot>> Begin(Store& store);
  ~ReadSnapshot();
  ReadSnapshot(const ReadSnapshot&) = delete;
  ReadSnapshot& operator=(const ReadSnapshot&) = delete;

 private:
  explicit ReadSnapshot(Store* store) : store_(store) {}
  Store* store_;
};

}  // namespace tinbase
