// OpenVDB export: a surface as a level set, or the volume between two surfaces (a formation's
// thickness) as a fog volume, in a .vdb file (openvdb::tools). OpenVDB's types stay inside
// vdb_writer.cc; callers see plain values.
//
// Both grids are sampled on voxel columns: voxel (i, j, k) is centred at (origin_x + i*h,
// origin_y + j*h, k*h), h the voxel size, origin half a voxel in from the surface's plan-view
// corner snapped down to a multiple of h. The grid's transform carries that origin, so world
// coordinates are the store's while OpenVDB's single-precision mesh input only ever sees
// coordinates near zero. Only visible triangles count: hidden ones are not part of the surface.
//
// - Level set (GRID_LEVEL_SET, "surface"): the narrow-band signed distance to the solid between
//   the surface and a flat floor below it (the surface's triangles, the floor and vertical walls
//   along the boundary form a closed mesh for tools::meshToLevelSet); negative inside.
// - Fog volume (GRID_FOG_VOLUME, "thickness"): in each column where both surfaces have a visible
//   triangle, each voxel holds the fraction of its height that lies between base and top (1
//   inside, a fraction at the ends, nothing where top is below base), so the sum of the values
//   times h^3 is the midpoint-rule volume of max(top - base, 0).
// Thread-safety: pure functions (OpenVDB is initialised once per process).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/tin/tin.h"

namespace tinbase {

struct VdbOptions {
  double voxel = 0;             // voxel size in the CRS's units; 0: the longer side / 512
  std::optional<double> floor;  // level set: the floor's z; default 3 voxels below the surface
  std::string name;             // the grid's name; default "surface" / "thickness"
  std::string crs_wkt;          // kept as the grid's "tinbase:crs" metadata when given
  int64_t max_voxels = int64_t{1} << 30;  // refuse grids larger than this (columns x layers)
};

struct VdbReport {
  std::string grid_class;  // "level set" or "fog volume"
  double voxel = 0;
  int64_t active_voxels = 0;
  double volume = 0;  // the volume the grid encloses, in CRS units cubed
};

// Writes `surface` as a level set to `path` (a temporary file the caller commits).
// InvalidArgument when no triangle is visible, the voxel size is not positive and finite, the
// floor is not below the lowest visible vertex, or the grid would exceed max_voxels (naming the
// count and suggesting a larger voxel); IOError naming the path when it cannot be written.
Result<VdbReport> WriteSurfaceLevelSet(const Tin& surface, const VdbOptions& options,
                                       const std::string& path);

// Writes the volume between `base` and `top` as a fog volume to `path`. InvalidArgument as above,
// and when the two surfaces' visible triangles do not overlap in plan view.
Result<VdbReport> WriteThicknessFogVolume(const Tin& top, const Tin& base,
                                          const VdbOptions& options, const std::string& path);

// The first grid of the .vdb file at `path`, measured: its class, voxel size, active voxels and
// the volume it encloses (tools::levelSetVolume for a level set, the sum of values times the
// voxel volume for a fog volume). IOError when the file cannot be read; InvalidArgument when its
// first grid is not a float grid of one of those classes.
Result<VdbReport> MeasureVdb(const std::string& path);

}  // namespace tinbase
