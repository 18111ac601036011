#include "db/surface_builder.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "db/change_log.h"
#include "db/dem_block_cache.h"
#include "db/dem_cell_source.h"

namespace tinbase {

namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Change BuildChange(const SurfaceInfo& surface, const Tin& tin) {
  Change change;
  change.surface = surface.id;
  change.action = "build";
  change.added = static_cast<int64_t>(tin.triangles.size());
  change.min_x = change.min_y = std::numeric_limits<double>::infinity();
  change.max_x = change.max_y = -std::numeric_limits<double>::infinity();
  for (const TinVertex& v : tin.vertices) {
    change.min_x = std::min(change.min_x, v.x);
    change.min_y = std::min(change.min_y, v.y);
    change.max_x = std::max(change.max_x, v.x);
    change.max_y = std::max(change.max_y, v.y);
  }
  return change;
}

// Greedy insertion of a DEM the block cache can hold works on its grid in memory, so it can
// refine on two threads (a DemCellSource serves one). A larger DEM is read block by block as the
// refinement goes, so the build is bounded by the TIN's size and the block cache, not by the
// DEM's: DEMs larger than memory build. A block that cannot be read fails the build with its
// error (the streamed source is sticky, and BuildGreedyTin checks it), never as nodata.
Result<Tin> GreedyTinOfStoredDem(DemStore& dems, const DemInfo& dem, GreedyOptions greedy,
                                 GreedyReport* report) {
  const double dem_bytes = static_cast<double>(dem.geometry.CellCount()) * sizeof(float);
  if (dem_bytes <= static_cast<double>(DemBlockCache::Instance().capacity())) {
    TB_ASSIGN_OR_RETURN(Grid grid, dems.ReadGrid(dem));
    return BuildGreedyTin(grid, greedy, report);
  }
  // Tile by tile, so blocks are decoded a few times each rather than once per insertion that
  // lands far from the last.
  greedy.tile = dem.block_size;
  DemCellSource source(dems, dem);
  return BuildGreedyTin(source, greedy, report);
}

Result<Tin> BuildGreedy(DemStore& dems, const DemInfo& dem, const SurfaceBuildOptions& options,
                        SurfaceInfo* spec, SurfaceBuildReport* report) {
  TB_ASSIGN_OR_RETURN(Tin tin, GreedyTinOfStoredDem(dems, dem, options.greedy, &report->quality));
  spec->kind = SurfaceKind::kDelaunay;
  // A point budget may stop greedy early: record the tolerance the surface really keeps, so
  // invariant 7 is a promise and not a wish.
  spec->tolerance = std::max(options.greedy.tolerance, report->quality.max_error);
  return tin;
}

// The TIN of `method` from the DEM's grid in memory; fills the method's part of `report` and the
// surface's kind and tolerance in `spec`.
Result<Tin> BuildInMemory(DemStore& dems, const DemInfo& dem, const SurfaceBuildOptions& options,
                          SurfaceInfo* spec, SurfaceBuildReport* report) {
  TB_ASSIGN_OR_RETURN(Grid grid, dems.ReadGrid(dem));
  TerrainBuildOptions o;
  o.method = options.method;
  o.tolerance = options.greedy.tolerance;
  o.threshold = options.vip_threshold;
  o.max_points = options.greedy.max_points;
  o.collapse = options.collapse;
  TerrainBuildReport r;
  TB_ASSIGN_OR_RETURN(Tin tin, BuildTerrainTin(grid, o, &r));
  report->quality.max_error = r.max_error;
  report->quality.rms_error = r.rms_error;
  report->quality.points = r.points;
  report->collapse = r.collapse;
  spec->kind = r.delaunay ? SurfaceKind::kDelaunay : SurfaceKind::kFree;
  // VIP and collapse have no error bound: their tolerance is the error they measured.
  const bool bounded = o.method == TerrainMethod::kGreedy || o.method == TerrainMethod::kRtin;
  spec->tolerance = bounded ? std::max(options.greedy.tolerance, r.max_error) : r.max_error;
  return tin;
}

}  // namespace

Result<DemInfo> ResolveDem(DemStore& dems, const std::string& name) {
  if (!name.empty()) return dems.Find(name);
  TB_ASSIGN_OR_RETURN(auto all, dems.List());
  if (all.empty()) return Status::NotFound("the store has no DEM: run 'tinbase dem import' first");
  if (all.size() > 1) {
    std::string names;
    for (const auto& d : all) names += (names.empty() ? "" : ", ") + d.name;
    return Status::InvalidArgument("the store has several DEMs (" + names +
                                   "): name one with --dem");
  }
  return all.front();
}

Result<SurfaceBuildReport> BuildSurfaceFromDem(Store& store, const SurfaceBuildOptions& options) {
  if (options.method == TerrainMethod::kCollapse && options.collapse.faces < 2)
    return Status::InvalidArgument("the collapse method needs a face budget of at least 2");
  if (options.surface.empty()) return Status::InvalidArgument("a surface needs a name");
  SurfaceStore surfaces(store);
  if (surfaces.Find(options.surface).ok())
    return Status::Conflict("a surface named '" + options.surface + "' already exists");

  DemStore dems(store);
  TB_ASSIGN_OR_RETURN(DemInfo dem, ResolveDem(dems, options.dem));
  SurfaceBuildReport report;
  if (options.progress) options.progress(0.0);
  auto start = std::chrono::steady_clock::now();
  SurfaceInfo spec;
  TB_ASSIGN_OR_RETURN(Tin tin, options.method == TerrainMethod::kGreedy
                                   ? BuildGreedy(dems, dem, options, &spec, &report)
                                   : BuildInMemory(dems, dem, options, &spec, &report));
  report.build_seconds = SecondsSince(start);
  // The bar's split, an estimate: building the TIN is most of a build, writing its rows the rest.
  if (options.progress) options.progress(0.7);

  start = std::chrono::steady_clock::now();
  TB_ASSIGN_OR_RETURN(auto tx, store.BeginWrite());
  spec.name = options.surface;
  spec.method = TerrainMethodName(options.method);
  spec.dem = dem.id;
  TB_ASSIGN_OR_RETURN(report.surface, surfaces.Create(spec, tin));
  TB_ASSIGN_OR_RETURN(report.tx, AppendChange(store, BuildChange(report.surface, tin)));
  TB_RETURN_IF_ERROR(tx->Commit());
  if (options.progress) options.progress(1.0);
  report.write_seconds = SecondsSince(start);
  report.vertices = static_cast<int64_t>(tin.vertices.size());
  report.triangles = static_cast<int64_t>(tin.triangles.size());
  return report;
}

}  // namespace tinbase
