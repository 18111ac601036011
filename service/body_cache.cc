// A least-recently-used cache of answer bodies.
#include "service/body_cache.h"

namespace tinbase::service {

std::shared_ptr<const std::string> BodyCache::Find(const std::string& key) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = index_.find(key);
  if (it == index_.end()) return nullptr;
  order_.splice(order_.begin(), order_, it->second);
  return it->second->second;
}

void BodyCache::Put(const std::string& key, std::shared_ptr<const std::string> body) {
  const size_t size = body->size() + key.size();
  if (size > budget_ / 4) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (index_.count(key) != 0) return;
  order_.emplace_front(key, std::move(body));
  index_[key] = order_.begin();
  bytes_ += size;
  while (bytes_ > budget_ && !order_.empty()) {
    const Entry& last = order_.back();
    bytes_ -= last.second->size() + last.first.size();
    index_.erase(last.first);
    order_.pop_back();
  }
}

}  // namespace tinbase::service
