// OverhangClip: the stage of the polygon editor (db/polygon_editor.h) that cuts a polygon feature
// overhanging its surface to the surface's data area, before the feature is draped (docs/design.md,
// "Polygons that overhang the surface"). The geometry is core/vector/data_area_clip.h; this stage
// finds the rectangle the surface's triangles cover (SurfaceHull: a DEM's grid may have grown
// past it) and reads the DEM cells around the feature to find where it has no elevation.
// Breaklines pass unchanged (their vertices must lie on the surface). Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/vector/data_area_clip.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// A feature the editor cut to the data area, for the edit's report.
struct OverhangCut {
  int64_t feature = 0;      // the id it was stored under (0 until written)
  std::string label;        // as read: "file.geojson, feature 3"
  double area_outside = 0;  // plan area cut away, square map units of the store's CRS
};

// The rectangle `surface`'s triangles cover (builders triangulate the rectangle of its DEM's cell
// centres, and edits stay inside it). It is the DEM's rectangle unless the grid grew after the
// build (db/edit/resurvey.h: the surface keeps its hull). Cheap when the surface holds both
// corners of the DEM's rectangle (two point locations); otherwise the box of the surface's
// vertices (a scan of its vertex rows). Errors of the point locator (Corruption) and of the read.
Result<PlanRect> SurfaceHull(Store& store, const SurfaceInfo& surface, const DemInfo& dem);

// The data area of a surface of rectangle `hull` (SurfaceHull) draped on `dem` around `box`: the
// hull minus the squares without elevation of the cells within a few cells of `box`. Errors of
// DemStore::ReadWindow (a block that cannot be read: Corruption or IOError naming it).
Result<DataArea> DataAreaAround(DemStore& dems, const DemInfo& dem, const PlanRect& hull,
                                const Box& box);

// f's polygons clipped to the data area of its surface (rectangle `hull`, unused for breaklines)
// on `dem`; f is unchanged for kInside and for breaklines (verdict kInside), and holds the part
// inside for kCut (its caches unset). Errors as DataAreaAround and ClipToDataArea, with f's label.
Result<DataAreaClip> ClipFeatureToDataArea(DemStore& dems, const DemInfo& dem, const PlanRect& hull,
                                           EditorFeature& f);

// "lies wholly outside the data area of surface 'S' (hull minus nodata)": the message for a
// feature of verdict kOutside, after its label.
std::string WhollyOutsideMessage(const std::string& surface);

// The cuts as JSON for the CLI's --json and the service's answer: an array of
// {"feature": id, "label": "...", "area_outside": m2}.
nlohmann::json OverhangCutsJson(const std::vector<OverhangCut>& cuts);

}  // namespace tinbase
