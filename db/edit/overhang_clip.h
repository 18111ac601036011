// OverhangClip: the stage of the polygon editor (db/polygon_editor.h) that cuts a polygon feature
// overhanging its surface to the surface's data area, before the feature is draped (docs/design.md,
// "Polygons that overhang the surface"). The geometry is core/vector/data_area_clip.h; this stage
// reads the DEM cells around the feature to find where it has no elevation. Breaklines pass
// unchanged (their vertices must lie on the surface). Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/vector/data_area_clip.h"
#include "db/dem_store.h"
#include "db/feature_store.h"

namespace tinbase {

// A feature the editor cut to the data area, for the edit's report.
struct OverhangCut {
  int64_t feature = 0;      // the id it was stored under (0 until written)
  std::string label;        // as read: "file.geojson, feature 3"
  double area_outside = 0;  // plan area cut away, square map units of the store's CRS
};

// The data area of a surface draped on `dem` around `box` (the hull; the squares without elevation
// of the cells within a few cells of `box`). Errors of DemStore::ReadWindow (a block that cannot
// be read: Corruption or IOError naming it).
Result<DataArea> DataAreaAround(DemStore& dems, const DemInfo& dem, const Box& box);

// f's polygons clipped to the data area of its surface on `dem`; f is unchanged for kInside and
// for breaklines (verdict kInside), and holds the part inside for kCut (its caches unset).
// Errors as DataAreaAround and ClipToDataArea, with f's label.
Result<DataAreaClip> ClipFeatureToDataArea(DemStore& dems, const DemInfo& dem, EditorFeature& f);

// "lies wholly outside the data area of surface 'S' (hull minus nodata)": the message for a
// feature of verdict kOutside, after its label.
std::string WhollyOutsideMessage(const std::string& surface);

// The cuts as JSON for the CLI's --json and the service's answer: an array of
// {"feature": id, "label": "...", "area_outside": m2}.
nlohmann::json OverhangCutsJson(const std::vector<OverhangCut>& cuts);

}  // namespace tinbase
