// ChangeNotifier: wakes the change feed's waiting clients when a write of this service commits.
// Writes of other processes (the CLI) are found by the feed polling the changes table; this only
// makes this service's own edits arrive at once.
// Thread-safety: every member may be called from any thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>

namespace tinbase::service {

class ChangeNotifier {
 public:
  // Records that transaction `tx` committed and wakes every waiter.
  void Notify(int64_t tx);
  // Waits until a transaction after `since` is notified, or `timeout` passes, or Shutdown();
  // returns the newest notified transaction (which may still be <= since).
  int64_t WaitBeyond(int64_t since, std::chrono::milliseconds timeout);
  // Wakes every waiter for good (the server is stopping).
  void Shutdown();
  bool shut_down();

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  int64_t newest_ = 0;
  bool shut_down_ = false;
};

}  // namespace tinbase::service
