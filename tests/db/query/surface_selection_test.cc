// SelectSurface: a window, visibility and tag select exactly the triangles a brute-force test
// over the whole surface selects, with their neighbours re-linked inside the selection; empty
// selections and bad boxes are refused with messages naming them.
#include "db/query/surface_selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/geometry/predicates.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::TempDir;

Point2 P(const TinVertex& v) { return {v.x, v.y}; }

bool SegmentsCross(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  const int o1 = Orientation(a, b, c), o2 = Orientation(a, b, d);
  const int o3 = Orientation(c, d, a), o4 = Orientation(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  const auto on = [](const Point2& p, const Point2& q, const Point2& r) {
    return std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= r.y &&
           r.y <= std::max(p.y, q.y);
  };
  return (o1 == 0 && on(a, b, c)) || (o2 == 0 && on(a, b, d)) || (o3 == 0 && on(c, d, a)) ||
         (o4 == 0 && on(c, d, b));
}

// Triangle meets box: a vertex inside the box, a box corner inside the triangle, or crossing
// edges (independent of the separating-axis test the library uses).
bool MeetsByBruteForce(const Tin& tin, const TinTriangle& t, const Box& box) {
  const Point2 a = P(tin.vertices[t.v[0]]), b = P(tin.vertices[t.v[1]]),
               c = P(tin.vertices[t.v[2]]);
  for (const Point2& p : {a, b, c})
    if (box.Contains(p)) return true;
  const Point2 corners[4] = {{box.min_x, box.min_y},
                             {box.max_x, box.min_y},
                             {box.max_x, box.max_y},
                             {box.min_x, box.max_y}};
  for (const Point2& q : corners)
    if (Orientation(a, b, q) >= 0 && Orientation(b, c, q) >= 0 && Orientation(c, a, q) >= 0)
      return true;
  const Point2 tri[3] = {a, b, c};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (SegmentsCross(tri[i], tri[(i + 1) % 3], corners[j], corners[(j + 1) % 4])) return true;
  return false;
}

class SurfaceSelectionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::RandomTinOptions options;
    options.points = 1500;
    options.ring = true;
    Tin tin = testing::RandomDelaunayTin(options);
    // Hide every fifth triangle so visibility filters have something to drop.
    for (size_t t = 0; t < tin.triangles.size(); t += 5) tin.triangles[t].visible = false;
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    auto info = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    info_ = *info;
    ASSERT_TRUE((*tx)->Commit().ok());
    auto all = SurfaceStore(*store_).Load(info_);
    ASSERT_TRUE(all.ok());
    all_ = std::move(*all);
  }

  // Store ids of the triangles of the whole surface that `keep` accepts.
  template <typename Keep>
  std::set<int64_t> Expected(Keep keep) const {
    std::set<int64_t> out;
    for (size_t t = 0; t < all_.tin.triangles.size(); ++t)
      if (keep(all_.tin.triangles[t])) out.insert(all_.triangle_ids[t]);
    return out;
  }

  // The selection is `expected`, compact, and linked only inside itself.
  void ExpectSelection(const SurfaceFilter& filter, const std::set<int64_t>& expected) {
    auto got = SelectSurface(*store_, info_, filter);
    ASSERT_TRUE(got.ok()) << got.status().ToString();
    EXPECT_EQ(std::set<int64_t>(got->triangle_ids.begin(), got->triangle_ids.end()), expected);
    EXPECT_TRUE(std::is_sorted(got->triangle_ids.begin(), got->triangle_ids.end()));
    std::set<uint32_t> used;
    for (const TinTriangle& t : got->tin.triangles) used.insert(t.v.begin(), t.v.end());
    EXPECT_EQ(used.size(), got->tin.vertices.size()) << "unused vertices were kept";
    Tin relinked = got->tin;
    ASSERT_TRUE(LinkNeighbours(relinked));
    for (size_t t = 0; t < relinked.triangles.size(); ++t)
      EXPECT_EQ(relinked.triangles[t].n, got->tin.triangles[t].n) << "triangle " << t;
    for (size_t v = 0; v < got->tin.vertices.size(); ++v) {
      const auto it = std::find(all_.vertex_ids.begin(), all_.vertex_ids.end(), got->vertex_ids[v]);
      ASSERT_NE(it, all_.vertex_ids.end());
      EXPECT_EQ(all_.tin.vertices[it - all_.vertex_ids.begin()].x, got->tin.vertices[v].x);
    }
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo info_;
  LoadedSurface all_;
};

TEST_F(SurfaceSelectionTest, WindowSelectsEveryTriangleThatMeetsIt) {
  for (const Box& box :
       {Box{601000, 5102000, 603500, 5104000}, Box{605000, 5105000, 605000, 5105000},
        Box{599000, 5099000, 600500, 5111000}}) {
    SurfaceFilter filter;
    filter.bbox = box;
    ExpectSelection(filter, Expected([&](const TinTriangle& t) {
                      return MeetsByBruteForce(all_.tin, t, box);
                    }));
  }
}

TEST_F(SurfaceSelectionTest, TinyWindowInsideOneTriangleFindsIt) {
  const TinTriangle& t = all_.tin.triangles[all_.tin.triangles.size() / 2];
  const auto& v = all_.tin.vertices;
  const double cx = (v[t.v[0]].x + v[t.v[1]].x + v[t.v[2]].x) / 3;
  const double cy = (v[t.v[0]].y + v[t.v[1]].y + v[t.v[2]].y) / 3;
  SurfaceFilter filter;
  filter.bbox = Box{cx - 1e-3, cy - 1e-3, cx + 1e-3, cy + 1e-3};
  ExpectSelection(filter, Expected([&](const TinTriangle& u) {
                    return MeetsByBruteForce(all_.tin, u, *filter.bbox);
                  }));
}

TEST_F(SurfaceSelectionTest, VisibilityAndTagCombineWithTheWindow) {
  SurfaceFilter filter;
  filter.visible_only = true;
  ExpectSelection(filter, Expected([](const TinTriangle& t) { return t.visible; }));
  filter.tag = "granite";
  const auto granite = [&](const TinTriangle& t) {
    return t.tag != kNoTag && all_.tin.tags[t.tag] == "granite";
  };
  ExpectSelection(filter, Expected([&](const TinTriangle& t) { return t.visible && granite(t); }));
  filter.bbox = Box{604000, 5104000, 605500, 5106000};
  ExpectSelection(filter, Expected([&](const TinTriangle& t) {
                    return t.visible && granite(t) && MeetsByBruteForce(all_.tin, t, *filter.bbox);
                  }));
}

TEST_F(SurfaceSelectionTest, WholeSurfaceWhenNothingIsSet) {
  ExpectSelection(SurfaceFilter{},
                  std::set<int64_t>(all_.triangle_ids.begin(), all_.triangle_ids.end()));
}

TEST_F(SurfaceSelectionTest, EmptySelectionsAreNotFoundNamingTheFilter) {
  SurfaceFilter filter;
  filter.bbox = Box{0, 0, 10, 10};
  auto got = SelectSurface(*store_, info_, filter);
  ASSERT_EQ(got.status().code(), StatusCode::kNotFound);
  EXPECT_NE(got.status().message().find("nothing selected"), std::string::npos);
  EXPECT_NE(got.status().message().find("bbox 0,0,10,10"), std::string::npos)
      << got.status().message();
  filter = SurfaceFilter{};
  filter.tag = "basalt";
  got = SelectSurface(*store_, info_, filter);
  ASSERT_EQ(got.status().code(), StatusCode::kNotFound);
  EXPECT_NE(got.status().message().find("tag 'basalt'"), std::string::npos);
  filter = SurfaceFilter{};
  filter.feature = 99;
  got = SelectSurface(*store_, info_, filter);
  ASSERT_EQ(got.status().code(), StatusCode::kNotFound);
  EXPECT_NE(got.status().message().find("99"), std::string::npos) << got.status().message();
}

TEST(ParseBboxTest, ReadsFourNumbersAndRefusesTheRest) {
  auto box = ParseBbox("1,2.5,3,4e1");
  ASSERT_TRUE(box.ok());
  EXPECT_EQ(box->min_x, 1);
  EXPECT_EQ(box->min_y, 2.5);
  EXPECT_EQ(box->max_x, 3);
  EXPECT_EQ(box->max_y, 40);
  EXPECT_TRUE(ParseBbox("-5 -6 7 8").ok());
  for (const char* bad : {"", "1,2,3", "1,2,3,4,5", "a,b,c,d", "1,2,nan,4", "3,2,1,4", "1,2,3,x"}) {
    auto r = ParseBbox(bad);
    EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(r.status().message().find(std::string("'") + bad + "'"), std::string::npos)
        << r.status().message();
  }
}

}  // namespace
}  // namespace tinbase
