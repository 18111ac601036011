// OutputFile: see output_file.h.
#include "core/base/output_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace tinbase {

namespace {

std::string TempPathFor(const std::string& path) {
  static std::atomic<int> counter{0};
  return path + ".partial-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
}

Status CannotWrite(const std::string& path, const std::string& why) {
  return Status::IOError("cannot write '" + path + "': " + why);
}

}  // namespace

Result<OutputFile> OutputFile::Create(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) return Status::InvalidArgument("no output path given");
  std::error_code ec;
  if (fs::is_directory(path, ec)) return CannotWrite(path, "it is a directory");
  fs::path dir = fs::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) return CannotWrite(path, "no directory " + dir.string());
  if (access(dir.c_str(), W_OK) != 0) return CannotWrite(path, std::strerror(errno));
  if (fs::exists(path, ec) && access(path.c_str(), W_OK) != 0)
    return CannotWrite(path, std::strerror(errno));
  return OutputFile(path, TempPathFor(path));
}

OutputFile::OutputFile(OutputFile&& other) noexcept
    : path_(std::move(other.path_)),
      temp_path_(std::move(other.temp_path_)),
      committed_(other.committed_) {
  other.committed_ = true;  // the moved-from object owns no file
}

OutputFile& OutputFile::operator=(OutputFile&& other) noexcept {
  if (this != &other) {
    RemoveTemp();
    path_ = std::move(other.path_);
    temp_path_ = std::move(other.temp_path_);
    committed_ = other.committed_;
    other.committed_ = true;
  }
  return *this;
}

OutputFile::~OutputFile() { RemoveTemp(); }

void OutputFile::RemoveTemp() {
  if (committed_ || temp_path_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove(temp_path_, ignored);
}

Status OutputFile::Commit() {
  if (committed_) return Status::Ok();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(temp_path_, ec))
    return CannotWrite(path_, "the writer produced no file");
  std::filesystem::rename(temp_path_, path_, ec);
  if (ec) {
    RemoveTemp();
    return CannotWrite(path_, ec.message());
  }
  committed_ = true;
  return Status::Ok();
}

}  // namespace tinbase
