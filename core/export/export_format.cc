#include "core/export/export_format.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>

namespace tinbase {

namespace {

struct FormatEntry {
  ExportFormat format;
  const char* name;
  std::array<const char*, 2> extensions;  // lower case with the dot; nullptr when unused
};

constexpr std::array<FormatEntry, 5> kFormats = {{
    {ExportFormat::kObj, "obj", {".obj", nullptr}},
    {ExportFormat::kPly, "ply", {".ply", nullptr}},
    {ExportFormat::kStl, "stl", {".stl", nullptr}},
    {ExportFormat::kGlb, "glb", {".glb", nullptr}},
    {ExportFormat::kGeoJson, "geojson", {".geojson", ".json"}},
}};

}  // namespace

const char* ExportFormatName(ExportFormat format) {
  for (const FormatEntry& e : kFormats)
    if (e.format == format) return e.name;
  return "?";
}

std::string ExportFormatList() {
  std::string out;
  for (const FormatEntry& e : kFormats) out += (out.empty() ? "" : ", ") + std::string(e.name);
  return out;
}

Result<ExportFormat> ParseExportFormat(const std::string& name) {
  for (const FormatEntry& e : kFormats)
    if (name == e.name) return e.format;
  return Status::InvalidArgument("unknown export format '" + name +
                                 "' (expected one of: " + ExportFormatList() + ")");
}

std::optional<ExportFormat> ExportFormatFromPath(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext.empty()) return std::nullopt;
  for (const FormatEntry& e : kFormats)
    for (const char* known : e.extensions)
      if (known != nullptr && ext == known) return e.format;
  return std::nullopt;
}

}  // namespace tinbase
