// LocalFrame: the vertices of a selection in a local east-north-up frame centred on them, for
// viewers that want small coordinates in metres (the GLB export, core/export/glb_writer.h).
//
// The origin is the centre of the selection's box (plan view and height). With a CRS, the
// vertices go to the geographic system of the CRS's own datum (its GEOGCS: no datum shift is
// applied, so no accuracy is lost to one) through core/geometry/reproject.h, heights to metres,
// and then into GeographicLib's LocalCartesian at the origin on that datum's ellipsoid; heights
// are taken as ellipsoidal (no geoid model is applied, so the frame's "up" is off the plumb line
// by the deflection of the vertical, seconds of arc). Without a CRS the frame is the store's
// axes shifted to the origin. Thread-safety: pure function.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

struct LocalFrame {
  bool geodetic = false;  // true: a real ENU frame on an ellipsoid; false: shifted store axes
  // The origin in the store's CRS.
  double x0 = 0, y0 = 0, z0 = 0;
  // With a CRS: the origin as latitude, longitude (degrees) and ellipsoidal height (metres) in
  // `geographic_crs`, the geographic system of the store CRS's datum.
  double latitude = 0, longitude = 0, height = 0;
  std::string geographic_crs;  // its label ("EPSG:4258"), empty without a CRS
  double semi_major = 0, inverse_flattening = 0;
  // enu[i] is selection.vertices[i] as east, north, up (metres with a CRS, else store units).
  std::vector<std::array<double, 3>> enu;
};

// The selection's vertices in the frame. `crs` may be null. InvalidArgument naming the point
// when a vertex does not transform to geographic coordinates. REQUIRES: a non-empty selection.
Result<LocalFrame> ToLocalFrame(const Tin& tin, const Crs* crs, const MeshSelection& selection);

}  // namespace tinbase
