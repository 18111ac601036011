#include "core/pointcloud/point_tin.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "core/geometry/cdt.h"
#include "core/geometry/reproject.h"
#include "core/pointcloud/las_reader.h"
#include "core/pointcloud/xyz_reader.h"

namespace tinbase {
namespace {

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::vector<TinVertex> ToVertices(const std::vector<CloudPoint>& points) {
  std::vector<TinVertex> vertices;
  vertices.reserve(points.size());
  for (const CloudPoint& p : points) vertices.push_back({p.x, p.y, p.z, VertexKind::kLidar});
  return vertices;
}

}  // namespace

Result<PointCloud> ReadPointFile(const std::string& path, std::string* format) {
  const std::string ext = LowerExtension(path);
  if (ext == ".las" || ext == ".laz") {
    TB_ASSIGN_OR_RETURN(LasFile las, ReadLas(path));
    *format = "LAS " + std::to_string(las.header.version_major) + "." +
              std::to_string(las.header.version_minor) + ", point format " +
              std::to_string(las.header.point_format);
    return std::move(las.cloud);
  }
  *format = "XYZ";
  return ReadXyz(path);
}

Result<PointTin> BuildPointTin(const std::string& path, const PointTinOptions& options,
                               const std::optional<Crs>& target) {
  PointTin out;
  PointTinReport& report = out.report;
  TB_ASSIGN_OR_RETURN(PointCloud cloud, ReadPointFile(path, &report.format));
  report.points_in = cloud.points.size();
  const ClassSelection selection = ChooseClasses(cloud, options.classes);
  report.classes = selection.description;
  std::vector<TinVertex> vertices = ToVertices(SelectPoints(cloud, selection));
  report.selected = vertices.size();

  out.crs = target ? target : cloud.crs;
  if (target && cloud.crs && !cloud.crs->IsSame(*target)) {
    TB_RETURN_IF_ERROR(ReprojectXy(*cloud.crs, *target, vertices).WithContext(path));
    ConvertHeightUnits(*cloud.crs, *target, vertices);
    report.reprojected_from = cloud.crs->Label();
  }

  if (options.thin) {
    auto thinned = ThinByVoronoiDensity(vertices, options.thinning);
    if (!thinned.ok()) return thinned.status().WithContext(path);
    std::vector<TinVertex> kept;
    kept.reserve(thinned->kept.size());
    for (uint32_t i : thinned->kept) kept.push_back(vertices[i]);
    vertices = std::move(kept);
    report.duplicates = thinned->report.duplicates;
    report.dropped = thinned->report.dropped;
    report.cell_area_threshold = thinned->report.cell_area_threshold;
  }

  Cdt cdt;
  cdt.InsertVertices(vertices);
  out.tin = cdt.ToTin();
  if (!options.thin) report.duplicates = vertices.size() - out.tin.vertices.size();
  report.kept = out.tin.vertices.size();
  report.triangles = out.tin.triangles.size();
  if (out.tin.triangles.empty()) {
    return Status::InvalidArgument(path + ": the " + std::to_string(report.kept) + " points of " +
                                   report.classes +
                                   " span no triangle (fewer than three, or all collinear)");
  }
  return out;
}

}  // namespace tinbase
