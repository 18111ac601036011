// In-memory files for GDAL's writers.
#include "service/memory_file.h"

#include <cpl_vsi.h>

#include <atomic>

namespace tinbase::service {

MemoryFile::MemoryFile(const std::string& suffix) {
  static std::atomic<uint64_t> counter{0};
  path_ = "/vsimem/tinbase-serve-" + std::to_string(counter.fetch_add(1)) + suffix;
}

MemoryFile::~MemoryFile() { VSIUnlink(path_.c_str()); }

Result<std::string> MemoryFile::Read() const {
  vsi_l_offset size = 0;
  // Borrowed: the buffer stays owned by the file, which the destructor removes.
  const GByte* data = VSIGetMemFileBuffer(path_.c_str(), &size, /*bUnlinkAndSeize=*/FALSE);
  if (data == nullptr) return Status::IOError(path_ + ": nothing was written");
  return std::string(reinterpret_cast<const char*>(data), static_cast<size_t>(size));
}

}  // namespace tinbase::service
