#include "db/edit/line_z.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace tinbase {

Result<std::vector<EditPolyline>> OwnZPolylines(const EditorFeature& f) {
  std::vector<EditPolyline> out;
  for (size_t k = 0; k < f.lines.size(); ++k) {
    const std::string where = f.label + ", line " + std::to_string(k);
    if (k >= f.line_z.size() || f.line_z[k].size() != f.lines[k].size())
      return Status::InvalidArgument(where + ": no z (z from the feature needs LineString Z)");
    EditPolyline line;
    for (size_t i = 0; i < f.lines[k].size(); ++i) {
      const double z = f.line_z[k][i];
      if (!std::isfinite(z))
        return Status::InvalidArgument(where + ", vertex " + std::to_string(i) + ": z is " +
                                       (std::isnan(z) ? "not a number" : "not finite"));
      line.points.push_back({f.lines[k][i].x, f.lines[k][i].y, z, VertexKind::kRing});
    }
    out.push_back(std::move(line));
  }
  return out;
}

double LineNearDistance(const DemInfo& dem) {
  return kSnapCells * std::min(dem.geometry.cell_x, std::fabs(dem.geometry.cell_y));
}

void ApplyLineZ(const DemInfo& dem, LocalEdit& edit) {
  const LineElevation lines = LineElevationOf(edit.features, LineNearDistance(dem));
  if (lines.empty()) return;
  for (EditPolyline& line : edit.add)
    for (TinVertex& p : line.points)
      if (auto z = lines.ZAt({p.x, p.y})) p.z = *z;
}

}  // namespace tinbase
