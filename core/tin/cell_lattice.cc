#include "core/tin/cell_lattice.h"

#include <cassert>

namespace tinbase {

Status ValidateLatticeGrid(const Grid& dem, const std::string& builder) {
  const GridGeometry& g = dem.geometry;
  const std::string size = std::to_string(g.width) + " x " + std::to_string(g.height);
  if (g.width <= 0 || g.height <= 0) {
    return Status::InvalidArgument(builder + ": the DEM is empty (" + size + " cells)");
  }
  if (g.width < 2 || g.height < 2) {
    return Status::InvalidArgument(builder + ": the DEM needs at least 2 x 2 cells, got " + size);
  }
  if (g.width > INT32_MAX || g.height > INT32_MAX ||
      dem.cells.size() != static_cast<size_t>(g.CellCount())) {
    return Status::InvalidArgument(builder + ": the DEM's cells do not match its " + size +
                                   " geometry");
  }
  if (std::none_of(dem.cells.begin(), dem.cells.end(), [](float v) { return !std::isnan(v); })) {
    return Status::InvalidArgument(builder + ": the DEM has no valid cell (all nodata)");
  }
  return Status::Ok();
}

bool PlaneThrough(const std::array<Cell, 3>& p, const std::array<double, 3>& z, CellPlane* plane) {
  const double dc1 = p[1].col - p[0].col, dr1 = p[1].row - p[0].row;
  const double dc2 = p[2].col - p[0].col, dr2 = p[2].row - p[0].row;
  const double det = dc1 * dr2 - dc2 * dr1;
  if (det == 0) return false;
  const double dz1 = z[1] - z[0], dz2 = z[2] - z[0];
  plane->a = (dz1 * dr2 - dz2 * dr1) / det;
  plane->b = (dc1 * dz2 - dc2 * dz1) / det;
  plane->z0 = z[0];
  plane->c0 = p[0].col;
  plane->r0 = p[0].row;
  return true;
}

void NodataElevation::BuildValidPrefix() {
  const int64_t w = dem_.geometry.width, h = dem_.geometry.height;
  valid_prefix_.assign(static_cast<size_t>((w + 1) * (h + 1)), 0);
  for (int64_t r = 0; r < h; ++r) {
    for (int64_t c = 0; c < w; ++c) {
      valid_prefix_[static_cast<size_t>((r + 1) * (w + 1) + c + 1)] =
          valid_prefix_[static_cast<size_t>(r * (w + 1) + c + 1)] +
          valid_prefix_[static_cast<size_t>((r + 1) * (w + 1) + c)] -
          valid_prefix_[static_cast<size_t>(r * (w + 1) + c)] + (dem_.IsValid(c, r) ? 1 : 0);
    }
  }
}

int64_t NodataElevation::ValidInWindow(int64_t col, int64_t row, int64_t radius) const {
  const int64_t w = dem_.geometry.width, h = dem_.geometry.height;
  const int64_t c0 = std::max<int64_t>(0, col - radius), c1 = std::min(w, col + radius + 1);
  const int64_t r0 = std::max<int64_t>(0, row - radius), r1 = std::min(h, row + radius + 1);
  const auto at = [&](int64_t c, int64_t r) {
    return valid_prefix_[static_cast<size_t>(r * (w + 1) + c)];
  };
  return at(c1, r1) - at(c0, r1) - at(c1, r0) + at(c0, r0);
}

double NodataElevation::At(int64_t col, int64_t row) {
  if (dem_.IsValid(col, row)) return dem_.At(col, row);
  const int64_t key = row * dem_.geometry.width + col;
  if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
  if (valid_prefix_.empty()) BuildValidPrefix();
  // Smallest radius whose window holds a valid cell; the count grows with the radius.
  int64_t lo = 1, hi = std::max(dem_.geometry.width, dem_.geometry.height);
  assert(ValidInWindow(col, row, hi) > 0);
  while (lo < hi) {
    const int64_t mid = lo + (hi - lo) / 2;
    if (ValidInWindow(col, row, mid) > 0) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  // Summed here rather than from a table of sums, whose differences of large totals would
  // lose the digits of a small window's mean.
  double sum = 0;
  int64_t count = 0;
  for (int64_t r = std::max<int64_t>(0, row - lo);
       r <= std::min(dem_.geometry.height - 1, row + lo); ++r) {
    for (int64_t c = std::max<int64_t>(0, col - lo);
         c <= std::min(dem_.geometry.width - 1, col + lo); ++c) {
      if (dem_.IsValid(c, r)) {
        sum += dem_.At(c, r);
        ++count;
      }
    }
  }
  const double mean = sum / static_cast<double>(count);
  cache_.emplace(key, mean);
  return mean;
}

Cell CellOf(const GridGeometry& g, const TinVertex& v) {
  return Cell{static_cast<int32_t>(std::llround(g.ColumnAt(v.x))),
              static_cast<int32_t>(std::llround(g.RowAt(v.y)))};
}

namespace {

std::array<Cell, 3> TriangleCells(const GridGeometry& g, const Tin& tin, const TinTriangle& t) {
  return {CellOf(g, tin.vertices[t.v[0]]), CellOf(g, tin.vertices[t.v[1]]),
          CellOf(g, tin.vertices[t.v[2]])};
}

}  // namespace

void HideNodataTriangles(const Grid& dem, Tin& tin) {
  const GridGeometry& g = dem.geometry;
  for (TinTriangle& t : tin.triangles) {
    const std::array<Cell, 3> p = TriangleCells(g, tin, t);
    const Cell centroid = CentroidCell(p[0], p[1], p[2]);
    t.visible = dem.IsValid(std::clamp<int64_t>(centroid.col, 0, g.width - 1),
                            std::clamp<int64_t>(centroid.row, 0, g.height - 1));
  }
}

CellFit MeasureCellFit(const Grid& dem, const Tin& tin) {
  const GridGeometry& g = dem.geometry;
  std::vector<uint8_t> seen(dem.cells.size(), 0);
  double max_error = 0, sum_sq = 0;
  int64_t count = 0;
  for (const TinTriangle& t : tin.triangles) {
    const std::array<Cell, 3> p = TriangleCells(g, tin, t);
    CellPlane plane;
    if (!PlaneThrough(p, {tin.vertices[t.v[0]].z, tin.vertices[t.v[1]].z, tin.vertices[t.v[2]].z},
                      &plane)) {
      continue;
    }
    RasteriseTriangle(p, g.width, g.height, [&](int32_t r, int64_t first, int64_t last) {
      for (int64_t c = first; c <= last; ++c) {
        const size_t at = static_cast<size_t>(r * g.width + c);
        if (seen[at] || std::isnan(dem.cells[at])) continue;
        seen[at] = 1;
        const double error = std::fabs(plane.At(static_cast<double>(c), r) - dem.cells[at]);
        max_error = std::max(max_error, error);
        sum_sq += error * error;
        ++count;
      }
    });
  }
  CellFit fit;
  fit.max_error = max_error;
  fit.rms_error = count > 0 ? std::sqrt(sum_sq / static_cast<double>(count)) : 0;
  fit.cells = count;
  return fit;
}

}  // namespace tinbase
