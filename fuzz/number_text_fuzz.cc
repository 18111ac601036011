// Fuzzes ParseNumberText (core/base/number_text.h): any bytes give an answer, and an answer
// without a problem is a usable number.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/base/number_text.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const tinbase::NumberText n = tinbase::ParseNumberText(text);
  if (!n.problem && (!std::isfinite(n.value) || std::fabs(n.value) > tinbase::kMaxMagnitude))
    std::abort();
  return 0;
}
