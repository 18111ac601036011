#include "core/pointcloud/plan_density.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/PointIndexGrid.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <cmath>

namespace tinbase {
namespace {

// OpenVDB's PointArray interface over the plan positions. Coordinates are taken relative to the
// cloud's lower corner: projected coordinates in the millions would otherwise cost the voxel
// lookups precision, and index space is 32-bit.
class PlanPositions {
 public:
  using PosType = openvdb::Vec3R;

  explicit PlanPositions(const std::vector<TinVertex>& points) : points_(points) {
    for (const TinVertex& p : points) {
      origin_x_ = std::min(origin_x_, p.x);
      origin_y_ = std::min(origin_y_, p.y);
    }
  }
  size_t size() const { return points_.size(); }
  void getPos(size_t n, PosType& xyz) const {
    xyz = PosType(points_[n].x - origin_x_, points_[n].y - origin_y_, 0.0);
  }

 private:
  const std::vector<TinVertex>& points_;
  double origin_x_ = INFINITY, origin_y_ = INFINITY;
};

}  // namespace

std::vector<uint32_t> CountPointsWithinPlanRadius(const std::vector<TinVertex>& points,
                                                  double radius) {
  assert(radius > 0 && std::isfinite(radius));
  std::vector<uint32_t> counts(points.size(), 0);
  if (points.empty()) return counts;
  openvdb::initialize();  // idempotent; registers the grid types
  const PlanPositions positions(points);
  const auto transform = openvdb::math::Transform::createLinearTransform(radius);
  const auto grid =
      openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(positions, *transform);
  const double radius_squared = radius * radius;

  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size()), [&](const auto& range) {
    openvdb::tools::PointIndexGrid::ConstAccessor accessor = grid->getConstAccessor();
    openvdb::tools::PointIndexIterator<openvdb::tools::PointIndexTree> candidates;
    for (size_t i = range.begin(); i != range.end(); ++i) {
      PlanPositions::PosType centre;
      positions.getPos(i, centre);
      // Voxel-level candidates only; the distance test is ours, in world units, so the rule
      // (boundary included) does not depend on OpenVDB's index-space rounding.
      candidates.worldSpaceSearchAndUpdate(centre, radius, accessor, positions, *transform,
                                           /*subvoxelAccuracy=*/false);
      uint32_t count = 0;
      for (; candidates; ++candidates) {
        const TinVertex& q = points[*candidates];
        const double dx = q.x - points[i].x, dy = q.y - points[i].y;
        if (dx * dx + dy * dy <= radius_squared) ++count;
      }
      counts[i] = count;
    }
  });
  return counts;
}

}  // namespace tinbase
