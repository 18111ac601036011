// Running GDAL's own command-line readers (ogrinfo, gdalinfo; Debian package gdal-bin) from
// tests, so files we write are judged by a reader we did not write. A missing binary fails the
// test with a message naming the package: it never skips.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

namespace tinbase::testing {

struct ToolResult {
  int exit_code = -1;
  std::string out;  // stdout and stderr together
};

// Runs `command` through the shell; `command` is quoted by the caller.
inline ToolResult RunTool(const std::string& command) {
  ToolResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// True when `tool` is on PATH; otherwise records a failure naming it and its package.
inline bool HaveTool(const std::string& tool, const std::string& package = "gdal-bin") {
  if (RunTool("command -v " + tool).exit_code == 0) return true;
  ADD_FAILURE() << tool << " is not installed (Debian package " << package
                << "): the test cannot check the file without it";
  return false;
}

// The text between `key` and the end of its line in `text`, or "" when `key` is absent.
inline std::string ValueAfter(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  if (at == std::string::npos) return "";
  const size_t begin = at + key.size();
  return text.substr(begin, text.find('\n', begin) - begin);
}

}  // namespace tinbase::testing
