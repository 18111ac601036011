#include "core/tin/split_refinement.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "core/raster/cell_source.h"
#include "core/tin/tolerance_refiner.h"

namespace tinbase {
namespace {

// Below this many cells a build takes milliseconds and the seam's vertices (two at least, its
// ends) weigh more than the time saved.
constexpr int64_t kMinCellsToSplit = 128 * 128;

// The seam is column `at` (vertical) or row `at`; position t along it is row or column t.
struct Seam {
  bool vertical = true;
  int64_t at = 0;
  int64_t length = 0;

  std::pair<int64_t, int64_t> CellAt(int64_t t) const {
    return vertical ? std::pair{at, t} : std::pair{t, at};
  }
};

TinVertex VertexAt(const GridGeometry& g, int64_t col, int64_t row, double z) {
  return TinVertex{g.CellCenterX(col), g.CellCenterY(row), z, VertexKind::kDem};
}

// The seam's cells approximated alone: its two ends (z from boundary_z) and, while a valid cell
// is beyond the tolerance from the linear interpolation between chosen neighbours, the worst
// such cell. The segments are independent, so splitting depth first picks the same cells as
// worst-first order would. Returns the chain's vertices in order along the seam.
std::vector<TinVertex> SeamChain(const Grid& dem, const Seam& seam, double tolerance,
                                 const BoundaryElevationFn& boundary_z) {
  // The line's cells copied once: a column is a stride through the grid, read at every depth.
  std::vector<double> value(static_cast<size_t>(seam.length));
  for (int64_t t = 0; t < seam.length; ++t) {
    const auto [c, r] = seam.CellAt(t);
    value[static_cast<size_t>(t)] = static_cast<double>(dem.At(c, r));
  }
  const int64_t last = seam.length - 1;
  std::vector<double> z(static_cast<size_t>(seam.length), std::nan(""));
  z[0] = boundary_z(seam.CellAt(0).first, seam.CellAt(0).second);
  z[last] = boundary_z(seam.CellAt(last).first, seam.CellAt(last).second);
  std::vector<std::pair<int64_t, int64_t>> segments{{0, last}};
  while (!segments.empty()) {
    const auto [i, j] = segments.back();
    segments.pop_back();
    double worst = tolerance;
    int64_t worst_t = -1;
    for (int64_t t = i + 1; t < j; ++t) {
      const double v = value[static_cast<size_t>(t)];
      if (std::isnan(v)) continue;
      const double error = std::fabs(
          z[i] + (z[j] - z[i]) * static_cast<double>(t - i) / static_cast<double>(j - i) - v);
      if (error > worst) worst = error, worst_t = t;
    }
    if (worst_t < 0) continue;
    z[worst_t] = value[static_cast<size_t>(worst_t)];
    segments.insert(segments.end(), {{i, worst_t}, {worst_t, j}});
  }
  std::vector<TinVertex> chain;
  for (int64_t t = 0; t <= last; ++t) {
    if (std::isnan(z[t])) continue;
    const auto [c, r] = seam.CellAt(t);
    chain.push_back(VertexAt(dem.geometry, c, r, z[t]));
  }
  return chain;
}

// The line that splits the refinement's work evenly, estimated from kBalanceSamples lines, one
// in the middle of each of as many equal strips across the grid. The vertices a strip ends with
// are taken as proportional to its line's chain length (the breaks the line needs). Measured
// against where the median vertex of a one-thread build lies, that is within 1-2 % of the width
// on SRTM and generated terrain, at 0.5-5 m; the square of the length (density from the breaks of
// one line taken as isotropic) overweights rough strips: on SRTM N43E007's 1025^2 window at
// 0.5 m it put the line at column 278 where the median lies at 391, and the seam chosen near it
// (column 318) left the eastern half with 1.37x the western's vertices.
constexpr int kBalanceSamples = 32;

int64_t BalanceLine(const Grid& dem, bool vertical, double tolerance,
                    const BoundaryElevationFn& boundary_z) {
  const GridGeometry& g = dem.geometry;
  const int64_t across = vertical ? g.width : g.height, length = vertical ? g.height : g.width;
  const int samples = static_cast<int>(std::min<int64_t>(kBalanceSamples, across));
  std::vector<double> weight(static_cast<size_t>(samples));
  double total = 0;
  for (int i = 0; i < samples; ++i) {
    const Seam line{vertical, (2 * i + 1) * across / (2 * samples), length};
    total += weight[static_cast<size_t>(i)] =
        static_cast<double>(SeamChain(dem, line, tolerance, boundary_z).size());
  }
  // Positions in cell widths from the grid's first edge: strip i spans [i, i + 1) * width.
  const double width = static_cast<double>(across) / samples;
  double below = 0, at = static_cast<double>(across) / 2;
  for (int i = 0; i < samples && total > 0; ++i) {
    const double w = weight[static_cast<size_t>(i)];
    if (below + w >= total / 2) {
      at = (i + (total / 2 - below) / w) * width;
      break;
    }
    below += w;
  }
  return std::clamp<int64_t>(static_cast<int64_t>(std::floor(at)), 1, across - 2);
}

// ChooseSeam's line and its chain.
std::pair<Seam, std::vector<TinVertex>> ShortestSeamNearBalance(
    const Grid& dem, double tolerance, const BoundaryElevationFn& boundary_z) {
  const GridGeometry& g = dem.geometry;
  const bool vertical = g.width >= g.height;
  const int64_t across = vertical ? g.width : g.height;
  const int64_t balance = BalanceLine(dem, vertical, tolerance, boundary_z);
  const int64_t reach = across / 50, step = std::max<int64_t>(1, across / 200);
  Seam best{vertical, balance, vertical ? g.height : g.width};
  std::vector<TinVertex> best_chain = SeamChain(dem, best, tolerance, boundary_z);
  for (int64_t offset = step; offset <= reach; offset += step) {
    for (const int64_t at : {balance - offset, balance + offset}) {
      if (at < 1 || at > across - 2) continue;
      const Seam seam{vertical, at, best.length};
      std::vector<TinVertex> chain = SeamChain(dem, seam, tolerance, boundary_z);
      if (chain.size() < best_chain.size()) best = seam, best_chain = std::move(chain);
    }
  }
  return {best, std::move(best_chain)};
}

// Half `side` (0: columns or rows up to the seam, 1: from it) before refinement: its two
// corners away from the seam, then the seam chain.
Cdt StartHalf(const GridGeometry& g, const Seam& seam, int side,
              const std::vector<TinVertex>& chain, const BoundaryElevationFn& boundary_z) {
  const int64_t far = side == 0 ? 0 : (seam.vertical ? g.width : g.height) - 1;
  std::vector<TinVertex> start;
  for (const int64_t t : {int64_t{0}, seam.length - 1}) {
    const int64_t col = seam.vertical ? far : t, row = seam.vertical ? t : far;
    start.push_back(VertexAt(g, col, row, boundary_z(col, row)));
  }
  start.insert(start.end(), chain.begin(), chain.end());
  Cdt cdt;
  cdt.InsertVertices(start);
  return cdt;
}

// Refines one half; its faces lie on its side of the seam, so it reads only its own cells
// (and the seam's, never inserting one: the chain must stay the same in both halves).
void RefineHalf(Cdt& cdt, const Grid& dem, const Seam& seam, double tolerance) {
  GridCellSource source(dem);
  RefineOptions options;
  options.tolerance = tolerance;
  const double seam_x = dem.geometry.CellCenterX(seam.at);
  const double seam_y = dem.geometry.CellCenterY(seam.at);
  // The refiner asks with the same CellCenterX/Y computation, so == is exact.
  options.excluded = [&](double x, double y) { return seam.vertical ? x == seam_x : y == seam_y; };
  RefineToTolerance(cdt, source, options);
}

}  // namespace

bool WorthSplitting(const GridGeometry& g) {
  return std::max(g.width, g.height) >= 3 && g.CellCount() >= kMinCellsToSplit;
}

SeamChoice ChooseSeam(const Grid& dem, double tolerance, const BoundaryElevationFn& boundary_z) {
  const auto [seam, chain] = ShortestSeamNearBalance(dem, tolerance, boundary_z);
  return SeamChoice{seam.vertical, seam.at, chain.size()};
}

size_t MinSeamVertices(const GridGeometry& g) {
  const int64_t seam_cells = std::min(g.width, g.height);
  return std::max(kMinSeamVertices, static_cast<size_t>(seam_cells / kMaxSeamCellsPerVertex));
}

std::optional<Cdt> RefineInHalves(const Grid& dem, double tolerance,
                                  const BoundaryElevationFn& boundary_z, size_t min_seam_vertices) {
  const GridGeometry& g = dem.geometry;
  const auto found = ShortestSeamNearBalance(dem, tolerance, boundary_z);
  const Seam& seam = found.first;
  const std::vector<TinVertex>& chain = found.second;
  if (chain.size() < min_seam_vertices) return std::nullopt;
  Cdt first = StartHalf(g, seam, 0, chain, boundary_z);
  Cdt second = StartHalf(g, seam, 1, chain, boundary_z);
  // Each half reads and writes only its own triangulation: run side by side or one after the
  // other, they end the same.
  tbb::parallel_invoke([&] { RefineHalf(first, dem, seam, tolerance); },
                       [&] { RefineHalf(second, dem, seam, tolerance); });
  std::vector<Cdt::FaceRef> changed;
  first.Absorb(std::move(second), &changed);
  GridCellSource source(dem);
  RefineOptions options;
  options.tolerance = tolerance;
  RefineFacesToTolerance(first, source, options, std::move(changed));
  return first;
}

}  // namespace tinbase
