// Scratch files in the temporary directory.
#include "service/scratch_file.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace tinbase::service {

ScratchFile::ScratchFile(const std::string& suffix) {
  static std::atomic<uint64_t> counter{0};
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) dir = "/tmp";
  path_ = (dir / ("tinbase-serve-" + std::to_string(getpid()) + "-" +
                  std::to_string(counter.fetch_add(1)) + suffix))
              .string();
}

ScratchFile::~ScratchFile() {
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

Result<std::string> ScratchFile::Read() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return Status::IOError("cannot read " + path_);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace tinbase::service
