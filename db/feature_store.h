// FeatureStore: the `features` rows of a surface (polygons and breaklines with their mode, tag,
// level and WKB geometry), and the one definition of a surface's paint from them (docs/design.md,
// "Invariants", invariant 6): the features' modes in id order (core/tin/feature_paint), and no
// triangle visible whose centroid lies on DEM nodata (core/tin/tin_raster). The polygon editor
// writes with it, the update engine repaints with it and the integrity checker verifies with it.
// Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/polygon.h"
#include "core/geometry/polygon_locator.h"
#include "core/raster/cell_source.h"
#include "core/raster/grid.h"
#include "core/tin/block_grid.h"
#include "core/tin/feature_mode.h"
#include "core/tin/feature_paint.h"
#include "core/tin/line_elevation.h"
#include "core/tin/tin.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// A plan-view bounding box; empty (min above max) until a point is added.
struct Box {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -std::numeric_limits<double>::infinity(), max_y = max_x;
  void Add(const Point2& p) {
    min_x = std::min(min_x, p.x), min_y = std::min(min_y, p.y);
    max_x = std::max(max_x, p.x), max_y = std::max(max_y, p.y);
  }
  void Add(const Box& b) {
    if (b.empty()) return;
    Add(Point2{b.min_x, b.min_y}), Add(Point2{b.max_x, b.max_y});
  }
  bool empty() const { return !(min_x <= max_x); }
  bool Meets(const Box& b) const {
    return min_x <= b.max_x && b.min_x <= max_x && min_y <= b.max_y && b.min_y <= max_y;
  }
  bool Contains(const Point2& p) const {
    return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y;
  }
};

// A feature as the editor handles it, read from a file or from the store.
struct EditorFeature {
  int64_t id = 0;     // store id; 0 until written
  std::string label;  // "feature 12", or the source's "file.geojson, feature 3"
  FeatureMode mode = FeatureMode::kFill;
  std::optional<std::string> tag;
  std::optional<double> level;
  nlohmann::json attributes = nlohmann::json::object();
  std::vector<Polygon> polygons;
  std::vector<std::vector<Point2>> lines;
  // Mode points: survey points with their own z (db/edit/mass_points.h), kept as MultiPoint Z.
  std::vector<TinVertex> points;

  // Derived from polygons and lines on first use (BoxOf, InsideOf, RingBlocksOf) and shared by
  // later copies:
  // `--each` hands the same features from one transaction to the next, and rebuilding every
  // nearby feature's index in each would repeat the same work per feature. Hence polygons and lines
  // must not change once either has been asked for.
  mutable std::optional<Box> box_cache;
  mutable std::shared_ptr<const PolygonLocator> inside_cache;
  mutable std::shared_ptr<const std::vector<int64_t>> ring_blocks_cache;  // of ring_blocks_grid
  mutable BlockGrid ring_blocks_grid;

  // Line modes: where the lines' vertices take their z (`features.z_from`). With kFeature,
  // line_z holds each vertex's own z (line_z[k][i] for lines[k][i]); it is empty otherwise.
  ZFrom z_from = ZFrom::kDem;
  std::vector<std::vector<double>> line_z;
};

// The 3D lines of `features` (line features with z from the feature), points within `near` of
// one counting as on it (core/tin/line_elevation.h).
LineElevation LineElevationOf(const std::vector<EditorFeature>& features, double near);

// The plan-view box of the feature's rings, lines and points.
Box BoxOf(const EditorFeature& f);
// The union of the feature's polygons as a point-in-polygon index.
const std::shared_ptr<const PolygonLocator>& InsideOf(const EditorFeature& f);
// The blocks of `grid` the feature's rings come near (core/tin/ring_blocks.h BlocksNearRings).
const std::vector<int64_t>& RingBlocksOf(const EditorFeature& f, const BlockGrid& grid);

// Every feature of `surface`, in id order (the order their paint applies in). Corruption naming
// the feature when a row's mode is not one of FeatureMode's spellings; an error naming it when
// its geometry does not parse.
Result<std::vector<EditorFeature>> LoadFeatures(Store& store, const SurfaceInfo& surface);
// NotFound "surface 's' has no feature 12" when absent.
Result<EditorFeature> LoadFeature(Store& store, const SurfaceInfo& surface, int64_t id);

// Writes `f` as a new feature row of transaction `tx` (its mode in the canonical spelling,
// FeatureModeName) and sets f.id.
// REQUIRES: inside a WriteTransaction.
Status WriteFeature(Store& store, const SurfaceInfo& surface, int64_t tx, EditorFeature& f);
// The id of tag `value`, adding it to the dictionary when new. REQUIRES: a WriteTransaction.
Result<int64_t> InternTag(Store& store, const std::string& value);
// Deletes the feature row and its constraint rows. REQUIRES: inside a WriteTransaction.
Status DeleteFeature(Store& store, int64_t id);

// The paint the features give `tin` (visible and tag per triangle, replaced vertex levels),
// with every triangle whose centroid lies on nodata of `dem` hidden. Replaces tin.tags by the
// features' tag values (paint.tag indexes them). `dem` may be a window of the DEM, as long as it
// covers the triangles' centroids (a centroid off the window counts as nodata).
Paint PaintFromFeatures(const std::vector<EditorFeature>& features, const Grid* dem, Tin& tin);
// The same with the DEM streamed (db/dem_cell_source.h); the caller checks dem->status().
Paint PaintFromFeatures(const std::vector<EditorFeature>& features, CellSource* dem, Tin& tin);

// The surface of one polygon feature as paper 000 (docs/design.md, "Where the ideas come from")
// cuts it out: the triangles inside its polygons (its rings are constrained edges, so they tile
// the inside exactly; holes are left out), all visible, with their tags, neighbours re-linked
// among themselves. Reads the blocks of the feature's box only. NotFound "no feature 12";
// InvalidArgument for a breakline.
Result<LoadedSurface> LoadFeatureSurface(Store& store, int64_t feature);

// The polygons of the replace features: where invariant 7 does not apply.
std::vector<Polygon> ReplacePolygons(const std::vector<EditorFeature>& features);

}  // namespace tinbase
