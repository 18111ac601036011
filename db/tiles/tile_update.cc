// Tile pyramid updates: UpdateTilePyramid and UpdateAllTilePyramids of tile_pyramid.h.
//
// An update reads only the window of the surface that the finest tiles meeting the changes
// need (db/tiles/tile_window.h), so its cost follows the edit, not the surface. Whether the edit
// moved the surface's height range (which changes every tile) is told from the two vertices the
// pyramid recorded at the ends of the range and from the window: every vertex an edit adds,
// moves or removes lies inside the change's region, so outside it the old extremes still hold.
#include <algorithm>
#include <chrono>
#include <map>
#include <set>

#include "core/geometry/reproject.h"
#include "core/tiles/level_surfaces.h"
#include "db/change_log.h"
#include "db/mesh/mesh_tables.h"
#include "db/sql/settled_change.h"
#include "db/tiles/pyramid_levels.h"
#include "db/tiles/tile_pyramid.h"
#include "db/tiles/tile_window.h"
#include "db/tiles/tile_write_scope.h"

namespace tinbase {

namespace {

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The options a pyramid was built with, from its row.
Result<TileBuildOptions> OptionsOf(const TilePyramidInfo& pyramid) {
  TileBuildOptions options;
  options.max_zoom = pyramid.max_zoom;
  TB_ASSIGN_OR_RETURN(options.extensions, ParseTileExtensions(pyramid.extensions));
  options.water_tag = pyramid.water_tag;
  return options;
}

// The longitude/latitude box of the union of the changes' regions (store CRS), its edges
// densified so a curved image of a straight edge stays inside, grown by a hair for round-off.
Result<TileRect> ChangedRegion(const std::vector<Change>& changes, const Crs& crs) {
  TB_ASSIGN_OR_RETURN(Crs wgs84, Crs::FromUserInput("EPSG:4326"));
  std::vector<TinVertex> ring;
  constexpr int kSteps = 16;
  for (const Change& c : changes)
    for (int i = 0; i <= kSteps; ++i) {
      const double t = static_cast<double>(i) / kSteps;
      const double x = c.min_x + t * (c.max_x - c.min_x);
      const double y = c.min_y + t * (c.max_y - c.min_y);
      for (const auto& [px, py] : {std::pair{x, c.min_y}, std::pair{x, c.max_y},
                                   std::pair{c.min_x, y}, std::pair{c.max_x, y}})
        ring.push_back({px, py, 0, VertexKind::kDem});
    }
  TB_RETURN_IF_ERROR(ReprojectXy(crs, wgs84, ring));
  TileRect box{180, 90, -180, -90};
  for (const TinVertex& v : ring) {
    box.west = std::min(box.west, v.x), box.east = std::max(box.east, v.x);
    box.south = std::min(box.south, v.y), box.north = std::max(box.north, v.y);
  }
  constexpr double kHair = 1e-6;  // degrees, about 0.1 m
  box.west -= kHair, box.south -= kHair, box.east += kHair, box.north += kHair;
  return box;
}

// `region` grown to every triangle around a vertex of a triangle that meets it: with normals, a
// vertex's normal is summed over the triangles around it, so a change moves the normals of its
// triangles' vertices, and every tile those vertices' triangles reach changes.
Result<TileRect> WithVertexStars(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                 const TileRect& region, int level) {
  TB_ASSIGN_OR_RETURN(const TileWindow window, ReadTileWindow(store, surface, crs, region, level));
  TB_ASSIGN_OR_RETURN(const GeoSurface geo,
                      GeographicSurface(window.tin, crs, /*normals=*/false, 0, 1));
  TileRect out = region;
  for (const TinVertex& v : geo.tin.vertices) {
    out.west = std::min(out.west, v.x), out.east = std::max(out.east, v.x);
    out.south = std::min(out.south, v.y), out.north = std::max(out.north, v.y);
  }
  return out;
}

bool Meets(const TileRect& a, const TileRect& b) {
  return a.west <= b.east && b.west <= a.east && a.south <= b.north && b.south <= a.north;
}

// The surface's height extremes now: from the pyramid's recorded extreme vertices and the
// window when those vertices still hold the old range, else from every vertex.
Result<HeightExtremes> CurrentExtremes(Store& store, const SurfaceInfo& surface, const Crs& crs,
                                       const TilePyramidInfo& old, const TileWindow& window) {
  if (old.min_vertex && old.max_vertex) {
    MeshTables tables(store.db(), surface);
    Result<VertexRow> lo = tables.Vertex(*old.min_vertex);
    Result<VertexRow> hi = tables.Vertex(*old.max_vertex);
    const double metres = crs.VerticalMetresPerUnit();
    if (lo.ok() && hi.ok() &&
        QuantisationRange(lo->z * metres, hi->z * metres) ==
            std::pair{old.min_height, old.max_height}) {
      LoadedSurface ends;
      ends.tin.vertices = {*lo, *hi};
      ends.vertex_ids = {*old.min_vertex, *old.max_vertex};
      if (window.min_z < lo->z) ends.tin.vertices[0].z = window.min_z, ends.vertex_ids[0] = 0;
      if (window.max_z > hi->z) ends.tin.vertices[1].z = window.max_z, ends.vertex_ids[1] = 0;
      // A vertex id of 0 means the range moved: the rebuild then records the real ones.
      return ExtremesOf(ends, crs);
    }
    if (!lo.ok() && lo.status().code() != StatusCode::kNotFound) return lo.status();
    if (!hi.ok() && hi.status().code() != StatusCode::kNotFound) return hi.status();
  }
  TB_ASSIGN_OR_RETURN(const SurfaceSummary summary,
                      Summarise(store, surface, crs, /*geographic=*/false));
  return summary.extremes;
}

// What an update computed before it writes.
struct UpdatePlan {
  PyramidInputs in;
  bool full_rebuild = false;
  std::set<TileKey> keys;   // every tile key of the pyramid before the update
  std::set<TileKey> stale;  // those whose bounds meet the changes
  std::vector<LevelTiles> levels;
  double read_seconds = 0;
  double make_seconds = 0;
};

// `mark`: the transaction the pyramid records as shown once the update is written.
Result<UpdatePlan> PlanUpdate(Store& store, const SurfaceInfo& surface, const TilePyramidInfo& old,
                              const TileBuildOptions& options, const std::vector<Change>& changes,
                              int64_t mark, const Crs& crs) {
  const auto start = std::chrono::steady_clock::now();
  TB_ASSIGN_OR_RETURN(auto snapshot, SnapshotUnlessInTransaction(store));
  TileStore tiles(store.db());
  UpdatePlan plan;
  plan.in.pyramid = old;
  plan.in.pyramid.tx = mark;
  plan.in.base_error = surface.tolerance.value_or(1.0);
  TB_ASSIGN_OR_RETURN(TileRect region, ChangedRegion(changes, crs));
  if (options.extensions.normals) {
    TB_ASSIGN_OR_RETURN(region, WithVertexStars(store, surface, crs, region, old.max_zoom));
  }
  const TileRange range =
      TilesMeeting(old.max_zoom, region.west, region.south, region.east, region.north);
  TileWindow window;
  if (!range.empty()) {
    TB_ASSIGN_OR_RETURN(window,
                        ReadTileWindow(store, surface, crs, RectOfRange(range), old.max_zoom));
  }
  TB_ASSIGN_OR_RETURN(const HeightExtremes extremes,
                      CurrentExtremes(store, surface, crs, old, window));
  if (extremes.min != old.min_height || extremes.max != old.max_height) {
    plan.full_rebuild = true;
    return plan;
  }
  plan.in.pyramid.min_vertex = extremes.min_vertex;
  plan.in.pyramid.max_vertex = extremes.max_vertex;
  plan.in.water_tag = TagIndex(window.tin, options.water_tag);
  TB_ASSIGN_OR_RETURN(plan.in.finest, GeographicSurface(window.tin, crs, options.extensions.normals,
                                                        old.min_height, old.max_height));
  const auto wanted = [&](const TileKey& key) { return Meets(RectOf(key), region); };
  TB_ASSIGN_OR_RETURN(plan.keys, tiles.Keys(surface.id));
  for (const TileKey& key : plan.keys)
    if (wanted(key)) plan.stale.insert(key);
  plan.read_seconds = SecondsSince(start);
  const auto made = std::chrono::steady_clock::now();
  // Unchanged children of the tiles made again are read from the store, decoded once.
  StoredTiles stored(tiles, surface.id);
  plan.levels = NonEmpty(MakeLevels(
                             plan.in, options, wanted, plan.stale,
                             [&](const TileKey& key) { return stored.Get(key); }, 0),
                         plan.in);
  TB_RETURN_IF_ERROR(stored.error());
  plan.make_seconds = SecondsSince(made);
  return plan;
}

Status WriteUpdate(Store& store, const SurfaceInfo& surface, const TilePyramidInfo& old,
                   const TileBuildOptions& options, UpdatePlan& plan, TileUpdateReport* report) {
  TileStore tiles(store.db());
  std::set<TileKey> keys = plan.keys;
  for (const TileKey& key : plan.stale) keys.erase(key);
  for (const LevelTiles& level : plan.levels)
    for (const auto& [key, mesh] : level.meshes) keys.insert(key);

  TB_ASSIGN_OR_RETURN(TileWriteScope tx, TileWriteScope::Begin(store));
  for (const TileKey& key : plan.stale) {
    bool remade = false;
    for (const LevelTiles& level : plan.levels) remade = remade || level.meshes.count(key) > 0;
    if (remade) continue;
    TB_RETURN_IF_ERROR(tiles.DeleteTile(surface.id, key));
    ++report->tiles_deleted;
  }
  std::set<TileKey> meeting = plan.stale;
  for (LevelTiles& level : plan.levels)
    for (auto& [key, mesh] : level.meshes) {
      if (options.extensions.metadata && key.level % kMetadataAvailability == 0)
        mesh.metadata = MetadataOf(keys, key);
      TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(mesh));
      TB_RETURN_IF_ERROR(tiles.PutTile(surface.id, key, bytes, plan.in.pyramid.tx));
      ++report->tiles_rewritten;
      meeting.insert(key);
    }
  TB_RETURN_IF_ERROR(tiles.SetPyramidTx(surface.id, plan.in.pyramid.tx));
  const TilePyramidInfo& now = plan.in.pyramid;
  if (now.min_vertex != old.min_vertex || now.max_vertex != old.max_vertex)
    TB_RETURN_IF_ERROR(tiles.SetHeightVertices(surface.id, *now.min_vertex, *now.max_vertex));
  TB_RETURN_IF_ERROR(tx.Commit());
  report->tiles_meeting = static_cast<int64_t>(meeting.size());
  return Status::Ok();
}

}  // namespace

Result<TileUpdateReport> UpdateTilePyramid(Store& store, const SurfaceInfo& surface) {
  TileStore tiles(store.db());
  TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> old, tiles.Pyramid(surface.id));
  if (!old)
    return Status::InvalidArgument("surface '" + surface.name +
                                   "' has no tiles to update (run tinbase tiles build first)");
  TileUpdateReport report;
  report.since_tx = report.tx = old->tx;
  // Every change seen is applied, but the pyramid records only how far they are settled
  // (change_log.h): a change that commits later below one applied here is applied next time,
  // with those above it again.
  TB_ASSIGN_OR_RETURN(const int64_t settled, SettledChange(store.db()));
  TB_ASSIGN_OR_RETURN(const std::vector<Change> all, ChangesSince(store, old->tx));
  const int64_t mark = SettledThrough(old->tx, all, settled);
  std::vector<Change> changes;
  for (const Change& c : all)
    if (c.surface == surface.id) changes.push_back(c);
  report.changes = static_cast<int64_t>(changes.size());
  if (changes.empty()) return report;

  TB_ASSIGN_OR_RETURN(const TileBuildOptions options, OptionsOf(*old));
  TB_ASSIGN_OR_RETURN(const std::optional<Crs> crs, store.GetCrs());
  if (!crs) return Status::InvalidArgument("the store has no CRS: its tiles cannot be updated");
  TB_ASSIGN_OR_RETURN(UpdatePlan plan,
                      PlanUpdate(store, surface, *old, options, changes, mark, *crs));
  report.tx = plan.in.pyramid.tx;
  if (plan.full_rebuild) {
    TB_ASSIGN_OR_RETURN(const TileBuildReport rebuilt, BuildTilePyramid(store, surface, options));
    report.tx = rebuilt.pyramid.tx;
    report.full_rebuild = true;
    for (const TileLevelReport& l : rebuilt.levels) report.tiles_rewritten += l.tiles;
    return report;
  }
  report.read_seconds = plan.read_seconds;
  report.make_seconds = plan.make_seconds;
  const auto written = std::chrono::steady_clock::now();
  TB_RETURN_IF_ERROR(WriteUpdate(store, surface, *old, options, plan, &report));
  report.write_seconds = SecondsSince(written);
  return report;
}

Result<std::vector<std::pair<SurfaceInfo, TileUpdateReport>>> UpdateAllTilePyramids(Store& store) {
  TB_ASSIGN_OR_RETURN(const std::vector<SurfaceInfo> surfaces, SurfaceStore(store).List());
  std::vector<std::pair<SurfaceInfo, TileUpdateReport>> out;
  TileStore tiles(store.db());
  for (const SurfaceInfo& surface : surfaces) {
    TB_ASSIGN_OR_RETURN(const std::optional<TilePyramidInfo> pyramid, tiles.Pyramid(surface.id));
    if (!pyramid) continue;
    TB_ASSIGN_OR_RETURN(TileUpdateReport report, UpdateTilePyramid(store, surface));
    out.emplace_back(surface, report);
  }
  return out;
}

}  // namespace tinbase
