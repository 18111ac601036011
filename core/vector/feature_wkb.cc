#include "core/vector/feature_wkb.h"

#include <ogr_geometry.h>

#include <cmath>
#include <memory>

namespace tinbase {

namespace {

OGRLinearRing ToOgrRing(const Ring& ring) {
  OGRLinearRing out;
  for (const Point2& p : ring) out.addPoint(p.x, p.y);
  if (!ring.empty()) out.addPoint(ring.front().x, ring.front().y);  // OGC rings are closed
  return out;
}

// A polygon's ring (null when the WKB gives the polygon none), open. Corruption unless it has at
// least three finite vertices: what tinbase writes always does (the decoder reads a column that
// may be damaged; found by fuzz/feature_wkb_fuzz.cc).
Result<Ring> FromOgrRing(const OGRLinearRing* ring) {
  if (ring == nullptr) return Status::Corruption("feature geometry has a polygon without rings");
  Ring out;
  // Drop the closing vertex: tinbase keeps rings open.
  for (int i = 0; i + 1 < ring->getNumPoints(); ++i) {
    const Point2 p{ring->getX(i), ring->getY(i)};
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      return Status::Corruption("feature geometry has a vertex that is not finite");
    out.push_back(p);
  }
  if (out.size() < 3)
    return Status::Corruption("feature geometry has a ring of fewer than 3 vertices");
  return out;
}

std::vector<uint8_t> ToWkb(const OGRGeometry& geometry) {
  std::vector<uint8_t> wkb(geometry.WkbSize());
  geometry.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
  return wkb;
}

Result<std::unique_ptr<OGRGeometry>> FromWkb(const std::vector<uint8_t>& wkb) {
  OGRGeometry* raw = nullptr;
  if (OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &raw, wkb.size()) != OGRERR_NONE ||
      raw == nullptr)
    return Status::Corruption("feature geometry is not valid WKB");
  return std::unique_ptr<OGRGeometry>(raw);
}

}  // namespace

std::vector<uint8_t> PolygonsToWkb(const std::vector<Polygon>& polygons) {
  OGRMultiPolygon multi;
  for (const Polygon& polygon : polygons) {
    OGRPolygon part;
    OGRLinearRing shell = ToOgrRing(polygon.shell);
    part.addRing(&shell);
    for (const Ring& hole : polygon.holes) {
      OGRLinearRing h = ToOgrRing(hole);
      part.addRing(&h);
    }
    multi.addGeometry(&part);
  }
  return ToWkb(multi);
}

Result<std::vector<Polygon>> PolygonsFromWkb(const std::vector<uint8_t>& wkb) {
  TB_ASSIGN_OR_RETURN(auto geometry, FromWkb(wkb));
  std::unique_ptr<OGRGeometry> multi(OGRGeometryFactory::forceToMultiPolygon(geometry.release()));
  if (multi == nullptr || wkbFlatten(multi->getGeometryType()) != wkbMultiPolygon)
    return Status::Corruption("feature geometry is not a polygon");
  std::vector<Polygon> out;
  for (const OGRPolygon* part : *multi->toMultiPolygon()) {
    Polygon polygon;
    TB_ASSIGN_OR_RETURN(polygon.shell, FromOgrRing(part->getExteriorRing()));
    for (int i = 0; i < part->getNumInteriorRings(); ++i) {
      TB_ASSIGN_OR_RETURN(Ring hole, FromOgrRing(part->getInteriorRing(i)));
      polygon.holes.push_back(std::move(hole));
    }
    out.push_back(std::move(polygon));
  }
  return out;
}

std::vector<uint8_t> LinesToWkb(const std::vector<std::vector<Point2>>& lines) {
  OGRMultiLineString multi;
  for (const auto& line : lines) {
    OGRLineString part;
    for (const Point2& p : line) part.addPoint(p.x, p.y);
    multi.addGeometry(&part);
  }
  return ToWkb(multi);
}

Result<std::vector<std::vector<Point2>>> LinesFromWkb(const std::vector<uint8_t>& wkb) {
  TB_ASSIGN_OR_RETURN(auto geometry, FromWkb(wkb));
  std::unique_ptr<OGRGeometry> multi(
      OGRGeometryFactory::forceToMultiLineString(geometry.release()));
  if (multi == nullptr || wkbFlatten(multi->getGeometryType()) != wkbMultiLineString)
    return Status::Corruption("feature geometry is not a line");
  std::vector<std::vector<Point2>> out;
  for (const OGRLineString* part : *multi->toMultiLineString()) {
    std::vector<Point2> line;
    for (int i = 0; i < part->getNumPoints(); ++i) line.push_back({part->getX(i), part->getY(i)});
    out.push_back(std::move(line));
  }
  return out;
}

}  // namespace tinbase
