// LandXmlSurface: everything a LandXML 1.2 file of tinbase carries for one surface, the value
// core/export/landxml_writer.h writes and core/import/landxml_reader.h reads back.
//
// The standard elements hold what other LandXML software reads: the vertices (Pnts), the
// triangles with their neighbours and visibility (Faces), the coordinate system and units, and
// the features' rings as breaklines and boundaries (SourceData). What tinbase needs besides, to
// rebuild an identical surface (tags, vertex kinds, constraint owners, the features' modes,
// levels and attributes, the surface's kind and method), goes into attributes of the tinbase
// namespace and a `Feature code="tinbase"` element, as docs/cli.md ("LandXML") describes.
// Plain data.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/tin/feature_mode.h"
#include "core/tin/tin.h"

namespace tinbase {

// The namespace of tinbase's extension attributes and the `code` of its Feature elements.
inline constexpr char kTinbaseLandXmlNamespace[] = "urn:tinbase:landxml:1";
inline constexpr char kLandXmlNamespace[] = "http://www.landxml.org/schema/LandXML-1.2";

// A feature of the surface (a row of `features`): polygons, or lines for a breakline.
struct LandXmlFeature {
  std::string name;  // the store's name column (its tag, or a label)
  FeatureMode mode = FeatureMode::kFill;
  std::optional<std::string> tag;
  std::optional<double> level;
  std::string attributes = "{}";  // JSON object text
  std::vector<Polygon> polygons;  // rings open, shells counter-clockwise, holes clockwise
  std::vector<std::vector<Point2>> lines;
  // kFeature: a 3D line, written as PntList3D with line_z[k][i] the z of lines[k][i] (and the
  // Property z_from); kDem: lines are draped, written as PntList2D, line_z empty.
  ZFrom z_from = ZFrom::kDem;
  std::vector<std::vector<double>> line_z;
};

// A constrained edge between vertex indices a and b and the feature (index into
// LandXmlSurface::features) whose ring or line made it; nullopt for the surface's own.
struct LandXmlConstraint {
  uint32_t a = 0;
  uint32_t b = 0;
  std::optional<uint32_t> feature;
};

struct LandXmlSurface {
  std::string name;
  std::string kind = "free";  // "delaunay" or "free" (SurfaceKindName)
  std::string method;         // the builder's name; empty when unknown
  std::optional<double> tolerance;
  std::string dem;  // the name of the DEM the surface is draped on; empty when none
  // tin.constraints is unused: `constraints` carries them with their owners.
  Tin tin;
  std::vector<LandXmlConstraint> constraints;
  std::vector<LandXmlFeature> features;  // in the order their paint applies (store id order)
  std::string crs_wkt;                   // empty when the store has no CRS
  std::optional<int> epsg;
  std::string crs_name;
  // Metres per linear unit of x, y and z (1 for metres and for a geographic CRS's heights).
  double metres_per_unit = 1.0;
};

}  // namespace tinbase
