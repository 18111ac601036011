#include "core/tin/vip_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/geometry/cdt.h"
#include "core/tin/cell_lattice.h"

namespace tinbase {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Status Validate(const Grid& dem, const VipOptions& options) {
  if (!(options.threshold >= 0) || !std::isfinite(options.threshold)) {
    return Status::InvalidArgument(
        "VIP TIN: threshold must be a finite, non-negative number of metres, got " +
        std::to_string(options.threshold));
  }
  if (options.max_points < 0 || (options.max_points > 0 && options.max_points < 4)) {
    return Status::InvalidArgument(
        "VIP TIN: max_points must be 0 (no limit) or at least 4 (the grid corners), got " +
        std::to_string(options.max_points));
  }
  return ValidateLatticeGrid(dem, "VIP TIN");
}

struct Candidate {
  double significance;
  Cell cell;
};

// Most significant first; ties by row, then column, so a budget cut is reproducible.
bool MoreSignificant(const Candidate& p, const Candidate& q) {
  if (p.significance != q.significance) return p.significance > q.significance;
  if (p.cell.row != q.cell.row) return p.cell.row < q.cell.row;
  return p.cell.col < q.cell.col;
}

std::vector<Candidate> SignificantCells(const Grid& dem, double threshold) {
  std::vector<Candidate> kept;
  for (int64_t r = 0; r < dem.geometry.height; ++r) {
    for (int64_t c = 0; c < dem.geometry.width; ++c) {
      const double s = VipSignificance(dem, c, r);
      if (s >= threshold)
        kept.push_back({s, Cell{static_cast<int32_t>(c), static_cast<int32_t>(r)}});
    }
  }
  return kept;
}

}  // namespace

double VipSignificance(const Grid& dem, int64_t col, int64_t row) {
  const int64_t w = dem.geometry.width, h = dem.geometry.height;
  const bool left_or_right = col == 0 || col == w - 1;
  const bool top_or_bottom = row == 0 || row == h - 1;
  if (left_or_right && top_or_bottom) return kInfinity;  // a corner
  if (!dem.IsValid(col, row)) return std::numeric_limits<double>::quiet_NaN();
  // Offsets to one end of each line; the other end is opposite. On the border only the line
  // along it exists.
  static constexpr int kAll[4][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}};
  static constexpr int kAlongColumn[1][2] = {{0, 1}};
  static constexpr int kAlongRow[1][2] = {{1, 0}};
  const int(*lines)[2] = kAll;
  int line_count = 4;
  if (left_or_right) {
    lines = kAlongColumn;
    line_count = 1;
  } else if (top_or_bottom) {
    lines = kAlongRow;
    line_count = 1;
  }
  const double z = dem.At(col, row);
  double sum = 0;
  int complete = 0;
  for (int i = 0; i < line_count; ++i) {
    const int dc = lines[i][0], dr = lines[i][1];
    if (!dem.IsValid(col + dc, row + dr) || !dem.IsValid(col - dc, row - dr)) continue;
    sum += std::fabs(z - 0.5 * (double{dem.At(col + dc, row + dr)} + dem.At(col - dc, row - dr)));
    ++complete;
  }
  return complete == 0 ? kInfinity : sum / complete;
}

Result<Tin> BuildVipTin(const Grid& dem, const VipOptions& options, VipReport* report) {
  TB_RETURN_IF_ERROR(Validate(dem, options));
  std::vector<Candidate> kept = SignificantCells(dem, options.threshold);
  const int64_t significant = static_cast<int64_t>(kept.size());
  if (options.max_points > 0 && significant > options.max_points) {
    // Corners are infinitely significant, so they survive any budget of at least 4.
    std::nth_element(kept.begin(), kept.begin() + (options.max_points - 1), kept.end(),
                     MoreSignificant);
    kept.resize(static_cast<size_t>(options.max_points));
    std::sort(kept.begin(), kept.end(), [](const Candidate& p, const Candidate& q) {
      return p.cell.row != q.cell.row ? p.cell.row < q.cell.row : p.cell.col < q.cell.col;
    });
  }

  NodataElevation elevation(dem);
  std::vector<TinVertex> points;
  points.reserve(kept.size());
  for (const Candidate& k : kept) {
    points.push_back(TinVertex{dem.geometry.CellCenterX(k.cell.col),
                               dem.geometry.CellCenterY(k.cell.row),
                               elevation.At(k.cell.col, k.cell.row), VertexKind::kDem});
  }
  Cdt cdt;
  cdt.InsertVertices(points);  // distinct cells, so indices follow `points`
  Tin tin = cdt.ToTin();
  HideNodataTriangles(dem, tin);
  if (report != nullptr) {
    const CellFit fit = MeasureCellFit(dem, tin);
    report->max_error = fit.max_error;
    report->rms_error = fit.rms_error;
    report->points = static_cast<int64_t>(tin.vertices.size());
    report->significant_cells = significant;
  }
  return tin;
}

}  // namespace tinbase
