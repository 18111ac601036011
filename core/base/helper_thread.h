// HelperThread: one worker thread kept for the life of its owner, which hands it one task at a
// time and waits for it, so work split into two parts many times (the scans of greedy
// refinement, core/tin/tolerance_refiner.cc) pays a hand-over per part, not a thread start.
//
// Both sides spin for a short while (kSpin) before they sleep: refinement hands over tasks of a
// few microseconds thousands of times a second, and a sleeping thread's wake-up (10-50 us on a
// VM) cost more than the task. Past kSpin the helper sleeps, so an idle owner costs no CPU.
// Thread-safety: Run and Wait are called by the owner's thread only.
#pragma once

#include <atomic>
#include <chrono>
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
      stop_.store(true, std::memory_order_release);
    }
    wake_.notify_one();
    thread_.join();
  }
  HelperThread(const HelperThread&) = delete;
  HelperThread& operator=(const HelperThread&) = delete;

  // Starts `task` on the helper and returns at once. REQUIRES: the last task was waited for.
  void Run(std::function<void()> task) {
    task_ = std::move(task);  // published by the release store of busy_
    {
      std::lock_guard<std::mutex> lock(mu_);
      busy_.store(true, std::memory_order_release);
    }
    wake_.notify_one();
  }

  // Returns once the task given to Run last has finished (at once when none is running).
  void Wait() {
    if (SpinWhile([this] { return busy_.load(std::memory_order_acquire); })) return;
    std::unique_lock<std::mutex> lock(mu_);
    done_.wait(lock, [this] { return !busy_.load(std::memory_order_acquire); });
  }

 private:
  // How long either side spins before it sleeps.
  static constexpr std::chrono::microseconds kSpin{50};

  // Spins while `still()` holds, up to kSpin; true when it stopped holding.
  template <typename Pred>
  static bool SpinWhile(Pred still) {
    const auto deadline = std::chrono::steady_clock::now() + kSpin;
    for (int i = 1;; ++i) {
      if (!still()) return true;
      if (i % 64 == 0 && std::chrono::steady_clock::now() > deadline) return false;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }

  void Loop() {
    for (;;) {
      const auto idle = [this] {
        return !busy_.load(std::memory_order_acquire) && !stop_.load(std::memory_order_acquire);
      };
      if (!SpinWhile(idle)) {
        std::unique_lock<std::mutex> lock(mu_);
        wake_.wait(lock, [&] { return !idle(); });
      }
      if (!busy_.load(std::memory_order_acquire)) return;  // stopping with nothing left to do
      task_();
      task_ = nullptr;
      {
        std::lock_guard<std::mutex> lock(mu_);
        busy_.store(false, std::memory_order_release);
      }
      done_.notify_one();
    }
  }

  std::mutex mu_;  // held to change busy_ or stop_, so a sleeper never misses the change
  std::condition_variable wake_, done_;
  std::function<void()> task_;  // the task busy_ says is given; touched by one side at a time
  std::atomic<bool> busy_{false}, stop_{false};
  std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace tinbase
