// Tins for tests, made from CGAL or from a grid, and the "store is intact" assertion.
//
// RandomDelaunayTin is a constrained Delaunay triangulation of random points (CGAL's CDT), with
// an optional ring of constrained edges, tags and hidden triangles, so every column of the
// surface tables carries data. PerturbedGridTin is a "free" TIN: a grid with random diagonals and
// a few displaced points, valid but in general not Delaunay. z comes from FixtureZ. Plain
// functions; deterministic for a seed.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/tin/tin.h"
#include "db/store.h"

namespace tinbase::testing {

// Smooth terrain, metres.
double FixtureZ(double x, double y);

struct RandomTinOptions {
  int points = 2000;
  uint32_t seed = 1;
  bool ring = false;  // a constrained 48-gon in the middle, its inside tagged "granite"
  double x0 = 600000, y0 = 5100000, size = 10000;     // the square the points are drawn from
  std::vector<std::pair<double, double>> extra = {};  // more points (kind user), anywhere
};
Tin RandomDelaunayTin(const RandomTinOptions& options);

// nx * ny grid points `cell` apart from (600000, 5100000); `displaced` of the inner points are
// moved by up to 0.2 cell; each cell is split by a random diagonal.
Tin PerturbedGridTin(int nx, int ny, uint32_t seed, double cell = 30, double displaced = 0.1);

// GoogleTest failure listing the first problems when CheckStore finds any; `full` adds
// invariants 6 and 7 (paint and tolerance).
void ExpectStoreIntact(Store& store, bool full = false);

}  // namespace tinbase::testing
