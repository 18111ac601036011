#include "db/edit/resurvey.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/tin/tin_raster.h"
#include "db/change_log.h"
#include "db/edit/update_engine.h"
#include "db/feature_store.h"
#include "db/surface_store.h"

namespace tinbase {

namespace {

// Cells flagged on a window of the DEM, grown by one cell (a flagged cell's neighbours enter the
// bilinear z of any point within a cell of it), with a summed-area table to ask whether a range
// of cells holds one.
class FlaggedCells {
 public:
  FlaggedCells(const GridGeometry& g, const std::vector<uint8_t>& flags) : g_(g) {
    const int64_t w = g.width, h = g.height;
    std::vector<uint8_t> grown(flags.size(), 0);
    for (int64_t r = 0; r < h; ++r)
      for (int64_t c = 0; c < w; ++c) {
        if (!flags[static_cast<size_t>(r * w + c)]) continue;
        for (int64_t rr = std::max<int64_t>(r - 1, 0); rr <= std::min(r + 1, h - 1); ++rr)
          for (int64_t cc = std::max<int64_t>(c - 1, 0); cc <= std::min(c + 1, w - 1); ++cc)
            grown[static_cast<size_t>(rr * w + cc)] = 1;
      }
    sums_.assign(static_cast<size_t>((w + 1) * (h + 1)), 0);
    for (int64_t r = 0; r < h; ++r)
      for (int64_t c = 0; c < w; ++c)
        sums_[Index(c + 1, r + 1)] = grown[static_cast<size_t>(r * w + c)] +
                                     sums_[Index(c, r + 1)] + sums_[Index(c + 1, r)] -
                                     sums_[Index(c, r)];
    grown_ = std::move(grown);
  }

  // Whether a grown flagged cell's footprint meets the box [x0, x1] x [y0, y1].
  bool Meets(double x0, double y0, double x1, double y1) const {
    const double ca = (x0 - g_.origin_x) / g_.cell_x, cb = (x1 - g_.origin_x) / g_.cell_x;
    const double ra = (y0 - g_.origin_y) / g_.cell_y, rb = (y1 - g_.origin_y) / g_.cell_y;
    // A box edge on a cell edge meets both cells: the footprints are closed.
    const int64_t c0 = std::max<int64_t>(static_cast<int64_t>(std::ceil(std::min(ca, cb))) - 1, 0);
    const int64_t c1 =
        std::min<int64_t>(static_cast<int64_t>(std::floor(std::max(ca, cb))), g_.width - 1);
    const int64_t r0 = std::max<int64_t>(static_cast<int64_t>(std::ceil(std::min(ra, rb))) - 1, 0);
    const int64_t r1 =
        std::min<int64_t>(static_cast<int64_t>(std::floor(std::max(ra, rb))), g_.height - 1);
    if (c0 > c1 || r0 > r1) return false;
    const int64_t n = sums_[Index(c1 + 1, r1 + 1)] - sums_[Index(c0, r1 + 1)] -
                      sums_[Index(c1 + 1, r0)] + sums_[Index(c0, r0)];
    return n > 0;
  }

  // The grown cells' footprints as boxes: runs along each row, a run repeated on the next rows
  // merged into one box.
  std::vector<Box> Boxes() const {
    std::vector<Box> out;
    std::vector<std::pair<std::pair<int64_t, int64_t>, size_t>> open, next;
    for (int64_t r = 0; r < g_.height; ++r) {
      next.clear();
      for (int64_t c = 0; c < g_.width;) {
        if (!grown_[static_cast<size_t>(r * g_.width + c)]) {
          ++c;
          continue;
        }
        const int64_t c0 = c;
        while (c < g_.width && grown_[static_cast<size_t>(r * g_.width + c)]) ++c;
        const std::pair<int64_t, int64_t> run{c0, c};
        Box cells;
        cells.Add(Point2{g_.origin_x + static_cast<double>(c0) * g_.cell_x,
                         g_.origin_y + static_cast<double>(r) * g_.cell_y});
        cells.Add(Point2{g_.origin_x + static_cast<double>(c) * g_.cell_x,
                         g_.origin_y + static_cast<double>(r + 1) * g_.cell_y});
        auto above =
            std::find_if(open.begin(), open.end(), [&](const auto& o) { return o.first == run; });
        if (above != open.end()) {
          out[above->second].Add(cells);
          next.push_back(*above);
        } else {
          out.push_back(cells);
          next.push_back({run, out.size() - 1});
        }
      }
      std::swap(open, next);
    }
    return out;
  }

 private:
  size_t Index(int64_t c, int64_t r) const { return static_cast<size_t>(r * (g_.width + 1) + c); }

  GridGeometry g_;
  std::vector<uint8_t> grown_;
  std::vector<int64_t> sums_;
};

// The cells of `window` (new DEM cells) that `tin` misses by more than `tolerance`; cells the
// surface does not cover (its outer half cell) and nodata cells are not compared.
std::vector<uint8_t> MissedCells(const Tin& tin, const Grid& window, double tolerance,
                                 int64_t* missed) {
  const std::vector<float> z = RasteriseTin(tin, window.geometry);
  std::vector<uint8_t> flags(window.cells.size(), 0);
  for (size_t i = 0; i < flags.size(); ++i) {
    if (std::isnan(window.cells[i]) || std::isnan(z[i])) continue;
    if (std::fabs(static_cast<double>(z[i]) - window.cells[i]) <= tolerance) continue;
    flags[i] = 1;
    ++*missed;
  }
  return flags;
}

Box BoxOfDemBox(const DemBox& b) {
  Box box;
  box.Add(Point2{b.min_x, b.min_y});
  box.Add(Point2{b.max_x, b.max_y});
  return box;
}

// The extent of the surface's vertices: for a surface built on the DEM, the rectangle of the
// cell centres the DEM had then (a later import may have grown the grid beyond it).
Box ExtentOf(const Tin& tin) {
  Box box;
  for (const TinVertex& v : tin.vertices) box.Add(Point2{v.x, v.y});
  return box;
}

// InvalidArgument when a flagged cell of `window` lies within a cell of the surface's outer edge
// (`extent`, the centres of the outer rows and columns of the grid it was built on): a local
// edit keeps the boundary's edges (R's outline) and cannot refine along them, so the new cells
// there could not be met. Flagged cells are those the surface covers, so none lies beyond it.
Status RefuseBoundaryCells(const DemInfo& dem, const Box& extent, const Grid& window,
                           const std::vector<uint8_t>& flags) {
  const GridGeometry& g = dem.geometry;
  const GridGeometry& w = window.geometry;
  // Centres two cells in from the edge are kept; half a cell of slack absorbs rounding.
  const double reach_x = 1.5 * g.cell_x, reach_y = 1.5 * std::fabs(g.cell_y);
  const auto col0 = std::llround((w.origin_x - g.origin_x) / g.cell_x);
  const auto row0 = std::llround((w.origin_y - g.origin_y) / g.cell_y);
  for (int64_t r = 0; r < w.height; ++r)
    for (int64_t c = 0; c < w.width; ++c) {
      if (!flags[static_cast<size_t>(r * w.width + c)]) continue;
      const double x = w.CellCenterX(c), y = w.CellCenterY(r);
      if (x - extent.min_x > reach_x && extent.max_x - x > reach_x && y - extent.min_y > reach_y &&
          extent.max_y - y > reach_y)
        continue;
      return Status::InvalidArgument(
          "the new cell at column " + std::to_string(col0 + c) + ", row " +
          std::to_string(row0 + r) + " of DEM '" + dem.name +
          "' lies by the surface's boundary and differs from it by more than its tolerance; a "
          "local update cannot refine along the boundary: build the surface again");
    }
  return Status::Ok();
}

// One surface brought up to date with the cells of `written` (inside the import's transaction).
Result<SurfaceResurvey> ResurveySurface(Store& store, DemStore& dems, const DemInfo& dem,
                                        const SurfaceInfo& surface, const DemBox& written) {
  SurfaceResurvey out;
  out.surface = surface.name;
  TB_ASSIGN_OR_RETURN(LoadedSurface loaded, SurfaceStore(store).Load(surface));
  TB_ASSIGN_OR_RETURN(Grid window, dems.ReadWindow(dem, written, 0));
  const std::vector<uint8_t> flags =
      MissedCells(loaded.tin, window, surface.tolerance.value_or(1.0), &out.cells_missed);
  TB_RETURN_IF_ERROR(RefuseBoundaryCells(dem, ExtentOf(loaded.tin), window, flags));
  const FlaggedCells flagged(window.geometry, flags);
  LocalEdit edit;
  for (size_t t = 0; t < loaded.tin.triangles.size(); ++t) {
    Box box;
    for (uint32_t v : loaded.tin.triangles[t].v)
      box.Add(Point2{loaded.tin.vertices[v].x, loaded.tin.vertices[v].y});
    if (flagged.Meets(box.min_x, box.min_y, box.max_x, box.max_y))
      edit.seed.push_back(loaded.triangle_ids[t]);
  }
  out.seeded = static_cast<int64_t>(edit.seed.size());
  edit.resample = flagged.Boxes();
  TB_ASSIGN_OR_RETURN(edit.features, LoadFeatures(store, surface));
  // Paint over every block written: a cell that became nodata (or data) hides (or shows) the
  // triangles whose centroid it holds.
  edit.changed = BoxOfDemBox(written);
  UpdateEngine engine(store, surface, dems, dem);
  TB_ASSIGN_OR_RETURN(EditResult result, engine.Apply(edit));
  out.removed = result.removed;
  out.added = result.added;
  out.refinement_points = result.refinement_points;
  out.whole_surface = result.whole_surface;
  Box changed = edit.changed;
  changed.Add(result.region);
  Change change;
  change.surface = surface.id;
  change.action = "dem resurvey";
  change.removed = result.removed;
  change.added = result.added;
  change.min_x = changed.min_x, change.min_y = changed.min_y;
  change.max_x = changed.max_x, change.max_y = changed.max_y;
  TB_ASSIGN_OR_RETURN(out.tx, AppendChange(store, change));
  return out;
}

}  // namespace

Result<ResurveyReport> ImportUnderSurfaces(Store& store, const std::vector<std::string>& files,
                                           DemImportOptions options) {
  DemStore dems(store);
  ResurveyReport out;
  options.under_surfaces = [&](const DemImportReport& imported) -> Status {
    TB_ASSIGN_OR_RETURN(std::vector<SurfaceInfo> all, SurfaceStore(store).List());
    std::vector<SurfaceInfo> on_dem;
    for (const SurfaceInfo& s : all)
      if (s.dem == imported.dem.id) on_dem.push_back(s);
    if (on_dem.empty() || imported.written.min_x >= imported.written.max_x) return Status::Ok();
    // A grown grid keeps the old cells where they were (whole cells added around them), so the
    // surfaces stay where they are: their cells are compared, the new ones beyond them only
    // stored (a surface's hull does not grow; build it again to cover them).
    for (const SurfaceInfo& s : on_dem) {
      auto one = ResurveySurface(store, dems, imported.dem, s, imported.written);
      if (!one.ok()) return one.status().WithContext("surface '" + s.name + "'");
      out.surfaces.push_back(std::move(*one));
    }
    return Status::Ok();
  };
  TB_ASSIGN_OR_RETURN(out.import, dems.Import(files, options));
  return out;
}

}  // namespace tinbase
