// PointTin: a point file (LAS or XYZ) to a Delaunay TIN of `lidar` vertices, in memory.
//
// The steps db/point_import runs around its writes: read the file, keep the chosen classes,
// reproject to the target CRS, drop duplicate x, y, optionally thin by Voronoi density
// (voronoi_thinning.h) (ReadPoints), and bulk-Delaunay the survivors through the Cdt adapter
// (spatially sorted insertion; TriangulatePoints). The two halves are apart so the import can
// write the vertices while the triangulation runs. Kept apart from the store so all of it can be
// tested without one. Stateless; thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/pointcloud/point_cloud.h"
#include "core/pointcloud/voronoi_thinning.h"
#include "core/tin/tin.h"
#include "core/tin/triangle_batch.h"

namespace tinbase {

struct PointTinOptions {
  std::set<uint8_t> classes;  // empty: ground (class 2) when the file has any, else all points
  bool thin = false;
  ThinningOptions thinning;
};

struct PointTinReport {
  std::string format;     // "LAS 1.2, point format 3" or "XYZ"
  std::string classes;    // what the class filter kept (ClassSelection::description)
  size_t points_in = 0;   // points in the file
  size_t selected = 0;    // points of the kept classes
  size_t duplicates = 0;  // selected points at the x, y of an earlier one, left out
  size_t dropped = 0;     // thinned out
  size_t kept = 0;        // vertices of the TIN
  size_t triangles = 0;
  double cell_area_threshold = 0;  // when thinned
  std::string reprojected_from;    // the file's CRS label when it was reprojected, else empty
};

// The points of a file, ready to triangulate: no two at the same x, y.
struct PointSet {
  std::vector<TinVertex> vertices;  // kind kLidar; in x, y order unless thinned (input order)
  std::optional<Crs> crs;           // as PointTin::crs
  PointTinReport report;            // all but kept and triangles
};

struct PointTin {
  Tin tin;                 // every vertex kind kLidar; neighbours linked
  std::optional<Crs> crs;  // the TIN's CRS: the target when given, else the file's
  PointTinReport report;
};

// Reads `path` as LAS (extension .las; .laz is refused with the LAS reader's message) or as XYZ
// (any other extension). `format` receives the report's format string. Errors as ReadLas and
// ReadXyz.
Result<PointCloud> ReadPointFile(const std::string& path, std::string* format);

// Everything BuildPointTin does before the triangulation. Without thinning the points come out
// sorted by x, then y, each duplicate x, y left out but the first in file order. Errors as
// BuildPointTin's but the last.
Result<PointSet> ReadPoints(const std::string& path, const PointTinOptions& options,
                            const std::optional<Crs>& target);

// The Delaunay TIN of `points`, whose vertices are points.vertices in order; fills
// report->kept and report->triangles. InvalidArgument naming `path` when the points span no
// triangle. REQUIRES: no two points at the same x, y (as ReadPoints gives them).
Result<Tin> TriangulatePoints(const std::string& path, const std::vector<TinVertex>& points,
                              PointTinReport* report);

// TriangulatePoints, handing the triangles to `finished` in batches as they become final
// (Cdt::InsertVerticesInBands with `bands` bands, sorted by `order`) instead of returning them, so
// a store can write rows while the triangulation runs. Fills report->kept and report->triangles.
// InvalidArgument as TriangulatePoints, once every (then empty) batch is handed over.
// REQUIRES: as TriangulatePoints; bands >= 1.
Status StreamPointTriangles(const std::string& path, const std::vector<TinVertex>& points,
                            int bands, const TriangleOrder& order, const TriangleSink& finished,
                            PointTinReport* report);

// Builds the TIN of the file's points (ReadPoints, then TriangulatePoints). `target` is the CRS the
// TIN must be in (the store's), or nullopt to keep the file's; a file without a CRS (XYZ, or LAS
// without projection records) is taken to be in `target` already. Errors: those of ReadPointFile,
// ReprojectXy and ThinByVoronoiDensity (with the file named); InvalidArgument when the kept points
// span no triangle (fewer than three distinct points, or all collinear).
Result<PointTin> BuildPointTin(const std::string& path, const PointTinOptions& options,
                               const std::optional<Crs>& target);

}  // namespace tinbase
