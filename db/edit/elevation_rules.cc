#include "db/edit/elevation_rules.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "db/edit/line_z.h"

namespace tinbase {

ElevationRules::ElevationRules(DemStore& dems, const DemInfo& dem,
                               const std::vector<EditorFeature>& features,
                               std::shared_ptr<const PolygonLocator> restore)
    : dems_(dems), dem_(dem), restore_(std::move(restore)) {
  std::vector<Polygon> replace_polygons;
  for (const EditorFeature& f : features) {
    if (f.mode != FeatureMode::kReplace) continue;
    locators_.push_back(InsideOf(f));
    levels_.push_back(f.level.value_or(0));
    replace_polygons.insert(replace_polygons.end(), f.polygons.begin(), f.polygons.end());
  }
  has_replace_polygons_ = !replace_polygons.empty();
  replaced_ = std::make_unique<PolygonLocator>(replace_polygons);
  const double cell_x = dem.geometry.cell_x, cell_y = std::fabs(dem.geometry.cell_y);
  lines_ = LineElevationOf(features, LineNearDistance(dem));
  line_band_ = kLineBandCells * std::max(cell_x, cell_y);
}

std::optional<double> ElevationRules::Level(const Point2& p) const {
  for (size_t k = locators_.size(); k-- > 0;)
    if (locators_[k]->Locate(p) != PointInPolygon::kOutside) return levels_[k];
  return std::nullopt;
}

double ElevationRules::TargetZ(const TinVertex& v) const {
  if (auto z = lines_.ZAt({v.x, v.y})) return *z;
  if (auto level = Level({v.x, v.y})) return *level;
  if (restore_ && restore_->Locate({v.x, v.y}) != PointInPolygon::kOutside) {
    const double z = DemZ(v.x, v.y);
    if (std::isfinite(z)) return z;
  }
  return v.z;
}

double ElevationRules::NewZ(double x, double y) const {
  if (auto z = lines_.ZAt({x, y})) return *z;
  if (auto level = Level({x, y})) return *level;
  return DemZ(x, y);
}

bool ElevationRules::Replaced(const Point2& p) const {
  return has_replace() && replaced_->Locate(p) != PointInPolygon::kOutside;
}

bool ElevationRules::ToleranceExempt(const Point2& p) const {
  return Replaced(p) || (!lines_.empty() && lines_.Near(p, line_band_));
}

double ElevationRules::DemZ(double x, double y) const {
  Result<double> z = dems_.Elevation(dem_, x, y);
  if (z.ok()) return *z;
  if (first_error_.ok()) first_error_ = z.status();
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace tinbase
