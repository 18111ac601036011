#include "db/edit/overhang_clip.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "db/point_locator.h"

namespace tinbase {

namespace {

// Cells of margin around the feature's box when reading the DEM: a square without elevation
// is found from its four cells, and the ring may lie on the box's edge.
constexpr double kMarginCells = 2;
// The inset of clipped rings from the data area's edges, as a fraction of a cell (see DataArea):
// far above the rounding of coordinates, far below the editor's snapping distance (a thousandth).
constexpr double kInsetCells = 1e-6;
// Pieces of a cut smaller than this fraction of a cell's area are dropped with the cut.
constexpr double kMinPieceCells = 1e-3;

PlanRect HullOf(const GridGeometry& g) {
  const double x0 = g.CellCenterX(0), x1 = g.CellCenterX(g.width - 1);
  const double y0 = g.CellCenterY(0), y1 = g.CellCenterY(g.height - 1);
  return {std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1)};
}

// Whether the surface holds (x, y) (on an edge or a vertex counts).
Result<bool> Holds(PointLocator& locator, double x, double y) {
  auto located = locator.LocateTriangle(x, y);
  if (located.ok()) return true;
  if (located.status().code() == StatusCode::kNotFound) return false;
  return located.status();
}

// The box of the surface's vertices; nullopt when it has none.
Result<std::optional<PlanRect>> VertexBox(Store& store, const SurfaceInfo& surface) {
  TB_ASSIGN_OR_RETURN(
      Statement * stmt,
      store.db().Cached("SELECT min(x), min(y), max(x), max(y) FROM vertices WHERE surface = ?"));
  stmt->Bind(1, surface.id);
  TB_ASSIGN_OR_RETURN(const bool row, stmt->Step());
  std::optional<PlanRect> box;
  if (row && !stmt->ColumnIsNull(0))
    box = PlanRect{stmt->ColumnDouble(0), stmt->ColumnDouble(1), stmt->ColumnDouble(2),
                   stmt->ColumnDouble(3)};
  stmt->Reset();
  return box;
}

}  // namespace

Result<PlanRect> SurfaceHull(Store& store, const SurfaceInfo& surface, const DemInfo& dem) {
  const PlanRect grid = HullOf(dem.geometry);
  {
    TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
    PointLocator locator(store, surface);
    TB_ASSIGN_OR_RETURN(const bool low, Holds(locator, grid.min_x, grid.min_y));
    TB_ASSIGN_OR_RETURN(const bool high, Holds(locator, grid.max_x, grid.max_y));
    // The surface's domain is a rectangle inside the grid's: holding two opposite corners of
    // the grid's, it is the grid's.
    if (low && high) return grid;
  }
  TB_ASSIGN_OR_RETURN(std::optional<PlanRect> own, VertexBox(store, surface));
  if (!own) return grid;  // no vertices: the edit refuses every point as outside the surface
  return PlanRect{std::max(own->min_x, grid.min_x), std::max(own->min_y, grid.min_y),
                  std::min(own->max_x, grid.max_x), std::min(own->max_y, grid.max_y)};
}

Result<DataArea> DataAreaAround(DemStore& dems, const DemInfo& dem, const PlanRect& hull,
                                const Box& box) {
  const GridGeometry& g = dem.geometry;
  const double cell = std::min(g.cell_x, std::fabs(g.cell_y));
  DataArea area;
  area.hull = hull;
  area.hull_inset = kInsetCells * cell;
  area.min_piece_area = kMinPieceCells * cell * cell;
  const double margin = kMarginCells * cell;
  DemBox window{std::max(box.min_x - margin, g.MinX()), std::max(box.min_y - margin, g.MinY()),
                std::min(box.max_x + margin, g.MaxX()), std::min(box.max_y + margin, g.MaxY())};
  if (window.min_x >= window.max_x || window.min_y >= window.max_y) return area;  // off the DEM
  TB_ASSIGN_OR_RETURN(Grid cells, dems.ReadWindow(dem, window, 0));
  area.nodata = NoElevationRectangles(cells);
  return area;
}

Result<DataAreaClip> ClipFeatureToDataArea(DemStore& dems, const DemInfo& dem, const PlanRect& hull,
                                           EditorFeature& f) {
  if (f.polygons.empty()) return DataAreaClip{};
  auto clipped = [&]() -> Result<DataAreaClip> {
    TB_ASSIGN_OR_RETURN(DataArea area, DataAreaAround(dems, dem, hull, BoxOf(f)));
    return ClipToDataArea(f.polygons, area);
  }();
  if (!clipped.ok()) return clipped.status().WithContext(f.label);
  if (clipped->verdict != ClipVerdict::kCut) return clipped;
  // A fresh feature: the caches BoxOf and InsideOf filled describe the polygons as read.
  EditorFeature cut;
  cut.id = f.id;
  cut.label = std::move(f.label);
  cut.mode = f.mode;
  cut.tag = std::move(f.tag);
  cut.level = f.level;
  cut.attributes = std::move(f.attributes);
  cut.polygons = std::move(clipped->polygons);
  f = std::move(cut);
  clipped->polygons.clear();
  return clipped;
}

std::string WhollyOutsideMessage(const std::string& surface) {
  return "lies wholly outside the data area of surface '" + surface + "' (its hull minus nodata)";
}

nlohmann::json OverhangCutsJson(const std::vector<OverhangCut>& cuts) {
  nlohmann::json out = nlohmann::json::array();
  for (const OverhangCut& cut : cuts)
    out.push_back(
        {{"feature", cut.feature}, {"label", cut.label}, {"area_outside", cut.area_outside}});
  return out;
}

}  // namespace tinbase
