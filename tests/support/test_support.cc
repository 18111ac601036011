#include "tests/support/test_support.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "db/sql/connection.h"

namespace tinbase::testing {

std::string DataPath(const std::string& relative) {
  return std::string(TINBASE_TEST_DATA_DIR) + "/" + relative;
}

TempDir::TempDir() {
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  for (;;) {
    auto candidate = base / ("tinbase-test-" + std::to_string(rd()));
    if (std::filesystem::create_directory(candidate)) {
      dir_ = candidate.string();
      break;
    }
  }
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

std::map<std::string, std::string> TableChecksums(const std::string& store_path) {
  std::map<std::string, std::string> sums;
  auto db = Connection::Open(store_path, Connection::Mode::kReadOnly);
  if (!db.ok()) return {{"<error>", db.status().ToString()}};
  auto tables = (*db)->Prepare(
      (*db)->backend() == Backend::kSqlite
          ? "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
            "ORDER BY name"
          : "SELECT table_name FROM information_schema.tables WHERE table_schema = "
            "current_schema() AND table_type = 'BASE TABLE' ORDER BY table_name");
  if (!tables.ok()) return {{"<error>", tables.status().ToString()}};
  while (true) {
    auto row = (*tables)->Step();
    if (!row.ok() || !*row) break;
    const std::string table = (*tables)->ColumnText(0);
    auto rows = (*db)->Prepare("SELECT * FROM \"" + table + "\"");
    if (!rows.ok()) {
      sums[table] = rows.status().ToString();
      continue;
    }
    std::hash<std::string> hasher;
    size_t h = 0;
    int64_t count = 0;
    while (true) {
      auto r = (*rows)->Step();
      if (!r.ok() || !*r) break;
      std::string line;
      for (int c = 0; c < (*rows)->ColumnCount(); ++c) {
        size_t size = 0;
        const uint8_t* blob = (*rows)->ColumnBlob(c, &size);
        if (blob == nullptr && (*rows)->ColumnIsNull(c)) {
          line += "\x1fN";
          continue;
        }
        line += "\x1f";
        line.append(reinterpret_cast<const char*>(blob), size);
      }
      h += hasher(line) * 0x9E3779B97F4A7C15ull;  // order-independent: rows have no order
      ++count;
    }
    sums[table] = std::to_string(count) + ":" + std::to_string(h);
  }
  return sums;
}

CliResult RunCli(const std::string& args, const std::string& env) {
  TempDir tmp;
  const std::string out_path = tmp.Path("out");
  const std::string err_path = tmp.Path("err");
  const std::string command = env + " " + std::string(TINBASE_CLI) + " " + args + " >" + out_path +
                              " 2>" + err_path + " </dev/null";
  CliResult result;
  // fork + wait4 rather than std::system: wait4 reports the child's resource use, whose peak
  // RSS covers the shell and the tinbase process it waited for (Linux counts reaped children).
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  struct rusage usage {};
  if (pid < 0 || wait4(pid, &status, 0, &usage) != pid) {
    result.exit_code = 128;
    return result;
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  result.peak_rss_kib = usage.ru_maxrss;
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  result.out = slurp(out_path);
  result.err = slurp(err_path);
  return result;
}

}  // namespace tinbase::testing
