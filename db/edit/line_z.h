// Line z: the editor's stage for lines with z from the feature (3D lines; docs/design.md, "Soft
// lines and z from the feature"). A 3D line goes into the edit with its own z instead of being
// draped on the DEM, and every point an edit adds on a 3D line (a draped line's vertex that lands
// on one) takes the z the lines give it (core/tin/line_elevation.h), as the update engine's
// points do (db/edit/elevation_rules.h). Thread-safety: pure functions.
#pragma once

#include <vector>

#include "core/base/status.h"
#include "db/dem_store.h"
#include "db/edit/local_edit.h"
#include "db/feature_store.h"

namespace tinbase {

// The lines of `f` (z_from kFeature) as edit polylines with their own z, not densified (a 3D line
// is straight between its vertices). InvalidArgument "<label>, line k, vertex v: z is not a
// number" (or "is not finite") for a z the feature cannot give, and "<label>, line k: no z" when
// the line has none. REQUIRES: IsLineMode(f.mode).
Result<std::vector<EditPolyline>> OwnZPolylines(const EditorFeature& f);

// The points `edit` adds that lie on a 3D line of edit.features take that line's z (the lines of
// the surface's features after the edit; points within kSnapCells cells count as on one).
void ApplyLineZ(const DemInfo& dem, LocalEdit& edit);

// The distance within which a point counts as on a 3D line of a surface on `dem`.
double LineNearDistance(const DemInfo& dem);

}  // namespace tinbase
