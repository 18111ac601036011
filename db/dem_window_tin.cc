// The reduced TIN of a DEM window.
#include "db/dem_window_tin.h"

#include <string>
#include <utility>

#include "core/tin/grid_triangulation.h"

namespace tinbase {

Result<DemWindowTin> BuildDemWindowTin(DemStore& dems, const DemInfo& dem, const DemBox& box,
                                       const DemWindowTinOptions& options) {
  if (options.faces < 0 || options.faces == 1)
    return Status::InvalidArgument("the face budget must be at least 2, got " +
                                   std::to_string(options.faces));
  DemWindowTin out;
  TB_ASSIGN_OR_RETURN(out.level, dems.ClipLevel(dem, box, options.max_cells));
  TB_ASSIGN_OR_RETURN(const Grid grid, dems.ReadWindow(dem, box, out.level));
  out.geometry = grid.geometry;
  out.tin = GridTriangulation(grid);
  if (out.tin.triangles.empty())
    return Status::NotFound("the window of DEM '" + dem.name +
                            "' holds no complete square of valid cells");
  out.collapse.faces_in = out.collapse.faces_out = static_cast<int64_t>(out.tin.triangles.size());
  out.collapse.vertices_in = out.collapse.vertices_out =
      static_cast<int64_t>(out.tin.vertices.size());
  if (options.faces == 0) return out;
  CollapseOptions collapse;
  collapse.faces = options.faces;
  collapse.strategy = options.strategy;
  TB_ASSIGN_OR_RETURN(out.tin, CollapseToFaceBudget(out.tin, collapse, &out.collapse, &grid));
  return out;
}

}  // namespace tinbase
