// PointImport: a LiDAR (LAS) or XYZ point file to a new `delaunay` surface of `lidar` vertices.
//
// One write transaction: read the file's points (core/pointcloud/point_tin.h: class filter,
// reprojection to the store's CRS, duplicates out, optional Voronoi density thinning), adopt the
// file's CRS when the store has none yet, then bulk-Delaunay the points as a TBB task while the
// vertex rows are written (SurfaceStore::CreateWhileTriangulating) and write the triangles.
// Nothing is written on any error. The surface is the same on any number of threads.
// Thread-safety: as Store (one per thread); uses TBB's threads during the import.
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <string>

#include "core/base/status.h"
#include "core/pointcloud/point_tin.h"
#include "db/store.h"

namespace tinbase {

struct PointImportOptions {
  std::string file;           // .las, or a text file of x y z
  std::string surface;        // name of the new surface
  std::set<uint8_t> classes;  // empty: ground (class 2) when the file has any, else all points
  bool thin = false;
  ThinningOptions thresholds;  // used when `thin`
  // Called now and then with the fraction of the import done (the points read, then the
  // triangles handed to the writer against the ~2 per point a triangulation has), from the
  // calling thread or the triangulating task's; empty: not called. For progress bars.
  std::function<void(double fraction)> progress;
};

struct PointImportReport {
  int64_t surface_id = 0;
  std::string crs;           // label of the CRS the surface is in, empty when none
  bool adopted_crs = false;  // the store took the file's CRS
  PointTinReport points;     // points in, selected, duplicates, dropped, kept, triangles
};

// Imports options.file as surface options.surface. Returns the report on success. Errors:
// InvalidArgument for an empty surface name and for everything BuildPointTin rejects (named by
// file), Conflict when the surface name is taken, Busy when another writer holds the store,
// and the store's errors.
Result<PointImportReport> ImportPoints(Store& store, const PointImportOptions& options);

}  // namespace tinbase
