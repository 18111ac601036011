// ElevationRules: the z an edit gives a vertex (docs/design.md, "Inserting a polygon"). A point
// on a 3D line (a line feature with z from the feature) takes the line's z (core/tin/
// line_elevation.h: the line of the highest feature id where several meet); else a point inside
// a replace feature takes its level (the last such feature in id order wins, as in painting); an
// existing vertex inside a removed replace feature gets its DEM z back; a new point elsewhere
// takes the DEM's z. Borrows the DEM store; not thread-safe (sampling reads blocks
// through the store's cache).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "core/geometry/polygon_locator.h"
#include "core/tin/line_elevation.h"
#include "core/tin/tin.h"
#include "db/dem_store.h"
#include "db/feature_store.h"

namespace tinbase {

class ElevationRules {
 public:
  // `features`: the surface's features after the edit; `restore`: the inside of the removed
  // replace features, or null.
  ElevationRules(DemStore& dems, const DemInfo& dem, const std::vector<EditorFeature>& features,
                 std::shared_ptr<const PolygonLocator> restore);

  // The level of the last replace feature covering `p`, if any.
  std::optional<double> Level(const Point2& p) const;
  // z of an existing vertex after the edit: a replace level, the DEM again where a removed
  // replace feature had flattened it (when the DEM has data there), else as stored.
  double TargetZ(const TinVertex& v) const;
  // z of a point the edit creates (ring points, crossings): the replace level or the DEM (NaN
  // where the DEM has no data; a failed read also gives NaN and is kept for status()).
  double NewZ(double x, double y) const;
  // The first DEM read that failed (Corruption or IOError naming the block), else OK. The
  // callers of TargetZ and NewZ run inside CGAL callbacks that cannot return an error, so a read
  // failure is recorded here and checked after each stage: it is never mistaken for no data.
  const Status& status() const { return first_error_; }
  // Whether `p` lies inside a replace feature: the tolerance does not apply there.
  bool Replaced(const Point2& p) const;
  // Whether some replace feature has a polygon.
  bool has_replace() const { return has_replace_polygons_; }
  // Whether the tolerance does not apply at `p`: inside a replace feature, or within
  // kLineBandCells of a 3D line.
  bool ToleranceExempt(const Point2& p) const;
  // The 3D lines of the features.
  const LineElevation& lines() const { return lines_; }

 private:
  double DemZ(double x, double y) const;

  DemStore& dems_;
  const DemInfo& dem_;
  std::vector<std::shared_ptr<const PolygonLocator>> locators_;  // replace features, id order
  std::vector<double> levels_;
  std::unique_ptr<PolygonLocator> replaced_;  // the union of the replace features' polygons
  bool has_replace_polygons_ = false;
  std::shared_ptr<const PolygonLocator> restore_;
  mutable Status first_error_;
  LineElevation lines_;
  double line_band_ = 0;  // kLineBandCells in map units
};

}  // namespace tinbase
