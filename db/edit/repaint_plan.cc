#include "db/edit/repaint_plan.h"

#include <algorithm>
#include <optional>
#include <set>
#include <utility>

#include "core/tin/cell_cover.h"
#include "core/tin/ring_blocks.h"
#include "db/mesh/mesh_tables.h"

namespace tinbase {
namespace {

// The features as the plan sees them: which blocks rings of any feature and of the changed ones
// come near, the changed features' polygons, and whether one is clip or replace.
struct NearRings {
  RingBlocks near_any, near_changed;
  std::vector<Polygon> changed;
  bool anywhere = false, per_triangle = false;
};

NearRings NoteFeatures(const BlockGrid& g, const BlockWindow& window, const LocalEdit& edit,
                       const std::vector<EditorFeature>& removed_features) {
  NearRings near{RingBlocks(g, window), RingBlocks(g, window), {}, false, false};
  std::set<int64_t> added_ids;
  for (const EditPolyline& line : edit.add) added_ids.insert(line.feature);
  Box window_box;  // the window's blocks, grown by the margin RingBlocks tests them with
  const double reach = g.size / 2 + RingBlocks::kMargin * g.size;
  const Point2 low = near.near_any.Centre(window.bx0, window.by0);
  const Point2 high = near.near_any.Centre(window.bx1, window.by1);
  window_box.Add(Point2{low.x - reach, low.y - reach});
  window_box.Add(Point2{high.x + reach, high.y + reach});
  const auto note = [&](const EditorFeature& f, bool is_changed) {
    if (!is_changed && !BoxOf(f).Meets(window_box)) return;  // no ring of it near the window
    if (!IsPolygonMode(f.mode)) return;
    near.near_any.AddBlocks(RingBlocksOf(f, g));
    if (!is_changed) return;
    near.near_changed.AddBlocks(RingBlocksOf(f, g));
    near.changed.insert(near.changed.end(), f.polygons.begin(), f.polygons.end());
    near.anywhere |= f.mode == FeatureMode::kClip;
    near.per_triangle |= f.mode == FeatureMode::kReplace;
  };
  for (const EditorFeature& f : edit.features) note(f, added_ids.count(f.id) > 0);
  for (const EditorFeature& f : removed_features) note(f, true);
  return near;
}

// Sorts the window's blocks into uniform ones (plan.uniform_blocks, their centres in `centres`)
// and runs of mixed ones, whose triangles it reads into plan.around; returns the mixed blocks'
// box.
Result<Box> SortBlocks(const EditContext& ctx, const BlockWindow& window, const NearRings& near,
                       RepaintPlan& plan, Tin& centres) {
  const BlockGrid& g = ctx.surface.blocks;
  const double reach = g.size / 2 + RingBlocks::kMargin * g.size;
  const Point2 low = near.near_any.Centre(window.bx0, window.by0);
  const Point2 high = near.near_any.Centre(window.bx1, window.by1);
  // The DEM under the window, for the data test of whole blocks; read only if one may be.
  std::optional<Grid> window_dem;
  const auto on_data = [&](const Point2& c) -> Result<bool> {
    if (!window_dem) {
      const double cell = ctx.Cell();
      TB_ASSIGN_OR_RETURN(
          window_dem,
          ctx.dems.ReadWindow(ctx.dem, {low.x - g.size - cell, low.y - g.size - cell,
                                        high.x + g.size + cell, high.y + g.size + cell}));
    }
    return BoxOnData(*window_dem, c.x - reach, c.y - reach, c.x + reach, c.y + reach);
  };
  Box mixed_box;
  for (int64_t by = window.by0; by <= window.by1; ++by) {
    int64_t run = -1;  // first block of the current run of mixed blocks in this row
    for (int64_t bx = window.bx0; bx <= window.bx1 + 1; ++bx) {
      bool mixed = false;
      if (bx <= window.bx1) {
        const Point2 c = near.near_any.Centre(bx, by);
        const bool may_change = near.anywhere || near.near_changed.Near(bx, by) ||
                                plan.changed_inside->Locate(c) != PointInPolygon::kOutside;
        bool uniform = may_change && !near.per_triangle && !near.near_any.Near(bx, by);
        if (uniform) {
          TB_ASSIGN_OR_RETURN(uniform, on_data(c));
        }
        if (uniform) {
          plan.uniform_blocks.push_back(BlockGrid::Pack(bx, by));
          const uint32_t v = static_cast<uint32_t>(centres.vertices.size());
          centres.vertices.push_back({c.x, c.y, 0});
          centres.triangles.push_back(TinTriangle{{v, v, v}});
        } else {
          mixed = may_change;
        }
      }
      if (mixed && run < 0) run = bx;
      if (!mixed && run >= 0) {
        TB_RETURN_IF_ERROR(ctx.mesh.TrianglesInBlocks(by, run, bx - 1, &plan.around));
        // The paint of these triangles reads the DEM at their centroids, which lie in these
        // blocks.
        mixed_box.Add(Point2{g.origin_x + static_cast<double>(run) * g.size,
                             g.origin_y + static_cast<double>(by) * g.size});
        mixed_box.Add(Point2{g.origin_x + static_cast<double>(bx) * g.size,
                             g.origin_y + static_cast<double>(by + 1) * g.size});
        run = -1;
      }
    }
  }
  return mixed_box;
}

}  // namespace

Result<RepaintPlan> PlanRepaint(const EditContext& ctx, const LocalEdit& edit,
                                const std::vector<EditorFeature>& removed_features) {
  RepaintPlan plan;
  if (edit.changed.empty()) return plan;
  const BlockGrid& g = ctx.surface.blocks;
  const BlockWindow window{g.ColumnOf(edit.changed.min_x), g.RowOf(edit.changed.min_y),
                           g.ColumnOf(edit.changed.max_x), g.RowOf(edit.changed.max_y)};
  NearRings near = NoteFeatures(g, window, edit, removed_features);
  plan.changed_inside = std::make_shared<const PolygonLocator>(near.changed);
  plan.outside_keeps_paint = !near.anywhere && !near.per_triangle;
  Tin centres;  // one point-like triangle per uniform block, at its centre
  TB_ASSIGN_OR_RETURN(const Box mixed_box, SortBlocks(ctx, window, near, plan, centres));
  if (!plan.uniform_blocks.empty()) {
    plan.uniform_paint =
        PaintFromFeatures(edit.features, static_cast<const Grid*>(nullptr), centres);
    plan.uniform_tags = std::move(centres.tags);
  }
  plan.paint_box = edit.changed;
  plan.paint_box.Add(mixed_box);
  return plan;
}

RepaintPlan WholeSurfaceRepaintPlan(const LocalEdit& edit) {
  RepaintPlan plan;
  plan.paint_box = edit.changed;
  return plan;
}

Result<std::vector<TriangleRepaint>> UniformBlockRepaints(
    const EditContext& ctx, const RepaintPlan& plan, const std::unordered_set<int64_t>& deleted,
    const MeshDelta& delta) {
  std::vector<TriangleRepaint> repaints;
  const std::vector<int64_t>& blocks = plan.uniform_blocks;
  if (blocks.empty()) return repaints;
  // Every tag id bound later is interned here, in this transaction (triangles.tag is not a
  // declared foreign key: migration 0009).
  std::vector<std::optional<int64_t>> tag_of_block;
  {
    std::vector<int64_t> tag_ids;
    for (const std::string& value : plan.uniform_tags) {
      TB_ASSIGN_OR_RETURN(int64_t id, InternTag(ctx.store, value));
      tag_ids.push_back(id);
    }
    for (int32_t tag : plan.uniform_paint.tag)
      tag_of_block.push_back(tag == kNoTag ? std::nullopt : std::optional<int64_t>(tag_ids[tag]));
  }
  const auto paint = [&](int64_t id, size_t k) {
    return TriangleRepaint{id, plan.uniform_paint.visible[k] != 0, tag_of_block[k]};
  };
  // The block index holds the ids (it covers the query). A run of consecutive blocks is one range
  // of the index; block k of it is blocks[k].
  MeshTables tables(ctx.store.db(), ctx.surface);
  for (size_t first = 0; first < blocks.size();) {
    size_t last = first;
    while (last + 1 < blocks.size() && blocks[last + 1] == blocks[last] + 1) ++last;
    TB_ASSIGN_OR_RETURN(const auto rows, tables.TriangleIdsAndBlocks(blocks[first], blocks[last]));
    for (const auto& [id, block] : rows) {
      if (deleted.count(id)) continue;
      repaints.push_back(paint(id, first + static_cast<size_t>(block - blocks[first])));
    }
    first = last + 1;
  }
  // The edit's new triangles whose block is uniform (their ids follow every stored one).
  for (size_t k = 0; k < delta.new_triangles.size(); ++k) {
    const auto it = std::lower_bound(blocks.begin(), blocks.end(), delta.new_triangles[k].block);
    if (it == blocks.end() || *it != delta.new_triangles[k].block) continue;
    repaints.push_back(paint(delta.first_triangle + static_cast<int64_t>(k),
                             static_cast<size_t>(it - blocks.begin())));
  }
  std::sort(
      repaints.begin(), repaints.end(),
      [](const TriangleRepaint& a, const TriangleRepaint& b) { return a.triangle < b.triangle; });
  return repaints;
}

}  // namespace tinbase
