// Small pieces the command kernels share: common arguments, number formatting, timing.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace tinbase::cli {

// Arguments every read command takes.
struct ReadArgs {
  std::string store;
  bool json = false;
};

// A number with up to `digits` significant digits and no trailing noise ("12.5", "1e-06").
inline std::string Num(double value, int digits = 10) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

class Stopwatch {
 public:
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace tinbase::cli
