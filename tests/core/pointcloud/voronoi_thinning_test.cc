// Voronoi density thinning (paper 003): generated clusters that must or must not be thinned, the
// rules it promises (hull kept, no two neighbours dropped, the thinned TIN within the vertical
// threshold of every dropped point), duplicates and bad input, and the paper's experiment
// repeated on a ~590-point window of Autzen ground points.
#include "core/pointcloud/voronoi_thinning.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/convex_hull_2.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <set>

#include "core/geometry/cdt.h"
#include "core/pointcloud/las_reader.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_checks.h"

namespace tinbase {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// Sparse jittered points every 5 units over [0, 100]², plus a dense cluster (spacing 1) over
// [40, 60]² whose z is `cluster_z(x, y)`. Everything outside the cluster is flat at z = 10.
template <typename ZFn>
std::vector<TinVertex> SparseWithCluster(ZFn cluster_z, std::mt19937& rng) {
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::vector<TinVertex> points;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double x = 5.0 * i + (i % 20 ? jitter(rng) : 0);
      const double y = 5.0 * j + (j % 20 ? jitter(rng) : 0);
      if (x > 39 && x < 61 && y > 39 && y < 61) continue;
      points.push_back({x, y, 10, VertexKind::kLidar});
    }
  }
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const double x = 40 + i + jitter(rng) / 2, y = 40 + j + jitter(rng) / 2;
      points.push_back({x, y, cluster_z(x, y), VertexKind::kLidar});
    }
  }
  return points;
}

bool InCluster(const TinVertex& p) { return p.x > 39 && p.x < 61 && p.y > 39 && p.y < 61; }

ThinningOptions ClusterOptions() {
  ThinningOptions o;
  o.max_cell_area = 5;  // cluster cells are ~1, sparse cells ~25
  o.vertical_threshold = 0.15;
  return o;
}

// Points on the boundary of the convex hull, by CGAL's exact predicates (independent of the
// thinning code, which reads the hull off its triangulation).
std::set<uint32_t> HullPoints(const std::vector<TinVertex>& points) {
  std::vector<K::Point_2> plan, hull;
  for (const TinVertex& p : points) plan.emplace_back(p.x, p.y);
  CGAL::convex_hull_2(plan.begin(), plan.end(), std::back_inserter(hull));
  std::set<uint32_t> on_hull;
  for (uint32_t i = 0; i < plan.size(); ++i) {
    if (CGAL::bounded_side_2(hull.begin(), hull.end(), plan[i]) == CGAL::ON_BOUNDARY) {
      on_hull.insert(i);
    }
  }
  return on_hull;
}

// The Delaunay edges of `points` (no duplicates), as input-index pairs.
std::set<std::pair<uint32_t, uint32_t>> DelaunayEdges(const std::vector<TinVertex>& points) {
  Cdt cdt;
  cdt.InsertVertices(points);
  const Tin tin = cdt.ToTin();
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (const TinTriangle& t : tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = t.v[i], b = t.v[(i + 1) % 3];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  }
  return edges;
}

// The worst |TIN(x, y) - z| over `probes`, evaluating the TIN by brute force over all
// triangles; -1 if some probe lies in no triangle.
double WorstInterpolationError(const Tin& tin, const std::vector<TinVertex>& probes) {
  double worst = 0;
  for (const TinVertex& q : probes) {
    double error = -1;
    for (const TinTriangle& t : tin.triangles) {
      const TinVertex& a = tin.vertices[t.v[0]];
      const TinVertex& b = tin.vertices[t.v[1]];
      const TinVertex& c = tin.vertices[t.v[2]];
      const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
      const double l1 = ((q.x - a.x) * (c.y - a.y) - (c.x - a.x) * (q.y - a.y)) / det;
      const double l2 = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / det;
      const double l0 = 1 - l1 - l2;
      constexpr double kEps = 1e-9;
      if (l0 < -kEps || l1 < -kEps || l2 < -kEps) continue;
      error = std::max(error, std::abs(l0 * a.z + l1 * b.z + l2 * c.z - q.z));
    }
    if (error < 0) return -1;
    worst = std::max(worst, error);
  }
  return worst;
}

Tin TinOf(const std::vector<TinVertex>& points, const std::vector<uint32_t>& indices) {
  std::vector<TinVertex> subset;
  for (uint32_t i : indices) subset.push_back(points[i]);
  Cdt cdt;
  cdt.InsertVertices(subset);
  return cdt.ToTin();
}

std::vector<TinVertex> Pick(const std::vector<TinVertex>& points,
                            const std::vector<uint32_t>& indices) {
  std::vector<TinVertex> out;
  for (uint32_t i : indices) out.push_back(points[i]);
  return out;
}

// The promises of one pass: counts add up, hull kept, no two dropped points are neighbours, and
// the TIN of the survivors is within the vertical threshold at every dropped point.
void ExpectFaithfulPass(const std::vector<TinVertex>& points, const ThinningResult& r,
                        double vertical_threshold) {
  EXPECT_EQ(r.report.points_in, points.size());
  EXPECT_EQ(r.report.kept + r.report.dropped + r.report.duplicates, points.size());
  EXPECT_EQ(r.kept.size(), r.report.kept);
  EXPECT_EQ(r.dropped.size(), r.report.dropped);
  EXPECT_TRUE(std::is_sorted(r.kept.begin(), r.kept.end()));
  const std::set<uint32_t> dropped(r.dropped.begin(), r.dropped.end());
  for (uint32_t h : HullPoints(points)) EXPECT_FALSE(dropped.count(h)) << "hull point " << h;
  for (auto [a, b] : DelaunayEdges(points)) {
    EXPECT_FALSE(dropped.count(a) && dropped.count(b)) << "neighbours " << a << ", " << b;
  }
  const Tin thinned = TinOf(points, r.kept);
  const double worst = WorstInterpolationError(thinned, Pick(points, r.dropped));
  EXPECT_GE(worst, 0) << "a dropped point lies outside the thinned TIN";
  EXPECT_LE(worst, vertical_threshold + 1e-9);
}

TEST(VoronoiThinning, DenseFlatClusterIsThinned) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.01);
  const auto points = SparseWithCluster([&](double, double) { return 10 + noise(rng); }, rng);
  auto r = ThinByVoronoiDensity(points, ClusterOptions());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  // An independent set of the cluster's 21 x 21 grid: between a fifth and a half of it.
  EXPECT_GT(r->report.dropped, 441u / 5);
  EXPECT_LT(r->report.dropped, 441u / 2);
  for (uint32_t i : r->dropped) EXPECT_TRUE(InCluster(points[i])) << "sparse point " << i;
  EXPECT_EQ(r->report.duplicates, 0u);
  EXPECT_EQ(r->report.cell_area_threshold, 5);
  EXPECT_EQ(r->report.passes_run, 1);
  ExpectFaithfulPass(points, *r, 0.15);
}

TEST(VoronoiThinning, DenseRoughClusterIsKept) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> rough(0, 3);
  const auto points = SparseWithCluster([&](double, double) { return 10 + rough(rng); }, rng);
  auto r = ThinByVoronoiDensity(points, ClusterOptions());
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  // With z spread over 3 units a point within 0.15 of all its ~6 neighbours is very unlikely.
  EXPECT_LE(r->report.dropped, 2u);
  ExpectFaithfulPass(points, *r, 0.15);
}

TEST(VoronoiThinning, SparsePointsAreUntouchedEvenWhenFlat) {
  std::mt19937 rng(5);
  auto points = SparseWithCluster([](double, double) { return 10.0; }, rng);
  std::erase_if(points, InCluster);
  auto r = ThinByVoronoiDensity(points, ClusterOptions());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->report.dropped, 0u);
  EXPECT_EQ(r->report.kept, points.size());
  EXPECT_EQ(r->report.passes_run, 0);
}

TEST(VoronoiThinning, UniformCloudHasNoDenseClusterByDefault) {
  // On a regular grid every bounded cell has the median area, so none is below 0.75 of it.
  std::vector<TinVertex> grid;
  for (int i = 0; i < 30; ++i) {
    for (int j = 0; j < 30; ++j) grid.push_back({2.0 * i, 2.0 * j, 0, VertexKind::kLidar});
  }
  auto r = ThinByVoronoiDensity(grid, ThinningOptions{});
  ASSERT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(r->report.cell_area_threshold, 0.75 * 4.0);
  EXPECT_EQ(r->report.dropped, 0u);
}

TEST(VoronoiThinning, DefaultThresholdFindsTheDenseClusterAmongSparsePoints) {
  std::mt19937 rng(6);
  const auto points = SparseWithCluster([](double, double) { return 10.0; }, rng);
  auto r = ThinByVoronoiDensity(points, ThinningOptions{});
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->report.dropped, 0u);
  for (uint32_t i : r->dropped) EXPECT_TRUE(InCluster(points[i])) << i;
  ExpectFaithfulPass(points, *r, ThinningOptions{}.vertical_threshold);
}

TEST(VoronoiThinning, DensityWindowFindsTheClusterAndCountsPointsNotCells) {
  // Sparse spacing 5, cluster spacing 1. A window of 30 units² (radius ~3.1) holds only the point
  // itself in the sparse part and ~29 points in the cluster, so "more than 10 per 30" is exactly
  // the cluster. A close pair in the sparse part has two tiny-ish Voronoi cells but only two
  // points in its window: the window leaves it alone.
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.01);
  auto points = SparseWithCluster([&](double, double) { return 10 + noise(rng); }, rng);
  points.push_back({12.6, 12.4, 10, VertexKind::kLidar});  // beside the sparse point near (10, 10)
  ThinningOptions o;
  o.window = DensityWindow{10, 30};
  o.vertical_threshold = 0.15;
  auto r = ThinByVoronoiDensity(points, o);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  for (uint32_t i : r->dropped) EXPECT_TRUE(InCluster(points[i])) << "sparse point " << i;
  EXPECT_GT(r->report.dropped, 441u / 5);
  EXPECT_LT(r->report.dropped, 441u / 2);
  // The cluster's points away from its rim are dense; nothing outside it is.
  EXPECT_GT(r->report.dense, 300u);
  EXPECT_LE(r->report.dense, 441u);
  EXPECT_EQ(r->report.cell_area_threshold, 0);
  ExpectFaithfulPass(points, *r, 0.15);

  // Widen the allowance past the cluster's count and nothing is dense.
  o.window = DensityWindow{40, 30};
  auto none = ThinByVoronoiDensity(points, o);
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none->report.dense, 0u);
  EXPECT_EQ(none->report.dropped, 0u);
}

TEST(VoronoiThinning, BadDensityWindowIsRejected) {
  const std::vector<TinVertex> points = {
      {0, 0, 0, VertexKind::kLidar}, {1, 0, 0, VertexKind::kLidar}, {0, 1, 0, VertexKind::kLidar}};
  ThinningOptions o;
  o.window = DensityWindow{10, 0};
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().message(),
            "thinning: density window area 0.000000 must be positive");
  o.window = DensityWindow{-1, 150};
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().message(),
            "thinning: density window count -1.000000 must be a finite value >= 0");
}

TEST(VoronoiThinning, HullPointsAreNeverDropped) {
  // Everything dense and perfectly flat: only the hull rule and the neighbour rule hold points.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(0, 50);
  std::vector<TinVertex> points;
  for (int i = 0; i < 2000; ++i) points.push_back({coord(rng), coord(rng), 1, VertexKind::kLidar});
  ThinningOptions o;
  o.max_cell_area = 1e9;
  o.passes = 6;
  auto r = ThinByVoronoiDensity(points, o);
  ASSERT_TRUE(r.ok());
  const std::set<uint32_t> kept(r->kept.begin(), r->kept.end());
  const std::set<uint32_t> hull = HullPoints(points);
  EXPECT_GE(hull.size(), 3u);
  for (uint32_t h : hull) EXPECT_TRUE(kept.count(h)) << "hull point " << h;
  EXPECT_GT(r->report.passes_run, 1);
  EXPECT_LT(r->report.kept, points.size() / 4) << "six passes over a flat cloud thin it hard";
  // Flat input: the thinned TIN is exact at every dropped point however many passes ran.
  EXPECT_NEAR(WorstInterpolationError(TinOf(points, r->kept), Pick(points, r->dropped)), 0, 1e-9);
}

TEST(VoronoiThinning, MorePassesDropMore) {
  std::mt19937 rng(8);
  std::normal_distribution<double> noise(0, 0.01);
  const auto points = SparseWithCluster([&](double, double) { return 10 + noise(rng); }, rng);
  ThinningOptions one = ClusterOptions(), three = ClusterOptions();
  three.passes = 3;
  auto r1 = ThinByVoronoiDensity(points, one);
  auto r3 = ThinByVoronoiDensity(points, three);
  ASSERT_TRUE(r1.ok() && r3.ok());
  EXPECT_GT(r3->report.dropped, r1->report.dropped);
  EXPECT_EQ(r3->report.cell_area_threshold, r1->report.cell_area_threshold);
}

TEST(VoronoiThinning, MeanTestAcceptsWhatAllNeighboursRejects) {
  // A checkerboard of +-0.1 in the cluster: every point is 0.2 from its 4-neighbours, so the
  // strict test (0.15) keeps it, while the mean of its neighbours is close to its own z only
  // where the diagonals agree with it.
  std::mt19937 rng(9);
  const auto points = SparseWithCluster(
      [](double x, double y) {
        const int parity =
            (static_cast<int>(std::lround(x)) + static_cast<int>(std::lround(y))) & 1;
        return 10 + (parity ? 0.1 : -0.1);
      },
      rng);
  ThinningOptions all = ClusterOptions(), mean = ClusterOptions();
  mean.flatness = FlatnessTest::kNeighbourMean;
  mean.vertical_threshold = 0.15;
  auto r_all = ThinByVoronoiDensity(points, all);
  auto r_mean = ThinByVoronoiDensity(points, mean);
  ASSERT_TRUE(r_all.ok() && r_mean.ok());
  EXPECT_EQ(r_all->report.dropped, 0u);
  EXPECT_GT(r_mean->report.dropped, 0u);
}

TEST(VoronoiThinning, DuplicatesKeepTheFirst) {
  std::mt19937 rng(10);
  std::normal_distribution<double> noise(0, 0.01);
  auto points = SparseWithCluster([&](double, double) { return 10 + noise(rng); }, rng);
  const size_t n = points.size();
  // Three later copies (different z) of points 0, 5 and the last one.
  points.push_back({points[0].x, points[0].y, 99, VertexKind::kLidar});
  points.push_back({points[5].x, points[5].y, 98, VertexKind::kLidar});
  points.push_back({points[n - 1].x, points[n - 1].y, 97, VertexKind::kLidar});
  auto r = ThinByVoronoiDensity(points, ClusterOptions());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->report.duplicates, 3u);
  for (uint32_t i : r->kept) EXPECT_LT(i, n) << "a later duplicate survived";
  for (uint32_t i : r->dropped) EXPECT_LT(i, n);
  EXPECT_EQ(r->report.kept + r->report.dropped, n);
  EXPECT_TRUE(std::count(r->kept.begin(), r->kept.end(), 0u));  // on the hull: kept
}

TEST(VoronoiThinning, NonFiniteInputIsRejectedWithItsIndex) {
  std::vector<TinVertex> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, NAN}, {2, 2, 0}};
  auto r = ThinByVoronoiDensity(points, ThinningOptions{});
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message().rfind("point 3: x, y or z is not finite", 0), 0u)
      << r.status().message();
  points[3].z = 0;
  points[1].x = INFINITY;
  EXPECT_EQ(ThinByVoronoiDensity(points, ThinningOptions{}).status().message().rfind("point 1:", 0),
            0u);
}

TEST(VoronoiThinning, OptionsOutOfRangeAreRejected) {
  const std::vector<TinVertex> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  ThinningOptions o;
  o.vertical_threshold = -1;
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().code(), StatusCode::kInvalidArgument);
  o = {};
  o.max_cell_area = 0;
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().code(), StatusCode::kInvalidArgument);
  o = {};
  o.median_fraction = NAN;
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().code(), StatusCode::kInvalidArgument);
  o = {};
  o.passes = 0;
  EXPECT_EQ(ThinByVoronoiDensity(points, o).status().code(), StatusCode::kInvalidArgument);
}

TEST(VoronoiThinning, DegenerateInputsKeepEverything) {
  for (size_t n : {0u, 1u, 2u, 7u}) {
    std::vector<TinVertex> line;
    for (size_t i = 0; i < n; ++i) line.push_back({double(i), 2.0 * double(i), 0});
    auto r = ThinByVoronoiDensity(line, ThinningOptions{});
    ASSERT_TRUE(r.ok()) << n;
    EXPECT_EQ(r->report.kept, n);
    EXPECT_EQ(r->report.dropped, 0u);
  }
}

// Paper 003 on real points: their 590 Lake Erie points (571.26 ft mean, 2 ft of relief) lost
// 137 to thinning with cells under 15 ft² (10 per 150 ft²) and a 0.15 ft vertical threshold,
// and the TIN went from 1157 to 884 triangles. Autzen is in feet too, so the same thresholds
// apply; the window is the flattest square of ~590 Autzen ground points.
TEST(VoronoiThinning, PaperExperimentOnAutzenGround) {
  auto las = ReadLas(testing::DataPath("las/autzen_trim.las"));
  ASSERT_TRUE(las.ok()) << las.status().ToString();
  std::vector<TinVertex> ground;
  for (const CloudPoint& p : las->cloud.points) {
    if (p.classification == kLasClassGround) ground.push_back({p.x, p.y, p.z, VertexKind::kLidar});
  }
  ASSERT_GT(ground.size(), 10000u);

  // Square windows on a 20 ft lattice, each grown until it holds 590 points; keep the one with
  // the least relief.
  const auto [xlo, xhi] =
      std::minmax_element(ground.begin(), ground.end(), [](auto& a, auto& b) { return a.x < b.x; });
  const auto [ylo, yhi] =
      std::minmax_element(ground.begin(), ground.end(), [](auto& a, auto& b) { return a.y < b.y; });
  std::vector<TinVertex> best;
  double best_relief = INFINITY;
  for (double cx = xlo->x + 60; cx < xhi->x - 60; cx += 20) {
    for (double cy = ylo->y + 60; cy < yhi->y - 60; cy += 20) {
      std::vector<std::pair<double, size_t>> by_distance;  // Chebyshev distance to the centre
      for (size_t i = 0; i < ground.size(); ++i) {
        const double d = std::max(std::abs(ground[i].x - cx), std::abs(ground[i].y - cy));
        if (d < 60) by_distance.push_back({d, i});
      }
      if (by_distance.size() < 590) continue;
      std::nth_element(by_distance.begin(), by_distance.begin() + 589, by_distance.end());
      by_distance.resize(590);
      std::vector<TinVertex> window;
      double zmin = INFINITY, zmax = -INFINITY;
      for (auto [d, i] : by_distance) {
        window.push_back(ground[i]);
        zmin = std::min(zmin, ground[i].z);
        zmax = std::max(zmax, ground[i].z);
      }
      if (zmax - zmin < best_relief) {
        best_relief = zmax - zmin;
        best = std::move(window);
      }
    }
  }
  ASSERT_EQ(best.size(), 590u);

  ThinningOptions paper;
  paper.max_cell_area = 15;  // "not more than 10 Voronoi polygons per 150 square feet"
  paper.vertical_threshold = 0.15;
  auto r = ThinByVoronoiDensity(best, paper);
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  Cdt before_cdt;
  before_cdt.InsertVertices(best);
  const size_t triangles_before = before_cdt.FaceCount();
  const size_t triangles_after = TinOf(best, r->kept).triangles.size();
  std::cout << "autzen window: relief " << best_relief << " ft, " << best.size() << " points ("
            << r->report.duplicates << " duplicates) -> " << r->report.kept << " kept, "
            << r->report.dropped << " dropped; triangles " << triangles_before << " -> "
            << triangles_after << " (paper: 590 -> 453 points, 1157 -> 884 triangles)\n";

  // The paper's shape: a fifth to a third of the points go, and the triangles fall with them
  // (a Delaunay TIN has about two triangles per point).
  EXPECT_GT(r->report.dropped, best.size() / 8);
  EXPECT_LT(r->report.dropped, best.size() / 2);
  EXPECT_LT(triangles_after, triangles_before);
  const double ratio = double(triangles_after) / double(triangles_before);
  const double point_ratio = double(r->report.kept) / double(best.size());
  EXPECT_NEAR(ratio, point_ratio, 0.05);
  ExpectFaithfulPass(best, *r, 0.15);

  // The paper's words taken literally: more than 10 points in the 150 ft² disc around a point.
  ThinningOptions literal;
  literal.window = DensityWindow{10, 150};
  literal.vertical_threshold = 0.15;
  auto by_window = ThinByVoronoiDensity(best, literal);
  ASSERT_TRUE(by_window.ok()) << by_window.status().ToString();
  const size_t window_triangles = TinOf(best, by_window->kept).triangles.size();
  std::cout << "same window, density window 10 per 150 ft2: " << by_window->report.dense
            << " dense, " << by_window->report.kept << " kept, " << by_window->report.dropped
            << " dropped; triangles " << triangles_before << " -> " << window_triangles << "\n";
  // Fewer go than by cell area (this window's typical spacing is near 10 per 150 ft² already),
  // and each dropped point really has more than 10 points, itself included, in its disc.
  EXPECT_GT(by_window->report.dropped, 0u);
  EXPECT_LT(by_window->report.dropped, best.size() / 2);
  const double radius_squared = 150 / std::numbers::pi;
  for (uint32_t i : by_window->dropped) {
    const size_t in_disc = std::count_if(best.begin(), best.end(), [&](const TinVertex& q) {
      return (q.x - best[i].x) * (q.x - best[i].x) + (q.y - best[i].y) * (q.y - best[i].y) <=
             radius_squared;
    });
    EXPECT_GT(in_disc, 10u) << "dropped point " << i;
  }
  ExpectFaithfulPass(best, *by_window, 0.15);

  // The default density threshold (0.75 of the median cell) on the same window, for comparison.
  auto by_default = ThinByVoronoiDensity(best, ThinningOptions{});
  ASSERT_TRUE(by_default.ok());
  std::cout << "same window, default threshold " << by_default->report.cell_area_threshold
            << " ft2: " << by_default->report.kept << " kept, " << by_default->report.dropped
            << " dropped\n";
  EXPECT_GT(by_default->report.dropped, 0u);
  ExpectFaithfulPass(best, *by_default, ThinningOptions{}.vertical_threshold);
}

}  // namespace
}  // namespace tinbase
