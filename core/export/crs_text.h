// The CRS as the exporters record it in their files' headers and metadata: a label
// ("EPSG:32632") and WKT2 on one line, so line-oriented formats (OBJ and PLY comments) can carry
// it. Thread-safety: pure functions.
#pragma once

#include <string>

#include "core/geometry/crs.h"

namespace tinbase {

// WKT2 (2018) of `crs` without line breaks; empty when GDAL cannot export it.
std::string OneLineWkt(const Crs& crs);

}  // namespace tinbase
