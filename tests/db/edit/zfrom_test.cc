// Lines with z from the feature (issue 28, item 2): a 3D line keeps its own z instead of the
// DEM's, linear between its vertices; where constrained lines cross, the crossing takes the z of
// the 3D line added last (a 3D line wins over a draped one); the DEM tolerance yields within a
// cell of a 3D line; `tinbase check --full` verifies the z (line-z); a z that is not a number is
// refused naming the feature, line and vertex, and the store is left unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "db/integrity_check.h"
#include "tests/support/edit_fixture.h"
#include "tests/support/line_features.h"
#include "tests/support/store_target.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::kEditCx;
using testing::kEditCy;

class ZFromTest : public testing::EditFixture {
 protected:
  double DemZ(const Point2& p) {
    auto z = dems_->Sample(dem_, p.x, p.y);
    EXPECT_TRUE(z.ok() && std::isfinite(*z)) << p.x << " " << p.y;
    return z.ok() ? *z : 0;
  }

  // Adds one line feature; returns its id.
  int64_t Add(FeatureMode mode, const std::vector<Point2>& points,
              const std::optional<std::vector<double>>& z) {
    auto report = testing::AddLines(*store_, {testing::LineFeature("line", mode, points, z)});
    EXPECT_TRUE(report.ok()) << report.status().ToString();
    return report.ok() ? report->first_feature_id : 0;
  }

  void ExpectIntact() { testing::ExpectStoreIntact(*store_, /*full=*/true); }

  // The z of every vertex of `feature`'s constraints, with its plan position.
  std::vector<std::pair<Point2, double>> VerticesOf(int64_t feature) {
    std::vector<std::pair<Point2, double>> out;
    for (const auto& c : testing::ConstraintsOf(*store_, feature)) {
      out.push_back({{c.ax, c.ay}, c.az});
      out.push_back({{c.bx, c.by}, c.bz});
    }
    EXPECT_FALSE(out.empty());
    return out;
  }

  // A GeoJSON file `name` of one LineString with `coordinates` (JSON text, as GDAL reads it) in
  // the DEM's CRS, and the options adding it as a breakline with z from the feature.
  PolygonAddOptions LineFileOptions(const std::string& name, const std::string& coordinates) {
    const std::string path = dir_.Path(name);
    std::ofstream(path) << R"({"type": "FeatureCollection", "crs": {"type": "name", "properties": )"
                        << R"({"name": "urn:ogc:def:crs:EPSG::28350"}}, "features": [{"type": )"
                        << R"("Feature", "properties": {}, "geometry": {"type": "LineString", )"
                        << R"("coordinates": )" << coordinates << "}}]}";
    PolygonAddOptions o;
    o.surface = "terrain";
    o.file = path;
    o.mode = FeatureMode::kBreakline;
    o.z_from = ZFrom::kFeature;
    return o;
  }

  const Point2 a_{kEditCx - 1500, kEditCy - 900}, b_{kEditCx + 1500, kEditCy + 1100};
  const Point2 c_{kEditCx - 1200, kEditCy + 1000}, d_{kEditCx + 1300, kEditCy - 1000};
};

// The z along segment p-q (z zp to zq) at the foot of x.
double Along(const Point2& p, double zp, const Point2& q, double zq, const Point2& x) {
  const double dx = q.x - p.x, dy = q.y - p.y;
  const double t = ((x.x - p.x) * dx + (x.y - p.y) * dy) / (dx * dx + dy * dy);
  return zp + t * (zq - zp);
}

// One 3D line per mode: its own z (offsets from the DEM at its ends), linear between its
// vertices, stored with the feature, its constraints of the mode's kind.
struct OwnZCase {
  const char* name;
  FeatureMode mode;
  double rise_a = 0;  // the line's z above the DEM at a_, and at b_
  double rise_b = 0;
  const char* kind;  // of its constraint rows
};

class ZFromOwnZTest : public ZFromTest, public ::testing::WithParamInterface<OwnZCase> {};

TEST_P(ZFromOwnZTest, ALineKeepsItsOwnZAndTheSurfaceStaysIntact) {
  const OwnZCase& line = GetParam();
  const double za = DemZ(a_) + line.rise_a, zb = DemZ(b_) + line.rise_b;
  const int64_t id = Add(line.mode, {a_, b_}, std::vector<double>{za, zb});
  for (const auto& c : testing::ConstraintsOf(*store_, id)) EXPECT_EQ(c.kind, line.kind);
  for (const auto& [p, z] : VerticesOf(id)) EXPECT_NEAR(z, Along(a_, za, b_, zb, p), 1e-6);
  auto stored = LoadFeature(*store_, surface_, id);
  ASSERT_TRUE(stored.ok());
  EXPECT_EQ(stored->z_from, ZFrom::kFeature);
  EXPECT_EQ(stored->line_z, (std::vector<std::vector<double>>{{za, zb}}));
  ExpectIntact();
}

// The breakline's z is 40 m above the DEM at one end and 30 m below at the other: far beyond the
// 5 m tolerance.
INSTANTIATE_TEST_SUITE_P(
    Modes, ZFromOwnZTest,
    ::testing::Values(OwnZCase{"Breakline", FeatureMode::kBreakline, 40, -30, "hard"},
                      OwnZCase{"Softline", FeatureMode::kSoftline, 12, 12, "soft"}),
    [](const ::testing::TestParamInfo<OwnZCase>& info) { return std::string(info.param.name); });

// Two 3D lines cross: the crossing is a vertex of both at the later line's z (the earlier one
// bends there). A draped breakline across the later line takes its z at their crossing too.
TEST_F(ZFromTest, WhereLinesCrossTheLaterThreeDLineGivesTheZ) {
  const double first_z = DemZ(a_) + 50, later_z = DemZ(c_) + 80;
  const int64_t first =
      Add(FeatureMode::kBreakline, {a_, b_}, std::vector<double>{first_z, first_z});
  const int64_t later =
      Add(FeatureMode::kBreakline, {c_, d_}, std::vector<double>{later_z, later_z});
  int bent = 0;
  for (const auto& [p, z] : VerticesOf(first)) {
    if (z == first_z) continue;
    EXPECT_EQ(z, later_z) << "at " << p.x << ", " << p.y;
    ++bent;
  }
  EXPECT_EQ(bent, 2) << "the crossing vertex, once per constraint on each side";
  for (const auto& [p, z] : VerticesOf(later)) EXPECT_EQ(z, later_z);
  ExpectIntact();

  const Point2 e{kEditCx + 600, kEditCy - 1400}, f{kEditCx + 900, kEditCy + 1400};
  const int64_t draped = Add(FeatureMode::kBreakline, {e, f}, std::nullopt);
  int on_later = 0;
  for (const auto& [p, z] : VerticesOf(draped)) on_later += z == later_z;
  EXPECT_EQ(on_later, 2) << "the draped line's crossing with the 3D line";
  ExpectIntact();
}

TEST_F(ZFromTest, CheckReportsAVertexOffItsLinesZ) {
  const double za = DemZ(a_) + 40, zb = DemZ(b_) + 40;
  const int64_t id = Add(FeatureMode::kBreakline, {a_, b_}, std::vector<double>{za, zb});
  const auto c = testing::ConstraintsOf(*store_, id).front();
  ASSERT_TRUE(
      store_->db().Exec("UPDATE vertices SET z = z + 3 WHERE id = " + std::to_string(c.va)).ok());
  auto problems = CheckStore(*store_, {.surface = {}, .full = true});
  ASSERT_TRUE(problems.ok());
  ASSERT_FALSE(problems->empty());
  EXPECT_EQ(problems->front().code, "line-z");
  EXPECT_NE(problems->front().message.find("vertex " + std::to_string(c.va) + " at "),
            std::string::npos)
      << problems->front().message;
  EXPECT_NE(problems->front().message.find("on 3D line feature " + std::to_string(id)),
            std::string::npos)
      << problems->front().message;
}

TEST_F(ZFromTest, ANanZIsRefusedNamingTheFeatureAndVertexAndChangesNothing) {
  const auto before = testing::TableChecksums(testing::StoreTarget(dir_, "s.tinbase"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto report = testing::AddLines(
      *store_, {testing::LineFeature("features[0]", FeatureMode::kBreakline, {a_, c_, b_},
                                     std::vector<double>{500, nan, 600})});
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(report.status().message(), "features[0], line 0, vertex 1: z is not a number");

  // The same from a file: GeoJSON's NaN, as GDAL reads it.
  auto from_file = AddPolygons(
      *store_, LineFileOptions("nan.geojson", "[[539000, 7497000, 500], [539600, 7497500, NaN]]"));
  ASSERT_FALSE(from_file.ok());
  EXPECT_EQ(from_file.status().message(),
            "nan.geojson feature 0, line 0, vertex 1: z is not a number");
  EXPECT_EQ(testing::TableChecksums(testing::StoreTarget(dir_, "s.tinbase")), before);
}

TEST_F(ZFromTest, ZFromTheFeatureNeedsLinesWithZ) {
  PolygonAddOptions o = LineFileOptions("flat.geojson", "[[539000, 7497000], [539600, 7497500]]");
  auto flat = AddPolygons(*store_, o);
  ASSERT_FALSE(flat.ok());
  EXPECT_EQ(flat.status().message(),
            "flat.geojson feature 0: --z-from feature needs lines with z (LineString Z)");
  o.mode = FeatureMode::kFill;
  auto fill = AddPolygons(*store_, o);
  ASSERT_FALSE(fill.ok());
  EXPECT_EQ(fill.status().message(),
            "--z-from feature is for lines (modes breakline and softline), not mode fill");
}

}  // namespace
}  // namespace tinbase
