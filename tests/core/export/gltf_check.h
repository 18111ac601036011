// Test helpers for .glb files: the Khronos glTF-Validator run on a file (node and the npm
// package gltf-validator, which scripts/install-test-tools.sh installs into tests/tools), and a
// plain split of a GLB into its JSON and binary chunks for checking content. A missing node or
// validator fails the test that asked, saying what to install; nothing is skipped. Header-only.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

namespace tinbase::testing {

inline std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The validator's report on `path` (its JSON), or null after recording a test failure when the
// validator could not run.
inline nlohmann::json ValidateGltf(const std::string& path) {
  const std::string script = std::string(TINBASE_TEST_DATA_DIR) + "/../tools/validate-gltf.js";
  if (std::system("command -v node >/dev/null 2>&1") != 0) {
    ADD_FAILURE() << "node is not installed: the glTF validator needs it (Debian: nodejs; then "
                     "scripts/install-test-tools.sh)";
    return nullptr;
  }
  const std::string err = path + ".validator-stderr";
  const std::string command = "node '" + script + "' '" + path + "' 2>'" + err + "'";
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "cannot run " << command;
    return nullptr;
  }
  std::string out;
  char buffer[4096];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  const int status = pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    ADD_FAILURE() << "the glTF validator did not run on " << path << ": " << ReadBytes(err)
                  << " (scripts/install-test-tools.sh installs it)";
    return nullptr;
  }
  std::remove(err.c_str());
  auto report = nlohmann::json::parse(out, nullptr, /*allow_exceptions=*/false);
  if (report.is_discarded()) ADD_FAILURE() << "the validator printed no JSON: " << out;
  return report;
}

// Asserts the validator finds no error in `path`, printing the errors it finds.
inline void ExpectValidGltf(const std::string& path) {
  const nlohmann::json report = ValidateGltf(path);
  if (report.is_null() || report.is_discarded()) return;  // already a failure
  const int errors = report["issues"]["numErrors"].get<int>();
  std::string messages;
  for (const auto& m : report["issues"]["messages"])
    if (m["severity"].get<int>() == 0) messages += m.dump() + "\n";
  EXPECT_EQ(errors, 0) << path << ":\n" << messages;
  EXPECT_EQ(report["info"]["version"], "2.0");
}

struct GlbFile {
  nlohmann::json gltf;
  std::string bin;

  // The bytes of bufferView `view`.
  std::string View(int view) const {
    const auto& v = gltf["bufferViews"][view];
    return bin.substr(v.value("byteOffset", size_t{0}), v["byteLength"].get<size_t>());
  }
  // Accessor `index`'s elements as doubles, component by component.
  template <typename T>
  std::vector<T> Values(const std::string& bytes) const {
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
  }
  std::vector<double> Accessor(int index) const {
    const auto& a = gltf["accessors"][index];
    const std::string bytes = View(a["bufferView"].get<int>());
    const size_t n = a["count"].get<size_t>() * (a["type"] == "SCALAR" ? 1 : 3);
    std::vector<double> out;
    switch (a["componentType"].get<int>()) {
      case 5126:
        for (float f : Values<float>(bytes)) out.push_back(f);
        break;
      case 5123:
        for (uint16_t u : Values<uint16_t>(bytes)) out.push_back(u);
        break;
      case 5125:
        for (uint32_t u : Values<uint32_t>(bytes)) out.push_back(u);
        break;
      default:
        ADD_FAILURE() << "unexpected component type " << a["componentType"];
    }
    out.resize(std::min(out.size(), n));
    return out;
  }
};

// The JSON and BIN chunks of a GLB (glTF 2.0, section "GLB File Format Specification").
inline GlbFile ParseGlb(const std::string& path) {
  GlbFile glb;
  const std::string bytes = ReadBytes(path);
  const auto u32 = [&](size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  EXPECT_GE(bytes.size(), 20u);
  if (bytes.size() < 20) return glb;
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), bytes.size());
  const uint32_t json_length = u32(12);
  EXPECT_EQ(u32(16), 0x4E4F534Au);  // "JSON"
  glb.gltf = nlohmann::json::parse(bytes.substr(20, json_length));
  const size_t bin_at = 20 + json_length;
  if (bin_at + 8 <= bytes.size()) {
    EXPECT_EQ(u32(bin_at + 4), 0x004E4942u);  // "BIN\0"
    glb.bin = bytes.substr(bin_at + 8, u32(bin_at));
  }
  return glb;
}

}  // namespace tinbase::testing
