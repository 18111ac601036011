// The first stage of a `points add` (db/edit/mass_points.h): which survey points go into the
// surface and which snap onto a vertex that is already there.
//
// Every point is located in the stored mesh (jump-and-walk through the edit's mesh cache, in a
// spatial order so each walk starts near its point). A point outside the surface is an error
// naming it. A point closer than the edit's snap distance (kSnapCells DEM cells,
// db/edit/local_edit.h) to a corner of the triangle holding it, or to an earlier point of the
// same file, would be merged with it by the update engine and lose its own z silently; here it
// is left out and reported instead, with what it snapped onto. Reads only; not thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/tin/tin.h"
#include "db/edit/edit_context.h"
#include "db/edit/local_edit.h"
#include "db/feature_store.h"

namespace tinbase {

// A survey point left out: `index` into the input, and the vertex (store id) or the earlier
// input point it lies on.
struct SnappedPoint {
  size_t index = 0;
  int64_t vertex = 0;   // 0 when it snapped onto an earlier point of the input
  size_t earlier = 0;   // that point's index, when vertex is 0
  double distance = 0;  // plan distance to it
};

struct ScreenedPoints {
  std::vector<size_t> kept;  // indices into the input, in a spatial order
  std::vector<SnappedPoint> snapped;
  Box box;  // of the kept points
};

// Screens `points` (named by `labels`) against the surface of `ctx` as stored. Of two points
// within the snap distance, the first in input order is kept.
// InvalidArgument "shots.csv, point 7: (x, y) lies outside surface 'terrain'" for the first point
// outside; Corruption when stored rows are inconsistent. REQUIRES: labels.size() == points.size().
Result<ScreenedPoints> ScreenPoints(const EditContext& ctx, const std::vector<TinVertex>& points,
                                    const std::vector<std::string>& labels);

// The stored vertex of a survey point: a kUser corner within the snap distance of `p` of the
// triangle holding it (the engine may have moved the point onto a constrained edge by that
// much); 0 when there is none (it went in as another vertex, or a later edit took it).
Result<int64_t> SurveyVertexAt(const EditContext& ctx, const TinVertex& p);

// "(x, y) onto vertex 12 (0.0004 away)" or "(x, y) onto shots.csv, point 3 (0 away)".
std::string DescribeSnap(const SnappedPoint& s, const std::vector<TinVertex>& points,
                         const std::vector<std::string>& labels);

}  // namespace tinbase
