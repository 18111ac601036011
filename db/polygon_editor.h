// PolygonEditor: inserts polygon and line features into a surface in one transaction
// (docs/design.md, "Inserting a polygon").
//
// The features are read and validated (core/vector/polygon_source), their rings draped on the
// surface's DEM and densified to the surface tolerance (core/tin/drape), all before the write
// transaction starts; then the update engine (db/edit/update_engine) re-triangulates only the
// conflict region, refines it to the tolerance and repaints around the features. Removing or
// updating a feature is the same local edit with its constraints going. Each call is one
// transaction (or, with `each`, one per feature) with one `changes` row; any error leaves the store
// as it was (per feature with `each`). Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/tin/feature_mode.h"
#include "db/edit/overhang_clip.h"
#include "db/edit/update_engine.h"
#include "db/feature_store.h"
#include "db/store.h"

namespace tinbase {

// A feature given in memory (a request body of `tinbase serve`) instead of read from a file:
// already in the store's CRS, its polygons valid (MakeValidPolygon). Unset mode, tag and level
// take the PolygonAddOptions' values.
struct MemoryFeature {
  std::string label;  // names the feature in messages: "features[3]"
  std::optional<FeatureMode> mode;
  std::optional<std::string> tag;
  std::optional<double> level;
  nlohmann::json attributes = nlohmann::json::object();
  std::vector<Polygon> polygons;           // clip, erase, fill, replace
  std::vector<std::vector<Point2>> lines;  // breakline, softline
  // Lines with their own z (z_from kFeature; unset: the options' z_from): line_z[k][i] is the z
  // of lines[k][i].
  std::optional<ZFrom> z_from;
  std::vector<std::vector<double>> line_z;
};

// Called inside an edit's write transaction once all its rows and its `changes` row (number
// `tx`) are written, just before the commit: what it writes commits with the edit, and an error
// it returns rolls the edit back and is the edit's error. `tinbase serve` brings the tile
// pyramids up to date there, so no tile is ever served that an edit has made stale.
using BeforeCommit = std::function<Status(Store& store, int64_t tx)>;

struct PolygonAddOptions {
  std::string surface;
  std::string file;
  // When set, these features are edited in place of the file's (file, layer, where and tag_field
  // are then ignored).
  std::optional<std::vector<MemoryFeature>> features;
  std::string layer;  // OGR layer; empty: the only one
  std::string where;  // OGR attribute filter
  // Required by AddPolygons; UpdatePolygon keeps the old feature's mode when absent.
  std::optional<FeatureMode> mode;
  std::string tag_field;        // the field whose value tags the triangles (fill, replace)
  std::string tag;              // or one tag for every feature
  std::optional<double> level;  // replace: the flat z
  bool repair = false;          // GEOS MakeValid before validation (core/vector/polygon_source)
  bool each = false;            // one transaction per feature; failures are reported, not fatal
  // AddPolygons calls it now and then with the fraction of the features done (without `each`,
  // preparing them is counted as half the work, the one edit the other half), from the calling
  // thread; empty: not called. For progress bars.
  std::function<void(double fraction)> progress;
  // Refuse polygons that overhang the surface's data area (its hull minus nodata), as before
  // clipping existed; otherwise they are cut to it (db/edit/overhang_clip.h).
  bool strict = false;
  // Called before each edit's commit (with `each`, once per feature); empty: not called.
  BeforeCommit before_commit;
  // Line modes: draped on the DEM, or each vertex at the source's own z (3D lines; the source's
  // geometry must have z, and every z must be a number).
  ZFrom z_from = ZFrom::kDem;
  // UpdatePolygon: whether z_from was given. When not, a line keeps the old feature's z_from (a
  // 3D line replaced stays 3D); a polygon mode always drapes.
  bool z_from_given = false;
};

struct PolygonAddReport {
  int64_t features = 0;
  int64_t ring_vertices = 0;  // after draping and densifying
  int64_t removed = 0;        // triangles
  int64_t added = 0;
  int64_t visible = 0;  // of the added triangles (counting the whole surface would be O(n))
  int64_t first_feature_id = 0;
  std::vector<int64_t> feature_ids;  // of the features added, in input order
  int64_t tx = 0;                    // the (last) transaction
  int64_t refinement_points = 0;
  // Edits that began from the mesh rows the edit before left in memory (db/mesh_cache.h): with
  // `each`, all but the first unless another writer came between or an edit failed.
  int64_t mesh_kept = 0;
  // Edits that read every row of the surface in one scan first (db/mesh_cache.h LoadSurface):
  // with `each` over a surface the load's points reach much of, the first edit only, while the
  // rows stay kept.
  int64_t surface_reads = 0;
  std::vector<std::string> failures;  // with `each`: "label: message" of features not added
  // Polygon features cut to the surface's data area, in input order (none with `strict`).
  std::vector<OverhangCut> clipped;
  // With `each`: "label: message" of features wholly outside the data area, skipped (a warning,
  // not a failure). Without `each` such a feature fails the call.
  std::vector<std::string> skipped;
};

// InvalidArgument naming the file, feature, ring and vertex for bad input (and for no mode);
// NotFound for an unknown surface; Corruption or IOError naming the DEM block when a ring is
// draped over a block that cannot be read (never "no elevation"); the store is unchanged on every
// error.
// With options.each, a feature that fails is listed in the report's failures and the others go
// on (the call fails only when none could be read).
// Unless options.strict, a polygon feature overhanging the surface's data area is cut to it and
// listed in the report's `clipped`; one wholly outside is InvalidArgument "<label>: lies wholly
// outside the data area ..." (with `each`: listed in `skipped`, the others go on).
Result<PolygonAddReport> AddPolygons(Store& store, const PolygonAddOptions& options);

// Removes feature `id` locally: its constraints go, the region is re-triangulated from the DEM to
// the tolerance, visibility and tags around it are recomputed. NotFound "no feature 12".
// `before_commit` as PolygonAddOptions'.
Result<PolygonAddReport> RemovePolygon(Store& store, int64_t id,
                                       const BeforeCommit& before_commit = {});

// Replaces feature `id` by the features of options.file (merged into one feature): mode, tag,
// level and (for lines, unless options.z_from_given) z_from default to the old feature's when
// options leave them empty. One transaction. Errors as
// AddPolygons and RemovePolygon; options.surface is ignored (the feature's surface is used).
Result<PolygonAddReport> UpdatePolygon(Store& store, int64_t id, const PolygonAddOptions& options);

// For db/history (revert, export --as-of): one local edit of `surface` that puts the `restore`
// features back, each under its own id (which no feature row holds), draped as AddPolygons drapes,
// and takes the features `remove` out, with one `changes` row of `action` and its feature
// versions. REQUIRES: inside a WriteTransaction the caller commits or drops. Errors as
// AddPolygons and RemovePolygon.
Result<PolygonAddReport> ApplyFeatureEdit(Store& store, const SurfaceInfo& surface,
                                          std::vector<EditorFeature> restore,
                                          const std::vector<int64_t>& remove,
                                          const std::string& action);

}  // namespace tinbase
