#include "core/tin/terrain_builder.h"

#include "core/tin/greedy_builder.h"
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
  }
  return "greedy";
}

bool ParseTerrainMethod(const std::string& name, TerrainMethod* method) {
  for (TerrainMethod m : {TerrainMethod::kGreedy, TerrainMethod::kVip, TerrainMethod::kRtin}) {
    if (name == TerrainMethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

bool IsDelaunayMethod(TerrainMethod method) { return method != TerrainMethod::kRtin; }

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
  }
  return Status::InvalidArgument("terrain TIN: unknown method");
}

}  // namespace tinbase
