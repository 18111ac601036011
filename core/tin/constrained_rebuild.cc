#include "core/tin/constrained_rebuild.h"

#include <cmath>
#include <set>
#include <string>
#include <utility>

namespace tinbase {
namespace {

std::string Where(size_t line, size_t point) {
  return "line " + std::to_string(line) + ", point " + std::to_string(point);
}

Status ValidateLine(const ConstraintPolyline& line, size_t index) {
  const std::string name = "line " + std::to_string(index);
  if (line.points.size() < 2) {
    return Status::InvalidArgument(name + ": a constraint polyline needs at least 2 points, got " +
                                   std::to_string(line.points.size()));
  }
  std::set<std::pair<double, double>> distinct;
  for (size_t i = 0; i < line.points.size(); ++i) {
    const TinVertex& p = line.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Status::InvalidArgument(Where(index, i) + ": coordinates are not finite");
    }
    distinct.insert({p.x, p.y});
  }
  if (distinct.size() < 2) {
    return Status::InvalidArgument(name + ": all points are at the same x, y");
  }
  if (line.closed && distinct.size() < 3) {
    return Status::InvalidArgument(name + ": a closed ring needs at least 3 distinct points, got " +
                                   std::to_string(distinct.size()));
  }
  return Status::Ok();
}

Status Validate(const Tin& base, const std::vector<ConstraintPolyline>& lines,
                const ElevationFn& elevation) {
  if (!elevation) return Status::InvalidArgument("constraint insertion: no elevation function");
  for (size_t i = 0; i < base.constraints.size(); ++i) {
    const auto [a, b] = base.constraints[i];
    if (a >= base.vertices.size() || b >= base.vertices.size()) {
      return Status::InvalidArgument(
          "base constraint " + std::to_string(i) + " (" + std::to_string(a) + ", " +
          std::to_string(b) + "): no such vertex among " + std::to_string(base.vertices.size()));
    }
  }
  for (size_t i = 0; i < lines.size(); ++i) TB_RETURN_IF_ERROR(ValidateLine(lines[i], i));
  return Status::Ok();
}

void ConstrainIfDistinct(Cdt& cdt, uint32_t a, uint32_t b) {
  if (a != b) cdt.InsertConstraint(a, b);
}

}  // namespace

Result<Tin> InsertConstraints(const Tin& base, const std::vector<ConstraintPolyline>& lines,
                              const ElevationFn& elevation, ConstrainedRebuildMap* map) {
  TB_RETURN_IF_ERROR(Validate(base, lines, elevation));
  ConstrainedRebuildMap local;
  ConstrainedRebuildMap& where = map != nullptr ? *map : local;

  Cdt cdt;
  where.base_vertices = cdt.InsertVertices(base.vertices);
  for (const auto& [a, b] : base.constraints) {
    ConstrainIfDistinct(cdt, where.base_vertices[a], where.base_vertices[b]);
  }
  // All line points go in before any new constraint, so a constraint is split by every point
  // on it whatever the line order.
  where.line_vertices.clear();
  for (const ConstraintPolyline& line : lines) {
    std::vector<TinVertex> points = line.points;
    for (TinVertex& p : points) p.kind = VertexKind::kRing;
    where.line_vertices.push_back(cdt.InsertVertices(points));
  }
  for (size_t l = 0; l < lines.size(); ++l) {
    const std::vector<uint32_t>& v = where.line_vertices[l];
    for (size_t i = 0; i + 1 < v.size(); ++i) ConstrainIfDistinct(cdt, v[i], v[i + 1]);
    if (lines[l].closed) ConstrainIfDistinct(cdt, v.back(), v.front());
  }

  const size_t inserted = cdt.vertices().size();
  Tin tin = cdt.ToTin(elevation);
  for (size_t i = inserted; i < tin.vertices.size(); ++i) {
    const TinVertex& v = tin.vertices[i];
    if (!std::isfinite(v.z)) {
      return Status::InvalidArgument("constraint crossing at (" + std::to_string(v.x) + ", " +
                                     std::to_string(v.y) + "): the elevation there is not finite");
    }
  }
  tin.tags = base.tags;
  return tin;
}

}  // namespace tinbase
