// Fuzzes ReadPointList (core/geometry/point_list.h), the x,y text of --points and --line: any
// bytes end in points or an error, and every point read is usable.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "core/base/number_text.h"
#include "core/geometry/point_list.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  auto points = tinbase::ReadPointList(in, "fuzz");
  if (!points.ok()) return 0;
  for (const tinbase::Point2& p : *points)
    if (tinbase::CheckNumber(p.x) || tinbase::CheckNumber(p.y)) std::abort();
  return 0;
}
