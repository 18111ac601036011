// Fuzzes ReadXyz (core/pointcloud/xyz_reader.h): any bytes end in a cloud or an error, and every
// point read is usable.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "core/base/number_text.h"
#include "core/pointcloud/xyz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  auto cloud = tinbase::ReadXyz(in, "fuzz");
  if (!cloud.ok()) return 0;
  for (const auto& p : cloud->points)
    if (tinbase::CheckNumber(p.x) || tinbase::CheckNumber(p.y) || tinbase::CheckNumber(p.z))
      std::abort();
  return 0;
}
