#include "core/vector/data_area_clip.h"

#include <ogr_geometry.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <utility>

namespace tinbase {

namespace {

using GeometryPtr = std::unique_ptr<OGRGeometry>;

void AddRing(const Ring& ring, OGRPolygon* polygon) {
  OGRLinearRing linear;
  for (const Point2& p : ring) linear.addPoint(p.x, p.y);
  linear.closeRings();
  polygon->addRing(&linear);
}

GeometryPtr RectGeometry(const PlanRect& r) {
  auto polygon = std::make_unique<OGRPolygon>();
  AddRing({{r.min_x, r.min_y}, {r.max_x, r.min_y}, {r.max_x, r.max_y}, {r.min_x, r.max_y}},
          polygon.get());
  return polygon;
}

GeometryPtr MultiPolygonOf(const std::vector<Polygon>& polygons) {
  auto multi = std::make_unique<OGRMultiPolygon>();
  for (const Polygon& p : polygons) {
    OGRPolygon polygon;
    AddRing(p.shell, &polygon);
    for (const Ring& hole : p.holes) AddRing(hole, &polygon);
    multi->addGeometry(&polygon);
  }
  return multi;
}

// The polygonal parts of `g` (GEOS may return a collection with lines and points where the
// clipped polygon only touches the data area's edge).
void CollectPolygons(const OGRGeometry& g, std::vector<const OGRPolygon*>* out) {
  const OGRwkbGeometryType type = wkbFlatten(g.getGeometryType());
  if (type == wkbPolygon) {
    out->push_back(g.toPolygon());
  } else if (type == wkbMultiPolygon || type == wkbGeometryCollection) {
    for (const OGRGeometry* part : *g.toGeometryCollection()) CollectPolygons(*part, out);
  }
}

std::vector<Ring> RingsOf(const OGRPolygon& polygon) {
  std::vector<Ring> rings;
  for (const OGRLinearRing* linear : polygon) {
    Ring ring;
    for (const OGRPoint& p : *linear) ring.push_back({p.getX(), p.getY()});
    rings.push_back(std::move(ring));
  }
  return rings;
}

// The data area as one geometry: the hull shrunk by `inset`, minus the union of the squares
// without elevation grown by it.
Result<GeometryPtr> DataAreaGeometry(const DataArea& area, double inset) {
  PlanRect hull = area.hull;
  hull.min_x += inset, hull.min_y += inset, hull.max_x -= inset, hull.max_y -= inset;
  GeometryPtr data = RectGeometry(hull);
  if (area.nodata.empty()) return data;
  OGRMultiPolygon cells;
  for (PlanRect r : area.nodata) {
    r.min_x -= inset, r.min_y -= inset, r.max_x += inset, r.max_y += inset;
    cells.addGeometryDirectly(RectGeometry(r).release());
  }
  GeometryPtr nodata(cells.UnionCascaded());
  if (!nodata) return Status::InvalidArgument("GEOS could not merge the DEM's nodata cells");
  GeometryPtr difference(data->Difference(nodata.get()));
  if (!difference) return Status::InvalidArgument("GEOS could not cut nodata from the hull");
  return difference;
}

double AreaOf(const std::vector<const OGRPolygon*>& polygons) {
  double area = 0;
  for (const OGRPolygon* p : polygons) area += p->get_Area();
  return area;
}

}  // namespace

Result<DataAreaClip> ClipToDataArea(const std::vector<Polygon>& polygons, const DataArea& area) {
  if (!OGRGeometryFactory::haveGEOS())
    return Status::InvalidArgument(
        "clipping a polygon to the surface needs GDAL built with GEOS (or use --strict)");
  DataAreaClip out;
  GeometryPtr input = MultiPolygonOf(polygons);
  // Inside the closed data area (no inset): the polygon goes in as given, bit for bit.
  TB_ASSIGN_OR_RETURN(GeometryPtr closed, DataAreaGeometry(area, 0));
  if (closed->Contains(input.get())) {
    out.polygons = polygons;
    return out;
  }
  TB_ASSIGN_OR_RETURN(GeometryPtr inset, DataAreaGeometry(area, area.hull_inset));
  GeometryPtr inside(input->Intersection(inset.get()));
  if (!inside) return Status::InvalidArgument("GEOS could not intersect the polygon with the DEM");
  std::vector<const OGRPolygon*> pieces;
  CollectPolygons(*inside, &pieces);
  std::vector<const OGRPolygon*> input_parts;
  CollectPolygons(*input, &input_parts);
  double kept_area = 0;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const double piece_area = pieces[k]->get_Area();
    if (piece_area <= area.min_piece_area) continue;
    auto valid = MakeValidPolygon(RingsOf(*pieces[k]));
    if (!valid.ok())
      return valid.status().WithContext("the part of the polygon on the DEM (piece " +
                                        std::to_string(k) + ")");
    out.polygons.push_back(std::move(*valid));
    kept_area += piece_area;
  }
  out.area_outside = std::max(0.0, AreaOf(input_parts) - kept_area);
  out.verdict = out.polygons.empty() ? ClipVerdict::kOutside : ClipVerdict::kCut;
  return out;
}

std::vector<PlanRect> NoElevationRectangles(const Grid& grid) {
  const GridGeometry& g = grid.geometry;
  // Square (c, r) lies between the centres of cells c, c + 1 and rows r, r + 1.
  const auto blank = [&](int64_t c, int64_t r) {
    return !grid.IsValid(c, r) && !grid.IsValid(c + 1, r) && !grid.IsValid(c, r + 1) &&
           !grid.IsValid(c + 1, r + 1);
  };
  std::vector<PlanRect> out;
  // Runs [c0, c1) of the row above, and the rectangle each grows.
  std::map<std::pair<int64_t, int64_t>, size_t> open;
  for (int64_t r = 0; r + 1 < g.height; ++r) {
    std::map<std::pair<int64_t, int64_t>, size_t> next;
    const double y0 = g.CellCenterY(r), y1 = g.CellCenterY(r + 1);
    for (int64_t c = 0; c + 1 < g.width;) {
      if (!blank(c, r)) {
        ++c;
        continue;
      }
      const int64_t c0 = c;
      while (c + 1 < g.width && blank(c, r)) ++c;
      const double x0 = g.CellCenterX(c0), x1 = g.CellCenterX(c);
      auto above = open.find({c0, c});
      if (above != open.end()) {
        PlanRect& rect = out[above->second];
        rect.min_y = std::min({rect.min_y, y0, y1});
        rect.max_y = std::max({rect.max_y, y0, y1});
        next[{c0, c}] = above->second;
        continue;
      }
      out.push_back({std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1)});
      next[{c0, c}] = out.size() - 1;
    }
    open = std::move(next);
  }
  return out;
}

}  // namespace tinbase
