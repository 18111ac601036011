// HelperThread: one worker thread kept for the life of its owner, which hands it one task at a
// time and waits for it, so work split into two parts many times (the row halves of a large
// triangle's scan, core/tin/tolerance_refiner.cc) pays a wake-up per part, not a thread start.
// Thread-safety: Run and Wait are called by the owner's thread only.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <utility>

namespace tinbase {

class HelperThread {
 public:
  HelperThread() : thread_([this] { Loop(); }) {}
  ~HelperThread() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  // Starts `task` on the helper and returns at once. REQUIRES: the last task was waited for.
  void Run(std::function<void()> task) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      task_ = std::move(task);
    }
    wake_.notify_one();
  }

  // Returns once the task given to Run last has finished (at once when none is running).
  void Wait() {
    std::unique_lock<std::mutex> lock(mu_);
    done_.wait(lock, [this] { return !task_; });
  }

 private:
  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || task_; });
      if (!task_) return;  // stopping with nothing left to do
      lock.unlock();
      task_();
      lock.lock();
      task_ = nullptr;
      done_.notify_one();
    }
  }

  std::mutex mu_;
  std::condition_variable wake_, done_;
  std::function<void()> task_;  // the running task; empty when idle
  bool stop_ = false;
  std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace tinbase
