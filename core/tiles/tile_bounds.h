// The bounding values of a quantized-mesh tile's header: centre, bounding sphere and the horizon
// occlusion point, from the tile's vertices on the WGS 84 ellipsoid (GeographicLib's Geocentric).
//
// The horizon occlusion point follows Cesium's definition: a point in the ellipsoid's scaled
// space (ECEF divided by the radii) such that when it is below the horizon, every vertex of the
// tile is too, so a client can cull the tile. Pure functions.
#pragma once

#include <array>
#include <vector>

#include "core/tiles/quantized_mesh.h"

namespace tinbase {

using Ecef = std::array<double, 3>;

// ECEF metres of (longitude, latitude) in degrees and height in metres above the ellipsoid.
Ecef ToEcef(double lon, double lat, double height);

// Fills centre, bounding sphere and horizon occlusion point of `header` from the ECEF positions
// of the tile's vertices. The centre is the bounding sphere's: clients draw the tile relative to
// it, so it is best near the vertices. REQUIRES: `positions` not empty.
void SetTileBounds(const std::vector<Ecef>& positions, QuantizedMeshHeader& header);

}  // namespace tinbase
