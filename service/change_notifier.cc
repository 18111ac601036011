// ChangeNotifier: a condition variable over the newest committed transaction.
#include "service/change_notifier.h"

#include <algorithm>

namespace tinbase::service {

void ChangeNotifier::Notify(int64_t tx) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    newest_ = std::max(newest_, tx);
  }
  changed_.notify_all();
}

int64_t ChangeNotifier::WaitBeyond(int64_t since, std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, timeout, [&] { return newest_ > since || shut_down_; });
  return newest_;
}

void ChangeNotifier::Shutdown() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    shut_down_ = true;
  }
  changed_.notify_all();
}

bool ChangeNotifier::shut_down() {
  std::lock_guard<std::mutex> lock(mutex_);
  return shut_down_;
}

}  // namespace tinbase::service
