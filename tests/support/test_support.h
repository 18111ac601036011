// Helpers shared by the test suite: temporary stores, data paths, table checksums, running the CLI.
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "db/store.h"

namespace tinbase::testing {

// tests/data/<relative>.
std::string DataPath(const std::string& relative);

// A fresh directory under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
};

// A checksum of every row of every table, by table name: equal maps mean equal contents.
std::map<std::string, std::string> TableChecksums(const std::string& store_path);

struct CliResult {
  int exit_code = 0;
  std::string out;
  std::string err;
  int64_t peak_rss_kib = 0;  // the most memory the command held resident at once
};
// Runs the tinbase binary with `args` (shell-quoted by the caller where needed), with `env`
// ("NAME=value ...") added to its environment.
CliResult RunCli(const std::string& args, const std::string& env = "");

}  // namespace tinbase::testing
