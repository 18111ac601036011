// PlanDensity: how crowded a point cloud is around each of its points, counted in plan.
//
// Paper 003 states its density criterion as a count per area ("no more than 10 Voronoi polygons
// per 150 square feet"). CountPointsWithinPlanRadius answers exactly that question for every
// point: the number of points, itself included, whose x, y lie within `radius` of its own. The
// points are bucketed with OpenVDB's PointIndexGrid (voxels one radius wide, z ignored), so each
// query reads only the few voxels around its point.
//
// Stateless; thread-safe. Uses TBB's worker threads (OpenVDB's own) for the queries.
#pragma once

#include <cstdint>
#include <vector>

#include "core/tin/tin.h"

namespace tinbase {

// REQUIRES: radius > 0 and finite; every x and y finite.
// Returns, for each point i, #{j : (x_j - x_i)² + (y_j - y_i)² <= radius²}, which is >= 1.
std::vector<uint32_t> CountPointsWithinPlanRadius(const std::vector<TinVertex>& points,
                                                  double radius);

}  // namespace tinbase
