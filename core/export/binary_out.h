// BinaryOut: little-endian numbers appended to a byte buffer, for the binary writers (PLY, STL,
// GLB). The formats are little-endian by definition; this file is where that is decided, so the
// writers stay correct on a big-endian host. Plain value type.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <utility>

namespace tinbase {

class BinaryOut {
 public:
  std::string& bytes() { return bytes_; }
  void Reserve(size_t n) { bytes_.reserve(n); }

  template <typename T>
  void Put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
      for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
    bytes_.append(raw, sizeof(T));
  }
  void PutText(const std::string& text) { bytes_ += text; }

 private:
  std::string bytes_;
};

}  // namespace tinbase
