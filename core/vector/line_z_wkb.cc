#include "core/vector/line_z_wkb.h"

#include <ogr_geometry.h>

#include <memory>

namespace tinbase {

std::vector<uint8_t> LinesZToWkb(const std::vector<std::vector<Point2>>& lines,
                                 const std::vector<std::vector<double>>& z) {
  OGRMultiLineString multi;
  for (size_t k = 0; k < lines.size(); ++k) {
    OGRLineString part;
    for (size_t i = 0; i < lines[k].size(); ++i)
      part.addPoint(lines[k][i].x, lines[k][i].y, z[k][i]);
    multi.addGeometry(&part);
  }
  multi.set3D(TRUE);
  std::vector<uint8_t> wkb(multi.WkbSize());
  multi.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
  return wkb;
}

Status LinesZFromWkb(const std::vector<uint8_t>& wkb, std::vector<std::vector<Point2>>* lines,
                     std::vector<std::vector<double>>* z) {
  OGRGeometry* raw = nullptr;
  if (OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &raw, wkb.size()) != OGRERR_NONE ||
      raw == nullptr)
    return Status::Corruption("feature geometry is not valid WKB");
  std::unique_ptr<OGRGeometry> multi(OGRGeometryFactory::forceToMultiLineString(raw));
  if (multi == nullptr || wkbFlatten(multi->getGeometryType()) != wkbMultiLineString ||
      !multi->Is3D())
    return Status::Corruption("feature geometry is not a line with z");
  lines->clear();
  z->clear();
  for (const OGRLineString* part : *multi->toMultiLineString()) {
    std::vector<Point2> line;
    std::vector<double> heights;
    for (int i = 0; i < part->getNumPoints(); ++i) {
      line.push_back({part->getX(i), part->getY(i)});
      heights.push_back(part->getZ(i));
    }
    lines->push_back(std::move(line));
    z->push_back(std::move(heights));
  }
  return Status::Ok();
}

}  // namespace tinbase
