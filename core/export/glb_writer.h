// GLB writer: a selection of a Tin as glTF 2.0 binary (.glb), written with tinygltf (Debian's
// libtinygltf-dev) and ordered with meshoptimizer (docs/cli.md, "Export", has the layout).
//
// - Positions are float32 in the local east-north-up frame of core/export/local_frame.h, on
//   glTF's axes (y up, right-handed): x = east, y = up, z = -north, so a triangle
//   counter-clockwise seen from above is a front face. The frame's origin (latitude, longitude,
//   height, and x, y, z in the store's CRS), the geographic system it is on and the store's CRS
//   (label, EPSG code, WKT) are in asset.extras.tinbase.
// - NORMAL per vertex: the area-weighted mean of its triangles' normals (smooth terrain).
// - One primitive per tag (its material named after the tag, colour from the tag's value by a
//   fixed hash, so a tag keeps its colour from export to export), one for untagged triangles
//   (light grey) and one for invisible triangles (translucent grey, only without visible_only).
// - With features: each triangle's feature (core/export/export_feature.h) as EXT_mesh_features
//   vertex attribute _FEATURE_ID_0 (vertices are split where features meet, so a triangle's three
//   corners agree), the row of an EXT_structural_metadata property table "features" with columns
//   id (INT64), mode (ENUM), tag (STRING) and one per attribute key (FLOAT64 when every feature
//   has a number there, else STRING: the string, or the value's JSON text); nullFeatureId is the
//   table's row count. Property ids are the keys with characters outside [A-Za-z0-9_] replaced
//   by '_' (the key itself is the property's name).
// - Indices in meshoptimizer's vertex-cache order and vertices in first-use order; 16-bit
//   indices where a primitive has fewer than 65536 vertices. No quantisation: 16-bit positions
//   would give centimetres over a few kilometres, not what surveyors expect.
// Thread-safety: pure function.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/export/export_feature.h"
#include "core/export/mesh_selection.h"
#include "core/geometry/crs.h"
#include "core/tin/tin.h"

namespace tinbase {

struct GlbContent {
  std::vector<ExportFeature> features;  // the property table's rows, in this order
  // Per triangle of the Tin: an index into `features` or kNoFeature; empty: no feature ids.
  std::vector<int32_t> triangle_feature;
};

// Writes the selected triangles of `tin` to `path` (created or truncated). `crs` may be null
// (the frame is then the store's axes shifted). InvalidArgument when nothing is selected, when
// a vertex does not transform to geographic coordinates, or when triangle_feature has the wrong
// size; IOError naming `path` when it cannot be written.
Status WriteGlb(const Tin& tin, const Crs* crs, const MeshSelection& selection,
                const GlbContent& content, const std::string& path);

}  // namespace tinbase
