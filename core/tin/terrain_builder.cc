#include "core/tin/terrain_builder.h"

#include <string>

#include "core/tin/greedy_builder.h"
#include "core/tin/grid_triangulation.h"
#include "core/tin/rtin_builder.h"
#include "core/tin/vip_builder.h"

namespace tinbase {
namespace {

template <typename MethodReport>
void Fill(const MethodReport& from, const Tin& tin, TerrainBuildReport* to) {
  to->max_error = from.max_error;
  to->rms_error = from.rms_error;
  to->points = from.points;
  to->triangles = static_cast<int64_t>(tin.triangles.size());
}

}  // namespace

const char* TerrainMethodName(TerrainMethod method) {
  switch (method) {
    case TerrainMethod::kGreedy:
      return "greedy";
    case TerrainMethod::kVip:
      return "vip";
    case TerrainMethod::kRtin:
      return "rtin";
    case TerrainMethod::kCollapse:
      return "collapse";
  }
  return "?";  // not reached: the switch covers every method
}

Result<TerrainMethod> ParseTerrainMethod(std::string_view name) {
  for (TerrainMethod m : kTerrainMethods)
    if (name == TerrainMethodName(m)) return m;
  return Status::InvalidArgument("unknown TIN method '" + std::string(name) +
                                 "' (expected greedy, vip, rtin or collapse)");
}

bool IsDelaunayMethod(TerrainMethod method) {
  return method == TerrainMethod::kGreedy || method == TerrainMethod::kVip;
}

Result<Tin> BuildTerrainTin(const Grid& dem, const TerrainBuildOptions& options,
                            TerrainBuildReport* report) {
  TerrainBuildReport local;
  TerrainBuildReport& out = report != nullptr ? *report : local;
  out = TerrainBuildReport{};
  out.method = options.method;
  out.delaunay = IsDelaunayMethod(options.method);
  switch (options.method) {
    case TerrainMethod::kGreedy: {
      GreedyReport greedy;
      TB_ASSIGN_OR_RETURN(
          Tin tin,
          BuildGreedyTin(dem, {.tolerance = options.tolerance, .max_points = options.max_points},
                         &greedy));
      Fill(greedy, tin, &out);
      out.within_tolerance = greedy.max_error <= options.tolerance;
      return tin;
    }
    case TerrainMethod::kVip: {
      VipReport vip;
      TB_ASSIGN_OR_RETURN(
          Tin tin,
          BuildVipTin(dem, {.threshold = options.threshold, .max_points = options.max_points},
                      &vip));
      Fill(vip, tin, &out);
      return tin;
    }
    case TerrainMethod::kRtin: {
      if (options.max_points != 0) {
        return Status::InvalidArgument(
            "RTIN: max_points must be 0, the binary triangle tree has no point budget (got " +
            std::to_string(options.max_points) + ")");
      }
      RtinReport rtin;
      TB_ASSIGN_OR_RETURN(Tin tin, BuildRtinTin(dem, {.tolerance = options.tolerance}, &rtin));
      Fill(rtin, tin, &out);
      out.within_tolerance = true;
      return tin;
    }
    case TerrainMethod::kCollapse: {
      const Tin full = GridTriangulation(dem);
      if (full.triangles.empty())
        return Status::InvalidArgument("the DEM has no 2 x 2 cells of data to triangulate");
      TB_ASSIGN_OR_RETURN(Tin tin,
                          CollapseToFaceBudget(full, options.collapse, &out.collapse, &dem));
      out.max_error = out.collapse.max_error;
      out.rms_error = out.collapse.rms_error;
      out.points = out.collapse.vertices_out;
      out.triangles = static_cast<int64_t>(tin.triangles.size());
      return tin;
    }
  }
  return Status::InvalidArgument("terrain TIN: unknown method");
}

}  // namespace tinbase
