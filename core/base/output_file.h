// OutputFile: a file written under a temporary name beside its final path and renamed onto it
// only when the writer says it is complete.
//
// Every exporter writes through one, so that an error half way (a full disk, a bad option found
// late, an empty selection) never leaves a truncated file that another program would read as
// valid, and an existing file at the path is replaced only by a complete one. Writers that take
// a path (GDAL drivers, libxml2, OpenVDB) write to temp_path(); stream writers open it themselves.
// Move-only; not thread-safe.
#pragma once

#include <string>
#include <utility>

#include "core/base/status.h"

namespace tinbase {

class OutputFile {
 public:
  // Checks that `path` can be written: its directory exists and is writable, and `path` is not a
  // directory. IOError naming the path and the reason otherwise. Nothing is created yet.
  static Result<OutputFile> Create(const std::string& path);

  OutputFile(OutputFile&& other) noexcept;
  OutputFile& operator=(OutputFile&& other) noexcept;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  // Removes the temporary file unless Commit() succeeded.
  ~OutputFile();

  const std::string& path() const { return path_; }
  // Where the writer writes: "<path>.partial-<pid>-<n>" in the same directory, so the final
  // rename stays on one file system.
  const std::string& temp_path() const { return temp_path_; }

  // Renames temp_path() onto path(). IOError when the writer wrote nothing there or the rename
  // fails (the temporary file is then removed).
  Status Commit();

 private:
  OutputFile(std::string path, std::string temp_path)
      : path_(std::move(path)), temp_path_(std::move(temp_path)) {}
  void RemoveTemp();

  std::string path_;
  std::string temp_path_;
  bool committed_ = false;
};

}  // namespace tinbase
