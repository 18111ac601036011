// Mass points: surveyed points (spot heights, GNSS shots) inserted into an existing surface with
// their own z, and taken out again (docs/design.md, "Mass points").
//
// A `points add` is one feature of mode `points` whose geometry is the MultiPoint Z of the
// points that went in (core/vector/point_wkb.h), so history and revert see it as any other edit.
// One transaction with one `changes` row: the points are read (core/vector/survey_points.h),
// screened (db/edit/point_screen.h: outside the surface is an error, onto a vertex is left out
// and reported), written as the feature, then inserted by the update engine as lone points of
// vertex kind `user` (db/edit/update_engine.h): the conflict region is the union of their
// cavities, re-triangulated and refined to the surface's tolerance around them. A `points
// remove` takes out one feature's points, or the survey points in a box (a feature partly in it
// is replaced by one holding the rest), the same way: the vertices go, their stars are
// re-triangulated from the DEM. Any error leaves the store as it was.
// Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/feature_store.h"
#include "db/polygon_editor.h"
#include "db/store.h"

namespace tinbase {

struct PointsAddOptions {
  std::string surface;
  std::string file;  // LAS, XYZ/CSV or an OGR point source (core/vector/survey_points.h)
  // When set, these points (in the store's CRS, named by `labels`, one each) are added instead
  // of the file's.
  std::optional<std::vector<TinVertex>> points;
  std::vector<std::string> labels;
  std::optional<std::string> tag;  // names the feature; no paint
  // Called inside the transaction just before its commit, as PolygonAddOptions::before_commit
  // (the tiles brought up to date with the edit); empty: not called.
  BeforeCommit before_commit;
};

struct PointsRemoveOptions {
  std::optional<int64_t> feature;  // a `points` feature, whole
  std::optional<Box> box;          // or the survey points of `surface` in this closed box
  std::string surface;
  BeforeCommit before_commit;  // as PointsAddOptions'
};

struct PointsReport {
  int64_t tx = 0;
  int64_t points_in = 0;  // read (add) or in the box or feature (remove)
  int64_t inserted = 0;   // went in as vertices (add) or came out (remove)
  // Add: the points left out, "shots.csv, point 7: (x, y) snapped onto vertex 12 (0.0004 away),
  // left out", in input order.
  std::vector<std::string> snapped;
  std::vector<int64_t> features_added;    // the new `points` feature(s)
  std::vector<int64_t> features_removed;  // remove: the features taken out or replaced
  int64_t removed = 0;                    // triangles
  int64_t added = 0;
  int64_t refinement_points = 0;
  std::string reprojected_from;  // the file's CRS label when it was reprojected
};

// Inserts the points of options.file (or options.points) into surface options.surface.
// InvalidArgument naming the file and point for bad input, a point outside the surface or a z
// far outside the DEM's relief, and when every point snapped; NotFound for an unknown surface;
// the store is unchanged on every error.
Result<PointsReport> AddPoints(Store& store, const PointsAddOptions& options);

// Takes out the points options names. InvalidArgument when it names neither or both a feature
// and a box, when the feature is not a `points` feature, or when the box holds no survey point;
// NotFound for an unknown feature or surface. The store is unchanged on every error.
Result<PointsReport> RemovePoints(Store& store, const PointsRemoveOptions& options);

// For db/history (revert, export --as-of; db/history/feature_inverse.h): one local edit of
// `surface`, inside the caller's write transaction, that takes out the `points` features `remove`
// and puts the `restore` ones back, each under its own id, with one `changes` row of `action`, its
// feature versions and mesh image. Only the net change moves vertices: a point in both stays.
// Restored points that now fall onto a vertex are left out (as AddPoints snaps them).
// REQUIRES: inside a WriteTransaction the caller commits or drops. Errors as AddPoints.
Result<PointsReport> ApplyPointsEdit(Store& store, const SurfaceInfo& surface,
                                     std::vector<EditorFeature> restore,
                                     const std::vector<int64_t>& remove, const std::string& action);

}  // namespace tinbase
