#include "core/export/tin_export.h"

#include <cassert>
#include <filesystem>
#include <system_error>

#include "core/base/output_file.h"
#include "core/export/geojson_writer.h"
#include "core/export/glb_writer.h"
#include "core/export/mesh_selection.h"
#include "core/export/obj_writer.h"
#include "core/export/ply_writer.h"
#include "core/export/stl_writer.h"

namespace tinbase {

namespace {

Status CheckInput(const Tin& tin, const std::string& path, const ExportOptions& options) {
  if (!options.triangle_ids.empty() && options.triangle_ids.size() != tin.triangles.size())
    return Status::InvalidArgument(path + ": " + std::to_string(options.triangle_ids.size()) +
                                   " triangle ids for " + std::to_string(tin.triangles.size()) +
                                   " triangles");
  if (!options.triangle_feature.empty() && options.triangle_feature.size() != tin.triangles.size())
    return Status::InvalidArgument(path + ": " + std::to_string(options.triangle_feature.size()) +
                                   " feature ids for " + std::to_string(tin.triangles.size()) +
                                   " triangles");
#ifndef NDEBUG
  for (const TinTriangle& tri : tin.triangles) {
    for (uint32_t v : tri.v) assert(v < tin.vertices.size());
    assert(tri.tag == kNoTag || (tri.tag >= 0 && static_cast<size_t>(tri.tag) < tin.tags.size()));
  }
#endif
  return Status::Ok();
}

Status Write(const Tin& tin, const Crs* crs, const MeshSelection& selection,
             const ExportOptions& options, const std::string& path) {
  switch (options.format) {
    case ExportFormat::kObj:
      return WriteObj(tin, crs, selection, path);
    case ExportFormat::kPly:
      return WritePly(tin, crs, selection, path);
    case ExportFormat::kStl:
      return WriteStl(tin, crs, selection, path);
    case ExportFormat::kGlb:
      return WriteGlb(tin, crs, selection, {options.features, options.triangle_feature}, path);
    case ExportFormat::kGeoJson:
      return WriteGeoJson(tin, crs, selection, options.triangle_ids, path);
  }
  return Status::InvalidArgument("unknown export format");
}

// `status` with every mention of the temporary file replaced by the name the user gave.
Status Renamed(const Status& status, const std::string& temp, const std::string& path) {
  std::string m = status.message();
  for (size_t at = m.find(temp); at != std::string::npos; at = m.find(temp, at + path.size()))
    m.replace(at, temp.size(), path);
  switch (status.code()) {
    case StatusCode::kInvalidArgument:
      return Status::InvalidArgument(m);
    case StatusCode::kNotFound:
      return Status::NotFound(m);
    default:
      return Status::IOError(m);
  }
}

}  // namespace

Result<ExportReport> ExportTin(const Tin& tin, const Crs* crs, const std::string& path,
                               const ExportOptions& options) {
  TB_RETURN_IF_ERROR(CheckInput(tin, path, options));
  const MeshSelection selection = SelectTriangles(tin, options.visible_only);
  TB_ASSIGN_OR_RETURN(OutputFile out, OutputFile::Create(path));
  // Writers name the file they write in their messages; users know it by its final name.
  Status written = Write(tin, crs, selection, options, out.temp_path());
  if (!written.ok()) return Renamed(written, out.temp_path(), path);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(out.temp_path(), ec);
  TB_RETURN_IF_ERROR(out.Commit());
  ExportReport report;
  report.vertices = static_cast<int64_t>(selection.vertices.size());
  report.triangles = static_cast<int64_t>(selection.triangles.size());
  report.bytes = ec ? 0 : static_cast<int64_t>(bytes);
  return report;
}

}  // namespace tinbase
