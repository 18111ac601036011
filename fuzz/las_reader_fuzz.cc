// Fuzzes ReadLas (core/pointcloud/las_reader.h): header, VLRs and point records of any bytes end
// in a cloud or an error, never a crash, a read past the file or an allocation the file cannot
// back. ReadLas reads a path, so each input goes to one file in memory-backed /dev/shm.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

#include "core/pointcloud/las_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/dev/shm/tinbase-fuzz-las-" + std::to_string(getpid());
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  auto las = tinbase::ReadLas(path);
  if (las.ok() && las->header.point_count < las->cloud.points.size()) std::abort();
  return 0;
}
