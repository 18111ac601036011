// StorePool: the service's connections to its store. Readers borrow one read-only connection per
// request and return it; SQLite's WAL gives each read its own snapshot, so readers never wait for
// a writer. Writes go through the one writer connection, one at a time in this process (other
// processes are serialised by SQLite's lock and its busy timeout).
// Thread-safety: every member may be called from any thread.
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/store.h"

namespace tinbase::service {

class StorePool;

// A borrowed connection; goes back to its pool (or releases the writer) when destroyed.
class StoreLease {
 public:
  StoreLease(StoreLease&& other) noexcept;
  StoreLease& operator=(StoreLease&&) = delete;
  StoreLease(const StoreLease&) = delete;
  StoreLease& operator=(const StoreLease&) = delete;
  ~StoreLease();

  Store& store() { return *store_; }
  Store* operator->() { return store_.get(); }

 private:
  friend class StorePool;
  StoreLease(StorePool* pool, std::unique_ptr<Store> store, bool writer);
  StorePool* pool_;
  std::unique_ptr<Store> store_;
  bool writer_;
};

class StorePool {
 public:
  // Opens the store once read-write (migrating it forward, checking it is a tinbase store) unless
  // `read_only`, and keeps up to `max_readers` read-only connections.
  static Result<std::unique_ptr<StorePool>> Open(const std::string& path, bool read_only,
                                                 int max_readers);

  // A read-only connection for one request (opened on first need, then reused).
  Result<StoreLease> Reader();
  // The writer connection; waits while another request of this process holds it.
  // FailedPrecondition-like InvalidArgument when the pool was opened read-only.
  Result<StoreLease> Writer();

  const std::string& path() const { return path_; }

 private:
  friend class StoreLease;
  StorePool(std::string path, std::unique_ptr<Store> writer, int max_readers);
  void Return(std::unique_ptr<Store> store, bool writer);

  std::string path_;
  int max_readers_;
  std::mutex mutex_;
  std::condition_variable writer_free_;
  std::unique_ptr<Store> writer_;  // null while leased, or when read-only
  bool has_writer_;
  std::vector<std::unique_ptr<Store>> idle_readers_;
};

}  // namespace tinbase::service
