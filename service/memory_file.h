// MemoryFile: a file in GDAL's in-memory file system (/vsimem/), for answers that GDAL's drivers
// write (a GeoTIFF window, a PNG) and that go to the client without touching the disk. Each
// object has its own unique name; the file is removed when the object dies.
// Thread-safety: one object per thread; /vsimem/ itself is thread-safe.
#pragma once

#include <string>

#include "core/base/status.h"

namespace tinbase::service {

class MemoryFile {
 public:
  // A name under /vsimem/ no other MemoryFile of this process uses, ending in `suffix` (".tif")
  // so drivers that look at the extension see the right one.
  explicit MemoryFile(const std::string& suffix);
  ~MemoryFile();
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;

  const std::string& path() const { return path_; }
  // The file's bytes. IOError naming the file when nothing was written there.
  Result<std::string> Read() const;

 private:
  std::string path_;
};

}  // namespace tinbase::service
