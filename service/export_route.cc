// GET /surfaces/{s}/export?format=glb|obj|geojson|landxml|ply|stl[&bbox=&feature=&visible_only=
// &tag=]: the file `tinbase export` writes for the same selection, as the answer's body. The
// writers write files (through OutputFile), so the file goes to a private temporary directory,
// its size is checked against ServiceOptions::max_result_bytes (413 naming the limit) before it
// is read into the answer, and the directory is removed whatever happens.
#include <stdlib.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/export/export_format.h"
#include "core/export/tin_export.h"
#include "db/export/export_features.h"
#include "db/export/landxml_export.h"
#include "db/query/surface_selection.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/surface_read.h"
#include "service/surface_route_parts.h"

namespace tinbase::service {

namespace {

// A directory of its own under the system's temporary directory, removed with its files when
// destroyed.
class ScratchDir {
 public:
  static Result<ScratchDir> Make() {
    std::error_code ec;
    std::string pattern = (std::filesystem::temp_directory_path(ec) / "tinbase-export-XXXXXX");
    if (ec || mkdtemp(pattern.data()) == nullptr)
      return Status::IOError("cannot make a temporary directory for the export");
    return ScratchDir(pattern);
  }
  ScratchDir(ScratchDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
  ScratchDir& operator=(ScratchDir&&) = delete;
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }

 private:
  explicit ScratchDir(std::string path) : path_(std::move(path)) {}
  std::string path_;
};

struct FormatInfo {
  const char* extension;
  const char* content_type;
};

FormatInfo InfoOf(const std::string& format) {
  if (format == "glb") return {"glb", "model/gltf-binary"};
  if (format == "obj") return {"obj", "model/obj"};
  if (format == "geojson") return {"geojson", "application/geo+json"};
  if (format == "landxml") return {"xml", "application/xml"};
  if (format == "ply") return {"ply", "application/octet-stream"};
  return {"stl", "model/stl"};
}

// Writes the selection in `format` (checked: a mesh format or "landxml") to `path`.
Status WriteExport(SurfaceRead& read, const std::string& format, const SurfaceFilter& filter,
                   const std::string& path) {
  if (format == "landxml") {
    TB_ASSIGN_OR_RETURN(LandXmlSurface surface,
                        LoadLandXmlSelection(read.store(), read.surface, filter));
    return ExportLandXml(surface, path);
  }
  TB_ASSIGN_OR_RETURN(ExportFormat mesh_format, ParseExportFormat(format));
  TB_ASSIGN_OR_RETURN(LoadedSurface selected, SelectSurface(read.store(), read.surface, filter));
  ExportOptions options;
  options.format = mesh_format;
  options.triangle_ids = selected.triangle_ids;
  if (mesh_format == ExportFormat::kGlb)
    TB_RETURN_IF_ERROR(AddExportFeatures(read.store(), read.surface, selected.tin, options));
  return ExportTin(selected.tin, read.crs != nullptr ? &read.crs->crs() : nullptr, path, options)
      .status();
}

// The file name the answer suggests: the surface's name with anything but [A-Za-z0-9._-]
// replaced, so no byte of a name can break out of the header.
std::string FileNameOf(const std::string& surface, const char* extension) {
  std::string name = surface;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  return name + "." + extension;
}

Result<std::string> ReadWhole(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) return Status::IOError("cannot read back the export");
  return bytes;
}

void Export(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto format = RequiredParam(req, "format");
  if (!format.ok()) return ReplyStatus(res, format.status());
  if (*format != "landxml" && !ParseExportFormat(*format).ok())
    return ReplyError(res, 400, "invalid_argument",
                      "parameter 'format': '" + *format + "' is not one of glb, obj, geojson, " +
                          "landxml, ply, stl");
  auto filter = FilterParams(req);
  if (!filter.ok()) return ReplyStatus(res, filter.status());
  auto read = BeginSurfaceRead(context, req);
  if (!read.ok()) return ReplyStatus(res, read.status());
  auto dir = ScratchDir::Make();
  if (!dir.ok()) return ReplyStatus(res, dir.status());
  const FormatInfo info = InfoOf(*format);
  const std::string path = dir->File(std::string("export.") + info.extension);
  if (Status s = WriteExport(*read, *format, *filter, path); !s.ok()) return ReplyStatus(res, s);
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return ReplyError(res, 500, "io_error", "the export left no file");
  const size_t limit = context.options().max_result_bytes;
  if (size > limit) return ReplyResultTooLarge(res, size, limit);
  auto bytes = ReadWhole(path);
  if (!bytes.ok()) return ReplyStatus(res, bytes.status());
  res.status = 200;
  res.body = std::move(*bytes);
  res.set_header("Content-Type", info.content_type);
  res.set_header("Content-Disposition",
                 "attachment; filename=\"" + FileNameOf(read->surface.name, info.extension) + "\"");
}

}  // namespace

void RegisterExportRoute(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/export)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               Export(context, req, res);
             });
}

}  // namespace tinbase::service
