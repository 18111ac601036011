#include "core/export/vdb_writer.h"

#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace tinbase {

namespace {

constexpr double kNoHeight = std::numeric_limits<double>::quiet_NaN();

struct PlanBox {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x, min_z = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x, max_z = max_x;
  bool empty() const { return !(min_x <= max_x && min_y <= max_y); }
};

// The box of the vertices of visible triangles.
PlanBox VisibleBox(const Tin& tin) {
  PlanBox box;
  for (const TinTriangle& t : tin.triangles) {
    if (!t.visible) continue;
    for (uint32_t v : t.v) {
      const TinVertex& p = tin.vertices[v];
      box.min_x = std::min(box.min_x, p.x), box.max_x = std::max(box.max_x, p.x);
      box.min_y = std::min(box.min_y, p.y), box.max_y = std::max(box.max_y, p.y);
      box.min_z = std::min(box.min_z, p.z), box.max_z = std::max(box.max_z, p.z);
    }
  }
  return box;
}

// Voxel columns over a plan-view box: column (i, j) is centred at (ox + i*h, oy + j*h).
struct Columns {
  double ox = 0, oy = 0, h = 1;
  int64_t nx = 0, ny = 0;
};

Result<double> VoxelSize(const PlanBox& box, const VdbOptions& options) {
  if (options.voxel != 0) {
    if (!(options.voxel > 0) || !std::isfinite(options.voxel))
      return Status::InvalidArgument("voxel size " + std::to_string(options.voxel) +
                                     " is not a positive number");
    return options.voxel;
  }
  const double extent = std::max(box.max_x - box.min_x, box.max_y - box.min_y);
  if (!(extent > 0)) return Status::InvalidArgument("the surface has no extent to voxelise");
  return extent / 512;
}

Result<Columns> MakeColumns(const PlanBox& box, double h, double layers, int64_t max_voxels) {
  Columns c;
  c.h = h;
  // Columns tile [base, base + n h) from a multiple of h, centred half a voxel in, so a surface
  // whose edges lie on multiples of h is covered exactly (no half columns hanging over).
  const double base_x = std::floor(box.min_x / h) * h, base_y = std::floor(box.min_y / h) * h;
  c.ox = base_x + h / 2;
  c.oy = base_y + h / 2;
  const double nx = std::max(1.0, std::ceil((box.max_x - base_x) / h));
  const double ny = std::max(1.0, std::ceil((box.max_y - base_y) / h));
  const double voxels = nx * ny * std::max(layers, 1.0);
  if (!(voxels <= static_cast<double>(max_voxels)))
    return Status::InvalidArgument("voxel size " + std::to_string(h) + " gives about " +
                                   std::to_string(static_cast<int64_t>(voxels)) +
                                   " voxels, more than " + std::to_string(max_voxels) +
                                   ": give a larger --voxel");
  c.nx = static_cast<int64_t>(nx);
  c.ny = static_cast<int64_t>(ny);
  return c;
}

// The height of `tin`'s visible triangles at each column centre (NaN where none covers it):
// each triangle interpolates linearly at the centres inside its plan-view box.
std::vector<double> Heights(const Tin& tin, const Columns& c) {
  std::vector<double> z(static_cast<size_t>(c.nx * c.ny), kNoHeight);
  for (const TinTriangle& t : tin.triangles) {
    if (!t.visible) continue;
    const TinVertex& a = tin.vertices[t.v[0]];
    const TinVertex& b = tin.vertices[t.v[1]];
    const TinVertex& d = tin.vertices[t.v[2]];
    const double area = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    if (!(area > 0)) continue;
    const auto lo = [&](double v, double o) {
      return std::max<int64_t>(0, std::ceil((v - o) / c.h));
    };
    const auto hi = [&](double v, double o, int64_t n) {
      return std::min<int64_t>(n - 1, std::floor((v - o) / c.h));
    };
    const int64_t i0 = lo(std::min({a.x, b.x, d.x}), c.ox),
                  i1 = hi(std::max({a.x, b.x, d.x}), c.ox, c.nx);
    const int64_t j0 = lo(std::min({a.y, b.y, d.y}), c.oy),
                  j1 = hi(std::max({a.y, b.y, d.y}), c.oy, c.ny);
    for (int64_t j = j0; j <= j1; ++j) {
      const double py = c.oy + static_cast<double>(j) * c.h;
      for (int64_t i = i0; i <= i1; ++i) {
        const double px = c.ox + static_cast<double>(i) * c.h;
        // Barycentric weights; a centre on a shared edge takes either triangle's (equal) value.
        const double wa = ((b.x - px) * (d.y - py) - (b.y - py) * (d.x - px)) / area;
        const double wb = ((d.x - px) * (a.y - py) - (d.y - py) * (a.x - px)) / area;
        const double wd = 1 - wa - wb;
        constexpr double kEdge = -1e-12;
        if (wa < kEdge || wb < kEdge || wd < kEdge) continue;
        z[static_cast<size_t>(j * c.nx + i)] = wa * a.z + wb * b.z + wd * d.z;
      }
    }
  }
  return z;
}

// The linear transform of voxel size h whose index origin sits at (ox, oy, 0) in world space.
openvdb::math::Transform::Ptr WorldTransform(const Columns& c) {
  auto xform = openvdb::math::Transform::createLinearTransform(c.h);
  xform->postTranslate(openvdb::Vec3d(c.ox, c.oy, 0));
  return xform;
}

void SetMeta(openvdb::FloatGrid& grid, const std::string& name, const VdbOptions& options) {
  grid.setName(options.name.empty() ? name : options.name);
  if (!options.crs_wkt.empty())
    grid.insertMeta("tinbase:crs", openvdb::StringMetadata(options.crs_wkt));
}

Status WriteGrid(const openvdb::FloatGrid::Ptr& grid, const std::string& path) {
  try {
    openvdb::io::File file(path);
    file.write(openvdb::GridPtrVec{grid});
    file.close();
  } catch (const std::exception& e) {
    return Status::IOError("cannot write " + path + ": " + e.what());
  }
  return Status::Ok();
}

// Active voxels and enclosed volume of a grid (see MeasureVdb).
VdbReport Measure(const openvdb::FloatGrid& grid) {
  VdbReport report;
  report.voxel = grid.voxelSize()[0];
  report.active_voxels = static_cast<int64_t>(grid.activeVoxelCount());
  if (grid.getGridClass() == openvdb::GRID_LEVEL_SET) {
    report.grid_class = "level set";
    report.volume = openvdb::tools::levelSetVolume(grid, /*useWorldSpace=*/true);
  } else {
    report.grid_class = "fog volume";
    double sum = 0;
    for (auto it = grid.cbeginValueOn(); it; ++it)
      sum += static_cast<double>(*it) * static_cast<double>(it.getVoxelCount());
    report.volume = sum * report.voxel * report.voxel * report.voxel;
  }
  return report;
}

// The surface's visible triangles, a floor under them and walls along their boundary, as one
// closed mesh in coordinates relative to the columns' origin.
void ClosedMesh(const Tin& tin, const Columns& c, double floor, std::vector<openvdb::Vec3s>& points,
                std::vector<openvdb::Vec3I>& triangles, std::vector<openvdb::Vec4I>& quads) {
  const auto n = static_cast<uint32_t>(tin.vertices.size());
  points.reserve(2 * n);
  for (const TinVertex& v : tin.vertices)
    points.emplace_back(static_cast<float>(v.x - c.ox), static_cast<float>(v.y - c.oy),
                        static_cast<float>(v.z));
  for (uint32_t i = 0; i < n; ++i)
    points.emplace_back(points[i].x(), points[i].y(), static_cast<float>(floor));
  for (const TinTriangle& t : tin.triangles) {
    if (!t.visible) continue;
    triangles.emplace_back(t.v[0], t.v[1], t.v[2]);
    triangles.emplace_back(t.v[0] + n, t.v[2] + n, t.v[1] + n);
    for (int k = 0; k < 3; ++k) {
      const int32_t across = t.n[k];
      if (across != kNoNeighbour && tin.triangles[across].visible) continue;
      const uint32_t p = t.v[(k + 1) % 3], q = t.v[(k + 2) % 3];
      quads.emplace_back(q, p, p + n, q + n);  // outward: to the right of p -> q
    }
  }
}

}  // namespace

Result<VdbReport> WriteSurfaceLevelSet(const Tin& surface, const VdbOptions& options,
                                       const std::string& path) {
  openvdb::initialize();
  const PlanBox box = VisibleBox(surface);
  if (box.empty()) return Status::InvalidArgument("the surface has no visible triangle");
  TB_ASSIGN_OR_RETURN(const double h, VoxelSize(box, options));
  const double floor = options.floor.value_or(box.min_z - 3 * h);
  if (!(floor < box.min_z))
    return Status::InvalidArgument("the floor (" + std::to_string(floor) +
                                   ") must lie below the lowest visible vertex (" +
                                   std::to_string(box.min_z) + ")");
  TB_ASSIGN_OR_RETURN(const Columns c,
                      MakeColumns(box, h, (box.max_z - floor) / h + 6, options.max_voxels));
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  ClosedMesh(surface, c, floor, points, triangles, quads);
  const auto local = openvdb::math::Transform::createLinearTransform(h);
  openvdb::FloatGrid::Ptr grid;
  try {
    grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*local, points, triangles, quads);
  } catch (const std::exception& e) {
    return Status::InvalidArgument(std::string("OpenVDB could not voxelise the surface: ") +
                                   e.what());
  }
  grid->setTransform(WorldTransform(c));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  SetMeta(*grid, "surface", options);
  grid->insertMeta("tinbase:floor", openvdb::DoubleMetadata(floor));
  TB_RETURN_IF_ERROR(WriteGrid(grid, path));
  return Measure(*grid);
}

Result<VdbReport> WriteThicknessFogVolume(const Tin& top, const Tin& base,
                                          const VdbOptions& options, const std::string& path) {
  openvdb::initialize();
  const PlanBox top_box = VisibleBox(top), base_box = VisibleBox(base);
  if (top_box.empty() || base_box.empty())
    return Status::InvalidArgument(std::string(top_box.empty() ? "the top" : "the base") +
                                   " surface has no visible triangle");
  PlanBox box;  // where both can have a height
  box.min_x = std::max(top_box.min_x, base_box.min_x),
  box.max_x = std::min(top_box.max_x, base_box.max_x);
  box.min_y = std::max(top_box.min_y, base_box.min_y),
  box.max_y = std::min(top_box.max_y, base_box.max_y);
  box.min_z = std::min(top_box.min_z, base_box.min_z),
  box.max_z = std::max(top_box.max_z, base_box.max_z);
  if (box.empty()) return Status::InvalidArgument("the two surfaces do not overlap in plan view");
  TB_ASSIGN_OR_RETURN(const double h, VoxelSize(box, options));
  TB_ASSIGN_OR_RETURN(const Columns c,
                      MakeColumns(box, h, (box.max_z - box.min_z) / h + 2, options.max_voxels));
  const std::vector<double> zt = Heights(top, c), zb = Heights(base, c);
  auto grid = openvdb::FloatGrid::create(0.0f);
  auto acc = grid->getAccessor();
  bool overlap = false;
  for (int64_t j = 0; j < c.ny; ++j) {
    for (int64_t i = 0; i < c.nx; ++i) {
      const size_t at = static_cast<size_t>(j * c.nx + i);
      if (std::isnan(zt[at]) || std::isnan(zb[at])) continue;
      overlap = true;
      const double lo = zb[at], hi = zt[at];
      if (!(hi > lo)) continue;
      // Voxel k spans [(k - 1/2) h, (k + 1/2) h]; its value is the part of that inside [lo, hi],
      // so a column's values sum to (hi - lo) / h.
      const auto k0 = static_cast<int32_t>(std::floor(lo / h + 0.5));
      const auto k1 = static_cast<int32_t>(std::floor(hi / h + 0.5));
      for (int32_t k = k0; k <= k1; ++k) {
        const double part = std::min(hi, (k + 0.5) * h) - std::max(lo, (k - 0.5) * h);
        if (part > 0)
          acc.setValue(openvdb::Coord(static_cast<int32_t>(i), static_cast<int32_t>(j), k),
                       static_cast<float>(std::min(part / h, 1.0)));
      }
    }
  }
  if (!overlap) return Status::InvalidArgument("the two surfaces do not overlap in plan view");
  grid->setTransform(WorldTransform(c));
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  SetMeta(*grid, "thickness", options);
  TB_RETURN_IF_ERROR(WriteGrid(grid, path));
  return Measure(*grid);
}

Result<VdbReport> MeasureVdb(const std::string& path) {
  openvdb::initialize();
  openvdb::GridPtrVecPtr grids;
  try {
    openvdb::io::File file(path);
    file.open();
    grids = file.getGrids();
    file.close();
  } catch (const std::exception& e) {
    return Status::IOError("cannot read " + path + ": " + e.what());
  }
  if (!grids || grids->empty()) return Status::InvalidArgument(path + " holds no grid");
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(grids->front());
  if (!grid) return Status::InvalidArgument(path + ": the first grid is not a float grid");
  const auto cls = grid->getGridClass();
  if (cls != openvdb::GRID_LEVEL_SET && cls != openvdb::GRID_FOG_VOLUME)
    return Status::InvalidArgument(path +
                                   ": the first grid is neither a level set nor a fog volume");
  return Measure(*grid);
}

}  // namespace tinbase
