// Measure layers: contour lines and per-triangle slope written as OGR vector layers that GIS
// programs open (QGIS, ogrinfo).
//
// The format follows the output's extension: .gpkg (GeoPackage), .geojson or .json (GeoJSON),
// .shp (ESRI Shapefile). Nothing is left at the path when writing fails: single-file formats go
// through OutputFile (core/base/output_file.h); a shapefile, which is several files named after
// the layer, is written in a temporary directory beside the target and its files renamed into
// place (the .shp last) once GDAL has closed them. Thread-safety: reentrant.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/crs.h"
#include "core/measure/contour_lines.h"
#include "core/measure/slope_aspect.h"
#include "core/tin/tin.h"

namespace tinbase {

enum class LayerFormat { kGeoPackage, kGeoJson, kShapefile };

// The format for `path` by its extension (case-insensitive). InvalidArgument "unknown format"
// naming the path and the extensions known otherwise.
Result<LayerFormat> LayerFormatForPath(const std::string& path);

// One LineString Z feature per contour line (z = its level; a closed line repeats its first
// point) in layer "contours", with fields id (Integer64) and elevation (Real), in `crs` when not
// null. Errors: LayerFormatForPath's; IOError naming the path when it cannot be written.
Status WriteContourLayer(const std::vector<ContourLine>& lines, const Crs* crs,
                         const std::string& path);

// One Polygon Z feature per entry of `slopes` in layer "slope", with fields triangle (the store
// id `triangle_ids[t]`), slope_deg, aspect_deg (null when flat) and tag (null when none).
// Errors as WriteContourLayer. REQUIRES: triangle_ids has one id per triangle of `tin`.
Status WriteSlopeLayer(const Tin& tin, const std::vector<TriangleSlope>& slopes,
                       const std::vector<int64_t>& triangle_ids, const Crs* crs,
                       const std::string& path);

}  // namespace tinbase
