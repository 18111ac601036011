// StorePool: read connections per request, and the one writer.
#include "service/store_pool.h"

#include <utility>

namespace tinbase::service {

StoreLease::StoreLease(StorePool* pool, std::unique_ptr<Store> store, bool writer)
    : pool_(pool), store_(std::move(store)), writer_(writer) {}

StoreLease::StoreLease(StoreLease&& other) noexcept
    : pool_(other.pool_), store_(std::move(other.store_)), writer_(other.writer_) {
  other.pool_ = nullptr;
}

StoreLease::~StoreLease() {
  if (pool_ != nullptr && store_ != nullptr) pool_->Return(std::move(store_), writer_);
}

StorePool::StorePool(std::string path, std::unique_ptr<Store> writer, int max_readers)
    : path_(std::move(path)),
      max_readers_(max_readers),
      writer_(std::move(writer)),
      has_writer_(writer_ != nullptr) {}

Result<std::unique_ptr<StorePool>> StorePool::Open(const std::string& path, bool read_only,
                                                   int max_readers) {
  std::unique_ptr<Store> writer;
  if (read_only) {
    // Opening once checks that the file is a store tinbase can read, before the first request.
    TB_ASSIGN_OR_RETURN(auto probe, Store::Open(path, Store::Access::kReadOnly));
  } else {
    TB_ASSIGN_OR_RETURN(writer, Store::Open(path, Store::Access::kReadWrite));
  }
  return std::unique_ptr<StorePool>(new StorePool(path, std::move(writer), max_readers));
}

Result<StoreLease> StorePool::Reader() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!idle_readers_.empty()) {
      std::unique_ptr<Store> store = std::move(idle_readers_.back());
      idle_readers_.pop_back();
      return StoreLease(this, std::move(store), false);
    }
  }
  TB_ASSIGN_OR_RETURN(auto store, Store::Open(path_, Store::Access::kReadOnly));
  return StoreLease(this, std::move(store), false);
}

Result<StoreLease> StorePool::Writer() {
  if (!has_writer_) return Status::InvalidArgument("the service is read-only");
  std::unique_lock<std::mutex> lock(mutex_);
  writer_free_.wait(lock, [this] { return writer_ != nullptr; });
  return StoreLease(this, std::move(writer_), true);
}

void StorePool::Return(std::unique_ptr<Store> store, bool writer) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (writer) {
    writer_ = std::move(store);
    writer_free_.notify_one();
  } else if (static_cast<int>(idle_readers_.size()) < max_readers_) {
    idle_readers_.push_back(std::move(store));
  }
}

}  // namespace tinbase::service
