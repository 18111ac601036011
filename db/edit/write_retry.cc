#include "db/edit/write_retry.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <random>
#include <thread>

namespace tinbase {

void PauseBeforeRetry(int attempt) {
  thread_local std::minstd_rand random(std::random_device{}());
  const int64_t cap = std::min<int64_t>(int64_t{5} << std::min(attempt, 10), 300);
  std::uniform_int_distribution<int64_t> millis(1, cap);
  std::this_thread::sleep_for(std::chrono::milliseconds(millis(random)));
}

}  // namespace tinbase
