// ScratchFile: a file in the system's temporary directory for writers that need a real path
// (the GLB writer streams through std::ofstream), removed when the object dies. Names are unique
// per process and object. Thread-safety: one object per thread.
#pragma once

#include <string>

#include "core/base/status.h"

namespace tinbase::service {

class ScratchFile {
 public:
  explicit ScratchFile(const std::string& suffix);
  ~ScratchFile();
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  const std::string& path() const { return path_; }
  // The file's bytes; IOError naming the file when it cannot be read.
  Result<std::string> Read() const;

 private:
  std::string path_;
};

}  // namespace tinbase::service
