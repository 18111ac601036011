#include "db/edit/overhang_clip.h"

#include <algorithm>
#include <cmath>
#include <utility>

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

}  // namespace

Result<DataArea> DataAreaAround(DemStore& dems, const DemInfo& dem, const Box& box) {
  const GridGeometry& g = dem.geometry;
  const double cell = std::min(g.cell_x, std::fabs(g.cell_y));
  DataArea area;
  area.hull = HullOf(g);
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

Result<DataAreaClip> ClipFeatureToDataArea(DemStore& dems, const DemInfo& dem, EditorFeature& f) {
  if (f.polygons.empty()) return DataAreaClip{};
  auto clipped = [&]() -> Result<DataAreaClip> {
    TB_ASSIGN_OR_RETURN(DataArea area, DataAreaAround(dems, dem, BoxOf(f)));
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
