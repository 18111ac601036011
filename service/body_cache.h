// BodyCache: answers made from stored bytes (a tile with refused extensions taken out, then
// gzipped), kept by a key that names the source and its content (the entity tag), so a warm
// request skips the decode, encode and deflate. Least recently used first out, within a byte
// budget. An entry can never be stale: a changed source has another tag, hence another key; the
// old entry just ages out. Thread-safety: every member may be called from any thread.
#pragma once

#include <cstddef>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <utility>

namespace tinbase::service {

class BodyCache {
 public:
  explicit BodyCache(size_t budget_bytes) : budget_(budget_bytes) {}

  // The body stored under `key`, or null.
  std::shared_ptr<const std::string> Find(const std::string& key);
  // Stores `body` under `key` (bodies larger than a quarter of the budget are not kept).
  void Put(const std::string& key, std::shared_ptr<const std::string> body);

 private:
  using Entry = std::pair<std::string, std::shared_ptr<const std::string>>;
  std::mutex mutex_;
  size_t budget_;
  size_t bytes_ = 0;
  std::list<Entry> order_;  // most recently used first
  std::unordered_map<std::string, std::list<Entry>::iterator> index_;
};

}  // namespace tinbase::service
