#include "db/point_import.h"

#include "db/surface_store.h"

namespace tinbase {

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
  TB_ASSIGN_OR_RETURN(PointTin built, BuildPointTin(options.file, tin_options, store_crs));

  PointImportReport report;
  report.points = built.report;
  if (built.crs) report.crs = built.crs->Label();
  if (!store_crs && built.crs) {
    TB_RETURN_IF_ERROR(store.SetCrs(*built.crs));
    report.adopted_crs = true;
  }
  SurfaceInfo spec;
  spec.name = options.surface;
  spec.kind = SurfaceKind::kDelaunay;
  spec.method = options.thin ? "lidar-voronoi-thinned" : "lidar";
  TB_ASSIGN_OR_RETURN(SurfaceInfo created, SurfaceStore(store).Create(spec, built.tin));
  report.surface_id = created.id;
  TB_RETURN_IF_ERROR(tx->Commit());
  return report;
}

}  // namespace tinbase
