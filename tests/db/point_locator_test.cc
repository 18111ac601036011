// LocatePoint agrees with a brute-force search over every triangle, on Delaunay and free
// surfaces, for points inside, on vertices, on edges and outside, and walks only a short way.
#include "db/point_locator.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/geometry/predicates.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::StoreTarget;
using testing::TempDir;

// The answers LocatePoint must agree with, by testing every triangle of a loaded surface.
class BruteForce {
 public:
  explicit BruteForce(const LoadedSurface& surface) : s_(surface) {}

  // Every triangle that holds p (several when p is on an edge or a vertex), as Tin indices.
  std::vector<size_t> Containing(const Point2& p) const {
    std::vector<size_t> out;
    for (size_t t = 0; t < s_.tin.triangles.size(); ++t) {
      if (Contains(t, p)) out.push_back(t);
    }
    return out;
  }

  // z of the plane through triangle t, by area coordinates in long double.
  long double Z(size_t t, const Point2& p) const {
    const auto& v = s_.tin.triangles[t].v;
    const auto cross = [](const TinVertex& a, const TinVertex& b, const Point2& o) {
      return (static_cast<long double>(a.x) - o.x) * (static_cast<long double>(b.y) - o.y) -
             (static_cast<long double>(a.y) - o.y) * (static_cast<long double>(b.x) - o.x);
    };
    const TinVertex& a = s_.tin.vertices[v[0]];
    const TinVertex& b = s_.tin.vertices[v[1]];
    const TinVertex& c = s_.tin.vertices[v[2]];
    const long double area = cross(b, c, {a.x, a.y});
    return (cross(b, c, p) * a.z + cross(c, a, p) * b.z + cross(a, b, p) * c.z) / area;
  }

  // The Tin index of a stored triangle id; size() when it is not one.
  size_t IndexOf(int64_t triangle_id) const {
    auto it = std::lower_bound(s_.triangle_ids.begin(), s_.triangle_ids.end(), triangle_id);
    if (it == s_.triangle_ids.end() || *it != triangle_id) return s_.triangle_ids.size();
    return static_cast<size_t>(it - s_.triangle_ids.begin());
  }

 private:
  Point2 At(uint32_t v) const { return {s_.tin.vertices[v].x, s_.tin.vertices[v].y}; }

  bool Contains(size_t t, const Point2& p) const {
    const auto& v = s_.tin.triangles[t].v;
    for (int i = 0; i < 3; ++i) {
      if (Orientation(At(v[(i + 1) % 3]), At(v[(i + 2) % 3]), p) < 0) return false;
    }
    return true;
  }

  const LoadedSurface& s_;
};

// A store at `path` holding `tin` as surface `name`.
struct StoredTin {
  std::unique_ptr<Store> store;
  SurfaceInfo info;
  LoadedSurface loaded;
};
Result<StoredTin> StoreTin(const std::string& path, const std::string& name, SurfaceKind kind,
                           const Tin& tin) {
  StoredTin out;
  TB_ASSIGN_OR_RETURN(out.store, Store::Create(path, "EPSG:32632"));
  TB_ASSIGN_OR_RETURN(auto tx, out.store->BeginWrite());
  SurfaceInfo spec;
  spec.name = name;
  spec.kind = kind;
  spec.method = "test";
  TB_ASSIGN_OR_RETURN(out.info, SurfaceStore(*out.store).Create(spec, tin));
  TB_RETURN_IF_ERROR(tx->Commit());
  TB_ASSIGN_OR_RETURN(out.loaded, SurfaceStore(*out.store).Load(out.info));
  return out;
}

class PointLocatorTest : public ::testing::Test {
 protected:
  void Create(const std::string& name, SurfaceKind kind, const Tin& tin) {
    auto stored = StoreTin(StoreTarget(dir_, "s.tinbase"), name, kind, tin);
    ASSERT_TRUE(stored.ok()) << stored.status().ToString();
    store_ = std::move(stored->store);
    info_ = stored->info;
    loaded_ = std::move(stored->loaded);
  }

  Point2 At(uint32_t v) const { return {loaded_.tin.vertices[v].x, loaded_.tin.vertices[v].y}; }

  // Locates p and compares with brute force; returns the walk's length (0 when outside).
  int ExpectAgreesWithBruteForce(const Point2& p) {
    const BruteForce brute(loaded_);
    const std::vector<size_t> holders = brute.Containing(p);
    auto located = LocatePoint(*store_, info_, p.x, p.y);
    if (holders.empty()) {
      EXPECT_FALSE(located.ok()) << "(" << p.x << ", " << p.y << ") is outside";
      EXPECT_EQ(located.status().code(), StatusCode::kNotFound);
      EXPECT_NE(located.status().message().find("is outside surface '" + info_.name + "'"),
                std::string::npos)
          << located.status().message();
      return 0;
    }
    EXPECT_TRUE(located.ok()) << located.status().ToString();
    if (!located.ok()) return 0;
    const size_t t = brute.IndexOf(located->triangle);
    EXPECT_LT(t, loaded_.tin.triangles.size()) << "no triangle " << located->triangle;
    if (t >= loaded_.tin.triangles.size()) return 0;
    EXPECT_TRUE(std::find(holders.begin(), holders.end(), t) != holders.end())
        << "triangle " << located->triangle << " does not hold (" << p.x << ", " << p.y << ")";
    EXPECT_NEAR(located->z, static_cast<double>(brute.Z(holders.front(), p)), 1e-6);
    const TinTriangle& tri = loaded_.tin.triangles[t];
    EXPECT_EQ(located->visible, tri.visible);
    EXPECT_EQ(located->tag.value_or(""), tri.tag == kNoTag ? "" : loaded_.tin.tags[tri.tag]);
    EXPECT_GE(located->steps, 1);
    return located->steps;
  }

  // Random points over the vertices' bounding box grown by 5% on each side.
  void ExpectRandomPointsAgree(int count, uint32_t seed, int max_mean_steps) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const TinVertex& v : loaded_.tin.vertices) {
      x0 = std::min(x0, v.x), y0 = std::min(y0, v.y);
      x1 = std::max(x1, v.x), y1 = std::max(y1, v.y);
    }
    const double mx = (x1 - x0) * 0.05, my = (y1 - y0) * 0.05;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(x0 - mx, x1 + mx), uy(y0 - my, y1 + my);
    int64_t steps = 0, inside = 0, outside = 0;
    for (int k = 0; k < count; ++k) {
      const int s = ExpectAgreesWithBruteForce({ux(rng), uy(rng)});
      steps += s;
      (s > 0 ? inside : outside) += 1;
    }
    ASSERT_GT(inside, count / 2);
    EXPECT_GT(outside, 0);
    const double mean = static_cast<double>(steps) / static_cast<double>(inside);
    std::printf("%lld inside, %lld outside, %.1f triangles visited on average of %zu\n",
                static_cast<long long>(inside), static_cast<long long>(outside), mean,
                loaded_.tin.triangles.size());
    EXPECT_LT(mean, max_mean_steps);
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo info_;
  LoadedSurface loaded_;
};

TEST_F(PointLocatorTest, DelaunayAgreesWithBruteForceOnRandomPoints) {
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 3000, .seed = 11, .ring = true}));
  ExpectRandomPointsAgree(3000, 12, 30);  // ~6000 triangles, ~32 per block
}

TEST_F(PointLocatorTest, FreeSurfaceAgreesWithBruteForceOnRandomPoints) {
  Create("rtin", SurfaceKind::kFree, testing::PerturbedGridTin(60, 50, 13));
  ExpectRandomPointsAgree(3000, 14, 30);
}

TEST_F(PointLocatorTest, PointsOnVerticesAreFound) {
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 2000, .seed = 15, .ring = true}));
  for (size_t v = 0; v < loaded_.tin.vertices.size(); v += 3) {
    const TinVertex& vertex = loaded_.tin.vertices[v];
    ExpectAgreesWithBruteForce({vertex.x, vertex.y});
    auto located = LocatePoint(*store_, info_, vertex.x, vertex.y);
    ASSERT_TRUE(located.ok());
    EXPECT_NEAR(located->z, vertex.z, 1e-9 * std::abs(vertex.z));
  }
}

TEST_F(PointLocatorTest, PointsOnEdgesAreFound) {
  // Midpoints of axis-parallel edges between undisplaced grid points lie exactly on the edge.
  Create("rtin", SurfaceKind::kFree, testing::PerturbedGridTin(40, 40, 16));
  int on_edges = 0;
  for (const TinTriangle& tri : loaded_.tin.triangles) {
    for (int i = 0; i < 3; ++i) {
      const Point2 a = At(tri.v[(i + 1) % 3]), b = At(tri.v[(i + 2) % 3]);
      if (a.x != b.x && a.y != b.y) continue;
      const Point2 mid{(a.x + b.x) / 2, (a.y + b.y) / 2};
      ASSERT_EQ(Orientation(a, b, mid), 0);
      ExpectAgreesWithBruteForce(mid);
      ++on_edges;
    }
  }
  EXPECT_GT(on_edges, 2000);
}

TEST_F(PointLocatorTest, SparseRegionsJumpFromNearbyBlocks) {
  // A dense cluster in one corner and four far corners: most blocks hold no centroid, so the
  // jump searches the rings around the point's block or falls back to any triangle.
  std::vector<std::pair<double, double>> corners;
  for (double dx : {-20000.0, 20000.0}) {
    for (double dy : {-20000.0, 20000.0}) corners.emplace_back(600500 + dx, 5100500 + dy);
  }
  Create("cluster", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 1500, .seed = 17, .size = 1000, .extra = corners}));
  int empty = 0;
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> ux(580500, 620500), uy(5080500, 5120500);
  for (int k = 0; k < 1000; ++k) {
    const Point2 p{ux(rng), uy(rng)};
    auto block = SurfaceStore(*store_).AnyTriangleInBlock(info_, info_.blocks.BlockOf(p.x, p.y));
    ASSERT_TRUE(block.ok());
    empty += !block->has_value();
    ExpectAgreesWithBruteForce(p);
  }
  EXPECT_GT(empty, 500);  // the jump really had to look further
  ExpectRandomPointsAgree(500, 19, 40);
}

TEST_F(PointLocatorTest, OutsidePointsAreNotFound) {
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 500, .seed = 19}));
  auto far = LocatePoint(*store_, info_, 0, -5.5);
  ASSERT_FALSE(far.ok());
  EXPECT_EQ(far.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(far.status().message(), "point (0, -5.5) is outside surface 'terrain'");
  EXPECT_EQ(LocatePoint(*store_, info_, 600000 + 5000, 5100000 + 10001).status().code(),
            StatusCode::kNotFound);
}

TEST_F(PointLocatorTest, WorksInsideAWriteTransaction) {
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 500, .seed = 20}));
  auto tx = store_->BeginWrite();
  ASSERT_TRUE(tx.ok());
  ExpectAgreesWithBruteForce({605000, 5105000});
  ASSERT_TRUE((*tx)->Commit().ok());
}

TEST_F(PointLocatorTest, LocatorWalksOnFromThePreviousPoint) {
  // An ellipse of closely spaced points reaching beyond the surface on the east: each walk starts
  // where the last ended (or jumps again after a point outside), and every answer is right.
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 3000, .seed = 22, .ring = true}));
  const BruteForce brute(loaded_);
  PointLocator locator(*store_, info_);
  int64_t steps = 0, inside = 0, outside = 0;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * M_PI * k / 2000;
    const Point2 p{605500 + 5500 * std::cos(a), 5105000 + 3000 * std::sin(a)};
    const std::vector<size_t> holders = brute.Containing(p);
    auto located = locator.Locate(p.x, p.y);
    if (holders.empty()) {
      ASSERT_EQ(located.status().code(), StatusCode::kNotFound) << located.status().ToString();
      ++outside;
      continue;
    }
    ASSERT_TRUE(located.ok()) << located.status().ToString();
    EXPECT_NE(std::find(holders.begin(), holders.end(), brute.IndexOf(located->triangle)),
              holders.end());
    EXPECT_NEAR(located->z, static_cast<double>(brute.Z(holders.front(), p)), 1e-6);
    steps += located->steps;
    ++inside;
  }
  ASSERT_GT(inside, 1000);
  EXPECT_GT(outside, 100);
  // ~17 m between points, triangles ~130 m across: most walks stay in the triangle they start in.
  EXPECT_LT(static_cast<double>(steps) / static_cast<double>(inside), 3.0);
}

TEST_F(PointLocatorTest, BrokenLinksAreCorruptionNotAWrongAnswer) {
  Create("terrain", SurfaceKind::kDelaunay,
         testing::RandomDelaunayTin({.points = 500, .seed = 21}));
  const BruteForce brute(loaded_);
  // Counts the vertices whose location fails with Corruption mentioning `text`; the others must
  // still be right (found in the jump triangle before any broken link is followed).
  const auto corrupt_count = [&](const std::string& text) {
    int corrupt = 0;
    for (const TinVertex& v : loaded_.tin.vertices) {
      auto located = LocatePoint(*store_, info_, v.x, v.y);
      if (located.ok()) {
        const auto holders = brute.Containing({v.x, v.y});
        EXPECT_NE(std::find(holders.begin(), holders.end(), brute.IndexOf(located->triangle)),
                  holders.end());
        continue;
      }
      EXPECT_EQ(located.status().code(), StatusCode::kCorruption) << located.status().ToString();
      EXPECT_NE(located.status().message().find(text), std::string::npos)
          << located.status().message();
      ++corrupt;
    }
    return corrupt;
  };
  // Every link points back to its own triangle: the walk re-enters it and must notice.
  ASSERT_TRUE(store_->db().Exec("UPDATE triangles SET n0 = id, n1 = id, n2 = id").ok());
  EXPECT_GT(corrupt_count("do not share the edge"), 0);
  ASSERT_TRUE(store_->db()
                  .Exec("UPDATE triangles SET n0 = 987654321, n1 = 987654321, n2 = 987654321")
                  .ok());
  EXPECT_GT(corrupt_count("triangle 987654321"), 0);
}

// Property: on random Delaunay and free surfaces, small and degenerate ones included, every
// random query point and every vertex is located exactly as brute force says. RapidCheck prints
// the seed that reproduces a failure.
RC_GTEST_PROP(PointLocatorProperty, AgreesWithBruteForce, ()) {
  const bool grid = *rc::gen::arbitrary<bool>();
  const auto seed = *rc::gen::arbitrary<uint32_t>();
  const Tin tin =
      grid ? testing::PerturbedGridTin(*rc::gen::inRange(2, 16), *rc::gen::inRange(2, 16), seed)
           : testing::RandomDelaunayTin(
                 {.points = *rc::gen::inRange(3, 300), .seed = seed, .size = 500});
  RC_PRE(!tin.triangles.empty());
  TempDir dir;
  auto stored = StoreTin(StoreTarget(dir, "p.tinbase"), "p",
                         grid ? SurfaceKind::kFree : SurfaceKind::kDelaunay, tin);
  RC_ASSERT(stored.ok());
  const BruteForce brute(stored->loaded);
  std::vector<Point2> queries;
  for (size_t v = 0; v < tin.vertices.size(); v += 5)
    queries.push_back({tin.vertices[v].x, tin.vertices[v].y});
  const auto fractions = *rc::gen::container<std::vector<std::pair<int, int>>>(
      40, rc::gen::pair(rc::gen::inRange(-100, 1100), rc::gen::inRange(-100, 1100)));
  for (auto [fx, fy] : fractions) {
    // The fixtures' points lie in a square from (600000, 5100000); grids span up to 450 m.
    queries.push_back({600000 + fx * 0.5, 5100000 + fy * 0.5});
  }
  for (const Point2& p : queries) {
    const std::vector<size_t> holders = brute.Containing(p);
    auto located = LocatePoint(*stored->store, stored->info, p.x, p.y);
    RC_ASSERT(located.ok() == !holders.empty());
    if (holders.empty()) {
      RC_ASSERT(located.status().code() == StatusCode::kNotFound);
      continue;
    }
    const size_t t = brute.IndexOf(located->triangle);
    RC_ASSERT(std::find(holders.begin(), holders.end(), t) != holders.end());
    RC_ASSERT(std::abs(located->z - static_cast<double>(brute.Z(t, p))) < 1e-6);
  }
}

}  // namespace
}  // namespace tinbase
