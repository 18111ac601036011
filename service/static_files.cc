// Static files of the web viewer (static_files.h).
#include "service/static_files.h"

#include <array>
#include <cctype>
#include <string_view>
#include <system_error>
#include <utility>

namespace tinbase::service {

namespace {

constexpr size_t kMaxPathLength = 1024;

bool IsPlainNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.' ||
         c == '@' || c == '+';
}

// OK when `segment` is a plain file or directory name; InvalidArgument naming it otherwise.
Status CheckSegment(std::string_view segment) {
  if (segment.empty()) return Status::InvalidArgument("an empty path segment is not allowed");
  if (segment.front() == '.')
    return Status::InvalidArgument("path segment '" + std::string(segment) +
                                   "' is not allowed (no '.', '..' or hidden files)");
  for (char c : segment) {
    if (!IsPlainNameChar(c))
      return Status::InvalidArgument("path segment '" + std::string(segment) +
                                     "' has a character the viewer's files never use");
  }
  return Status::Ok();
}

bool IsInside(const std::filesystem::path& file, const std::filesystem::path& root) {
  auto f = file.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++f) {
    if (f == file.end() || *f != *r) return false;
  }
  return true;
}

}  // namespace

Result<std::filesystem::path> ResolveStaticPath(const std::filesystem::path& root,
                                                const std::string& relative) {
  if (relative.size() > kMaxPathLength)
    return Status::InvalidArgument("the path is longer than " + std::to_string(kMaxPathLength) +
                                   " characters");
  size_t start = 0;
  while (true) {
    const size_t slash = relative.find('/', start);
    const std::string_view segment = std::string_view(relative).substr(
        start, slash == std::string::npos ? slash : slash - start);
    TB_RETURN_IF_ERROR(CheckSegment(segment));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  // The segments cannot climb, but a symbolic link inside the root still could: compare the
  // canonical forms.
  std::error_code error;
  const std::filesystem::path canonical_root = std::filesystem::canonical(root, error);
  if (error) return Status::NotFound("the viewer's directory is missing");
  const std::filesystem::path file = std::filesystem::canonical(canonical_root / relative, error);
  if (error || !IsInside(file, canonical_root) || !std::filesystem::is_regular_file(file, error))
    return Status::NotFound("no file '" + relative + "' in the viewer");
  return file;
}

const char* StaticContentType(const std::filesystem::path& file) {
  static constexpr std::array<std::pair<std::string_view, const char*>, 16> kTypes = {{
      {".html", "text/html; charset=utf-8"},
      {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"},
      {".cjs", "text/javascript; charset=utf-8"},
      {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},
      {".wasm", "application/wasm"},
      {".png", "image/png"},
      {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},
      {".gif", "image/gif"},
      {".svg", "image/svg+xml"},
      {".xml", "application/xml"},
      {".ktx2", "image/ktx2"},
      {".glb", "model/gltf-binary"},
      {".txt", "text/plain; charset=utf-8"},
  }};
  const std::string extension = file.extension().string();
  for (const auto& [ext, type] : kTypes) {
    if (extension == ext) return type;
  }
  return "application/octet-stream";
}

}  // namespace tinbase::service
