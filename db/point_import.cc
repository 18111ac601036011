#include "db/point_import.h"

#include <algorithm>

#include "db/surface_store.h"

namespace tinbase {
namespace {

// Bands of the streamed triangulation: after each, the triangles below it are final and their
// rows can be written while the next is inserted. Six, shrinking upwards
// (Cdt::InsertVerticesInBands: the first holds 31 % of the points, the last 1/36): the first
// band then ends about when the writer has written the vertex rows, so it does not wait for
// triangles (with four, the first 44 %, it waited a noticeable part of the import), and little
// is left to write after the triangulation. More bands cost a scan of the faces each. Small
// imports, written in moments anyway, go in one band. The bands depend on the point count
// alone, so the surface does not depend on the number of threads.
int TriangulationBands(size_t points) { return points < 20000 ? 1 : 6; }

}  // namespace

Result<PointImportReport> ImportPoints(Store& store, const PointImportOptions& options) {
  if (options.surface.empty()) {
    return Status::InvalidArgument(options.file + ": no surface name given for the points");
  }
  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  // The CRS is read inside the transaction so no other writer can set it between our read and
  // our write.
  TB_ASSIGN_OR_RETURN(std::optional<Crs> store_crs, store.GetCrs());
  PointTinOptions tin_options;
  tin_options.classes = options.classes;
  tin_options.thin = options.thin;
  tin_options.thinning = options.thresholds;
  // The bar's split: reading (and thinning) the points is its first 30 %, an estimate; the rest
  // follows the triangles handed to the writer, whose final count (~2 a point) is known.
  constexpr double kRead = 0.3;
  if (options.progress) options.progress(0.0);
  TB_ASSIGN_OR_RETURN(PointSet points, ReadPoints(options.file, tin_options, store_crs));
  if (options.progress) options.progress(kRead);

  PointImportReport report;
  report.points = points.report;
  if (points.crs) report.crs = points.crs->Label();
  if (!store_crs && points.crs) {
    TB_RETURN_IF_ERROR(store.SetCrs(*points.crs));
    report.adopted_crs = true;
  }
  SurfaceInfo spec;
  spec.name = options.surface;
  spec.kind = SurfaceKind::kDelaunay;
  spec.method = options.thin ? "lidar-voronoi-thinned" : "lidar";
  // The report is filled in by the triangulating task; CreateWhileTriangulating has waited for
  // it before it returns.
  TB_ASSIGN_OR_RETURN(
      SurfaceInfo created,
      SurfaceStore(store).CreateWhileTriangulating(
          spec, points.vertices, [&](const TriangleOrder& order, const TriangleSink& finished) {
            if (!options.progress)
              return StreamPointTriangles(options.file, points.vertices,
                                          TriangulationBands(points.vertices.size()), order,
                                          finished, &report.points);
            const double expected = 2.0 * static_cast<double>(points.vertices.size());
            const TriangleSink counted = [&](TriangleBatch batch) {
              const double done = static_cast<double>(batch.first + batch.triangles.size());
              finished(std::move(batch));
              options.progress(kRead + (1 - kRead) * std::min(1.0, done / expected));
            };
            return StreamPointTriangles(options.file, points.vertices,
                                        TriangulationBands(points.vertices.size()), order, counted,
                                        &report.points);
          }));
  report.surface_id = created.id;
  TB_RETURN_IF_ERROR(tx->Commit());
  return report;
}

}  // namespace tinbase
