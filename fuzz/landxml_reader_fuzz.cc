// Fuzzes ReadLandXml (core/import/landxml_reader.h), the reader of `import landxml`: any bytes
// end in a surface or in one error line; every surface read has finite coordinates, faces whose
// vertex indices are in range, and features and constraints that name vertices it has. The
// reader takes a path, so each input is written to a file of this process first.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/import/landxml_reader.h"

namespace {

void CheckSurface(const tinbase::LandXmlSurface& s) {
  const size_t n = s.tin.vertices.size();
  for (const tinbase::TinVertex& v : s.tin.vertices)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) std::abort();
  for (const tinbase::TinTriangle& t : s.tin.triangles)
    for (uint32_t v : t.v)
      if (v >= n) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/tinbase-fuzz-landxml-" + std::to_string(getpid()) + ".xml";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  auto surface = tinbase::ReadLandXml(path);
  if (!surface.ok()) {
    if (surface.status().message().find('\n') != std::string::npos) std::abort();
    return 0;
  }
  CheckSurface(*surface);
  return 0;
}
