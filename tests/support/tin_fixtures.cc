#include "tests/support/tin_fixtures.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <unordered_map>

#include "db/integrity_check.h"

namespace tinbase::testing {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexKind, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

Tin FromCdt(const Cdt& cdt) {
  Tin tin;
  std::unordered_map<Cdt::Vertex_handle, uint32_t> index;
  for (auto v : cdt.finite_vertex_handles()) {
    index.emplace(v, static_cast<uint32_t>(tin.vertices.size()));
    const double x = v->point().x(), y = v->point().y();
    tin.vertices.push_back({x, y, FixtureZ(x, y), v->info()});
  }
  for (auto f : cdt.finite_face_handles()) {
    TinTriangle t;
    for (int i = 0; i < 3; ++i) t.v[i] = index.at(f->vertex(i));
    tin.triangles.push_back(t);
  }
  for (auto e : cdt.finite_edges()) {
    if (!cdt.is_constrained(e)) continue;
    tin.constraints.emplace_back(index.at(e.first->vertex(Cdt::cw(e.second))),
                                 index.at(e.first->vertex(Cdt::ccw(e.second))));
  }
  EXPECT_TRUE(LinkNeighbours(tin));
  return tin;
}

}  // namespace

double FixtureZ(double x, double y) {
  return 500 + 80 * std::sin(x / 700) * std::cos(y / 900) + 0.01 * std::fmod(x + 2 * y, 1000);
}

Tin RandomDelaunayTin(const RandomTinOptions& options) {
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> u(0, options.size);
  std::vector<std::pair<Kernel::Point_2, VertexKind>> points;
  for (int i = 0; i < options.points; ++i)
    points.emplace_back(Kernel::Point_2(options.x0 + u(rng), options.y0 + u(rng)),
                        VertexKind::kDem);
  for (const auto& [x, y] : options.extra)
    points.emplace_back(Kernel::Point_2(x, y), VertexKind::kUser);
  Cdt cdt;
  cdt.insert(points.begin(), points.end());
  const double cx = options.x0 + options.size / 2, cy = options.y0 + options.size / 2;
  const double radius = options.size * 0.3;
  if (options.ring) {
    constexpr int kSides = 48;
    std::vector<Cdt::Vertex_handle> ring;
    for (int k = 0; k < kSides; ++k) {
      const double a = 2 * std::numbers::pi * k / kSides;
      ring.push_back(
          cdt.insert(Kernel::Point_2(cx + radius * std::cos(a), cy + radius * std::sin(a))));
      ring.back()->info() = VertexKind::kRing;
    }
    for (int k = 0; k < kSides; ++k) cdt.insert_constraint(ring[k], ring[(k + 1) % kSides]);
  }
  Tin tin = FromCdt(cdt);
  if (options.ring) {
    tin.tags = {"granite", "schist"};
    for (size_t t = 0; t < tin.triangles.size(); ++t) {
      TinTriangle& tri = tin.triangles[t];
      double mx = 0, my = 0;
      for (uint32_t v : tri.v) mx += tin.vertices[v].x / 3, my += tin.vertices[v].y / 3;
      if (std::hypot(mx - cx, my - cy) < radius)
        tri.tag = 0;
      else if (t % 7 == 0)
        tri.tag = 1;
      tri.visible = t % 11 != 0;
    }
  }
  return tin;
}

Tin PerturbedGridTin(int nx, int ny, uint32_t seed, double cell, double displaced_fraction) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> shift(-0.2 * cell, 0.2 * cell);
  std::bernoulli_distribution displaced(displaced_fraction), flip(0.5);
  Tin tin;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      double x = 600000 + i * cell, y = 5100000 + j * cell;
      const bool inner = i > 0 && j > 0 && i < nx - 1 && j < ny - 1;
      if (inner && displaced(rng)) x += shift(rng), y += shift(rng);
      tin.vertices.push_back({x, y, FixtureZ(x, y), VertexKind::kDem});
    }
  }
  const auto at = [nx](int i, int j) { return static_cast<uint32_t>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (flip(rng)) {
        tin.triangles.push_back({{a, b, c}});
        tin.triangles.push_back({{a, c, d}});
      } else {
        tin.triangles.push_back({{a, b, d}});
        tin.triangles.push_back({{b, c, d}});
      }
    }
  }
  EXPECT_TRUE(LinkNeighbours(tin));
  return tin;
}

void ExpectStoreIntact(Store& store, bool full) {
  auto problems = CheckStore(store, {.surface = {}, .full = full});
  ASSERT_TRUE(problems.ok()) << problems.status().ToString();
  std::string first;
  for (size_t k = 0; k < problems->size() && k < 5; ++k)
    first += "\n  " + (*problems)[k].code + ": " + (*problems)[k].message;
  EXPECT_TRUE(problems->empty()) << problems->size() << " problems:" << first;
}

}  // namespace tinbase::testing
