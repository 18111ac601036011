// LandXML 1.2 writer: one surface as `LandXML/Surfaces/Surface` with its `Definition` (Pnts,
// Faces), its features' rings in `SourceData`, and the file-level `Units` and
// `CoordinateSystem`, through libxml2's xmlTextWriter (which escapes every attribute and text).
//
// Conventions, as LandXML has them: a point's text is "northing easting elevation" (y x z); point
// ids are 1-based vertex indices; a face lists three point ids counter-clockwise seen from above
// (tinbase's order), `n` lists the 1-based faces across the edges (p1 p2), (p2 p3), (p3 p1), 0 on
// the boundary; `i="1"` marks an invisible face. Coordinates are written as the shortest text
// that reads back as the same double, so a round trip is bit-exact. Thread-safety: pure.
#pragma once

#include <string>

#include "core/base/status.h"
#include "core/export/landxml_surface.h"

namespace tinbase {

// Writes `surface` to `path` (a temporary file the caller commits; see core/base/output_file.h).
// IOError naming the path when it cannot be written. REQUIRES: surface.tin's indices are valid.
Status WriteLandXml(const LandXmlSurface& surface, const std::string& path);

// The LandXML `Units` element for a linear unit of `metres_per_unit` metres: its child
// ("Metric" or "Imperial") and linearUnit ("meter", "foot", "USSurveyFoot").
struct LandXmlUnits {
  const char* system;
  const char* linear;
};
LandXmlUnits UnitsFor(double metres_per_unit);

}  // namespace tinbase
