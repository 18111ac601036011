#include "core/pointcloud/point_tin.h"

#include <tbb/parallel_invoke.h>

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

// The selected points as TIN vertices, copied once from the cloud.
std::vector<TinVertex> SelectedVertices(const PointCloud& cloud, const ClassSelection& selection) {
  std::vector<TinVertex> vertices;
  vertices.reserve(selection.classes.empty() ? cloud.points.size() : 0);
  for (const CloudPoint& p : cloud.points) {
    if (selection.Keeps(p.classification)) vertices.push_back({p.x, p.y, p.z, VertexKind::kLidar});
  }
  return vertices;
}

// Sorts `vertices` by x, then y, and leaves out each one at the x, y of an earlier one in input
// order (the stable sort puts that one first among equals): the vertex Cdt::InsertVertices keeps
// too. The x, y order is also the one the store writes vertex rows in. Returns how many went.
// Large inputs sort their halves as two tasks and merge them, which is still stable (the first
// half's elements go first among equals), so the order is the same on any number of threads: the
// store's writer is idle until the points are sorted, and the sort is a sizeable part of an
// import.
size_t SortDroppingDuplicates(std::vector<TinVertex>& vertices) {
  const auto by_xy = [](const TinVertex& a, const TinVertex& b) {
    return a.x != b.x ? a.x < b.x : a.y < b.y;
  };
  constexpr size_t kHalvesFrom = 100000;
  if (vertices.size() < kHalvesFrom) {
    std::stable_sort(vertices.begin(), vertices.end(), by_xy);
  } else {
    const auto middle = vertices.begin() + static_cast<ptrdiff_t>(vertices.size() / 2);
    tbb::parallel_invoke([&] { std::stable_sort(vertices.begin(), middle, by_xy); },
                         [&] { std::stable_sort(middle, vertices.end(), by_xy); });
    std::inplace_merge(vertices.begin(), middle, vertices.end(), by_xy);
  }
  const auto end =
      std::unique(vertices.begin(), vertices.end(),
                  [](const TinVertex& a, const TinVertex& b) { return a.x == b.x && a.y == b.y; });
  const size_t dropped = static_cast<size_t>(vertices.end() - end);
  vertices.erase(end, vertices.end());
  return dropped;
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

Result<PointSet> ReadPoints(const std::string& path, const PointTinOptions& options,
                            const std::optional<Crs>& target) {
  PointSet out;
  PointTinReport& report = out.report;
  std::vector<TinVertex>& vertices = out.vertices;
  {
    TB_ASSIGN_OR_RETURN(PointCloud cloud, ReadPointFile(path, &report.format));
    report.points_in = cloud.points.size();
    const ClassSelection selection = ChooseClasses(cloud, options.classes);
    report.classes = selection.description;
    vertices = SelectedVertices(cloud, selection);
    out.crs = target ? target : cloud.crs;
    if (target && cloud.crs && !cloud.crs->IsSame(*target)) {
      TB_RETURN_IF_ERROR(ReprojectXy(*cloud.crs, *target, vertices).WithContext(path));
      ConvertHeightUnits(*cloud.crs, *target, vertices);
      report.reprojected_from = cloud.crs->Label();
    }
  }
  report.selected = vertices.size();

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
  } else {
    report.duplicates = SortDroppingDuplicates(vertices);
  }
  return out;
}

namespace {

// InvalidArgument naming `path` for points that span no triangle.
Status NoTriangles(const std::string& path, const PointTinReport& report) {
  return Status::InvalidArgument(path + ": the " + std::to_string(report.kept) + " points of " +
                                 report.classes +
                                 " span no triangle (fewer than three, or all collinear)");
}

}  // namespace

Result<Tin> TriangulatePoints(const std::string& path, const std::vector<TinVertex>& points,
                              PointTinReport* report) {
  Cdt cdt;
  cdt.InsertVertices(points);
  Tin tin = cdt.ToTin();
  report->kept = tin.vertices.size();
  report->triangles = tin.triangles.size();
  if (tin.triangles.empty()) return NoTriangles(path, *report);
  return tin;
}

Status StreamPointTriangles(const std::string& path, const std::vector<TinVertex>& points,
                            int bands, const TriangleOrder& order, const TriangleSink& finished,
                            PointTinReport* report) {
  Cdt cdt;
  size_t triangles = 0;
  cdt.InsertVerticesInBands(points, bands, order, [&](TriangleBatch batch) {
    triangles += batch.triangles.size();
    finished(std::move(batch));
  });
  report->kept = points.size();
  report->triangles = triangles;
  if (triangles == 0) return NoTriangles(path, *report);
  return Status::Ok();
}

Result<PointTin> BuildPointTin(const std::string& path, const PointTinOptions& options,
                               const std::optional<Crs>& target) {
  TB_ASSIGN_OR_RETURN(PointSet points, ReadPoints(path, options, target));
  PointTin out;
  out.crs = std::move(points.crs);
  out.report = std::move(points.report);
  TB_ASSIGN_OR_RETURN(out.tin, TriangulatePoints(path, points.vertices, &out.report));
  return out;
}

}  // namespace tinbase
