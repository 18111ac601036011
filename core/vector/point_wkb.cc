#include "core/vector/point_wkb.h"

#include <ogr_geometry.h>

#include <memory>

namespace tinbase {

std::vector<uint8_t> PointsToWkb(const std::vector<TinVertex>& points) {
  OGRMultiPoint multi;
  multi.set3D(TRUE);
  for (const TinVertex& p : points) {
    OGRPoint point(p.x, p.y, p.z);
    multi.addGeometry(&point);
  }
  std::vector<uint8_t> wkb(multi.WkbSize());
  multi.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
  return wkb;
}

Result<std::vector<TinVertex>> PointsFromWkb(const std::vector<uint8_t>& wkb) {
  OGRGeometry* raw = nullptr;
  if (OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &raw, wkb.size()) != OGRERR_NONE ||
      raw == nullptr)
    return Status::Corruption("feature geometry is not valid WKB");
  std::unique_ptr<OGRGeometry> geometry(OGRGeometryFactory::forceToMultiPoint(raw));
  if (geometry == nullptr || wkbFlatten(geometry->getGeometryType()) != wkbMultiPoint)
    return Status::Corruption("feature geometry is not a point geometry");
  if (!geometry->Is3D()) return Status::Corruption("feature points have no z");
  std::vector<TinVertex> out;
  for (const OGRPoint* p : *geometry->toMultiPoint())
    out.push_back({p->getX(), p->getY(), p->getZ(), VertexKind::kUser});
  return out;
}

}  // namespace tinbase
