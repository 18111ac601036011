// LocatePoint agrees with a brute-force search over every triangle, on Delaunay and free
// surfaces, for points inside, on vertices, on edges and outside, and walks only a short way.
#include "db/point_locator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/geometry/predicates.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::TempDir;

class PointLocatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(dir_.Path("s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
  }

  void Create(const std::string& name, SurfaceKind kind, const Tin& tin) {
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = name;
    spec.kind = kind;
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    ASSERT_TRUE((*tx)->Commit().ok());
    info_ = *info;
    auto loaded = SurfaceStore(*store_).Load(info_);
    ASSERT_TRUE(loaded.ok());
    loaded_ = std::move(*loaded);
  }

  Point2 At(uint32_t v) const { return {loaded_.tin.vertices[v].x, loaded_.tin.vertices[v].y}; }

  bool Contains(size_t t, const Point2& p) const {
    const auto& v = loaded_.tin.triangles[t].v;
    for (int i = 0; i < 3; ++i) {
      if (Orientation(At(v[(i + 1) % 3]), At(v[(i + 2) % 3]), p) < 0) return false;
    }
    return true;
  }

  // Every triangle that holds p (several when p is on an edge or a vertex).
  std::vector<size_t> Containing(const Point2& p) const {
    std::vector<size_t> out;
    for (size_t t = 0; t < loaded_.tin.triangles.size(); ++t) {
      if (Contains(t, p)) out.push_back(t);
    }
    return out;
  }

  // z of the plane through triangle t, by area coordinates in long double.
  long double ReferenceZ(size_t t, const Point2& p) const {
    const auto& v = loaded_.tin.triangles[t].v;
    const auto cross = [](const TinVertex& a, const TinVertex& b, const Point2& o) {
      return (static_cast<long double>(a.x) - o.x) * (static_cast<long double>(b.y) - o.y) -
             (static_cast<long double>(a.y) - o.y) * (static_cast<long double>(b.x) - o.x);
    };
    const TinVertex& a = loaded_.tin.vertices[v[0]];
    const TinVertex& b = loaded_.tin.vertices[v[1]];
    const TinVertex& c = loaded_.tin.vertices[v[2]];
    const long double area = cross(b, c, {a.x, a.y});
    return (cross(b, c, p) * a.z + cross(c, a, p) * b.z + cross(a, b, p) * c.z) / area;
  }

  size_t IndexOf(int64_t triangle_id) const {
    auto it =
        std::lower_bound(loaded_.triangle_ids.begin(), loaded_.triangle_ids.end(), triangle_id);
    EXPECT_TRUE(it != loaded_.triangle_ids.end() && *it == triangle_id);
    return static_cast<size_t>(it - loaded_.triangle_ids.begin());
  }

  // Locates p and compares with brute force; returns the walk's length (0 when outside).
  int ExpectAgreesWithBruteForce(const Point2& p) {
    const std::vector<size_t> holders = Containing(p);
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
    const size_t t = IndexOf(located->triangle);
    EXPECT_TRUE(std::find(holders.begin(), holders.end(), t) != holders.end())
        << "triangle " << located->triangle << " does not hold (" << p.x << ", " << p.y << ")";
    EXPECT_NEAR(located->z, static_cast<double>(ReferenceZ(holders.front(), p)), 1e-6);
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

}  // namespace
}  // namespace tinbase
