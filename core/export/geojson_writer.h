// GeoJSON writer: a selection of a Tin as a FeatureCollection of 3D Polygon features, one per
// triangle (a closed ring of its three vertices, counter-clockwise), with properties id (the
// store id, or the triangle's index when none are given), visible and tag (null when untagged).
// Written through OGR's GeoJSON driver so the CRS is declared as GDAL does, with RFC 7946 off
// (it would force WGS 84 longitude/latitude) and 17 significant figures so every double reads
// back exactly. Thread-safety: one GDAL session per call; safe from several threads.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

// Writes the selected triangles of `tin` to `path`, replacing any file there. `crs` may be null;
// `ids` is empty or holds one store id per triangle of `tin`. IOError naming `path` when GDAL
// cannot create or write it.
Status WriteGeoJson(const Tin& tin, const Crs* crs, const MeshSelection& selection,
                    const std::vector<int64_t>& ids, const std::string& path);

}  // namespace tinbase
