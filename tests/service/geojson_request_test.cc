// GeoJSON request bodies read into the editor's features: the geometry types, properties, the
// reprojection, and bad bodies refused with the place named.
#include "service/geojson_request.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace tinbase::service {
namespace {

Crs Utm32() { return *Crs::FromUserInput("EPSG:32632"); }

Result<std::vector<MemoryFeature>> Parse(const nlohmann::json& body,
                                         const std::optional<Crs>& source = std::nullopt) {
  return ParseGeoJsonFeatures(body.dump(), source, Utm32());
}

void ExpectRefused(const nlohmann::json& body, const std::string& expected) {
  auto r = Parse(body);
  ASSERT_FALSE(r.ok()) << body.dump();
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message().substr(0, expected.size()), expected);
}

nlohmann::json Feature(nlohmann::json geometry, nlohmann::json properties = nullptr) {
  return {{"type", "Feature"}, {"properties", std::move(properties)}, {"geometry", geometry}};
}

nlohmann::json Collection(std::vector<nlohmann::json> features) {
  return {{"type", "FeatureCollection"}, {"features", features}};
}

const nlohmann::json kSquare = {{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}}};

TEST(GeoJsonRequestTest, ReadsEveryLinearTypeWithItsProperties) {
  const nlohmann::json with_hole = {{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}},
                                    {{2, 2}, {2, 4}, {4, 4}, {4, 2}, {2, 2}}};
  auto r = Parse(Collection(
      {Feature({{"type", "Polygon"}, {"coordinates", kSquare}},
               {{"mode", "replace"}, {"level", 12.5}, {"tag", "pit"}, {"code", "A-1"}}),
       Feature({{"type", "MultiPolygon"},
                {"coordinates", {with_hole, {{{20, 0, 5}, {30, 0, 5}, {30, 10, 5}, {20, 0, 5}}}}}}),
       Feature({{"type", "LineString"}, {"coordinates", {{0, 0}, {0, 0}, {5, 5}}}},
               {{"mode", nullptr}, {"tag", nullptr}}),
       Feature({{"type", "MultiLineString"}, {"coordinates", {{{0, 0}, {1, 1}}, {{2, 2}, {3, 3}}}}},
               {{"mode", "breakline"}})}));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->size(), 4u);
  const MemoryFeature& pit = (*r)[0];
  EXPECT_EQ(pit.label, "features[0]");
  EXPECT_EQ(pit.mode, FeatureMode::kReplace);
  EXPECT_EQ(pit.level, 12.5);
  EXPECT_EQ(pit.tag, "pit");
  EXPECT_EQ(pit.attributes, nlohmann::json({{"code", "A-1"}}));
  ASSERT_EQ(pit.polygons.size(), 1u);
  EXPECT_EQ(pit.polygons[0].shell.size(), 4u) << "the closing vertex is dropped";
  const MemoryFeature& multi = (*r)[1];
  EXPECT_FALSE(multi.mode);
  ASSERT_EQ(multi.polygons.size(), 2u);
  EXPECT_EQ(multi.polygons[0].holes.size(), 1u);
  EXPECT_EQ(multi.polygons[1].shell.size(), 3u) << "z is dropped";
  ASSERT_EQ((*r)[2].lines.size(), 1u);
  ASSERT_EQ((*r)[2].lines[0].size(), 2u) << "repeated points are dropped";
  EXPECT_TRUE(SamePoint((*r)[2].lines[0][1], Point2{5, 5}));
  EXPECT_FALSE((*r)[2].mode) << "a null mode is no mode";
  EXPECT_FALSE((*r)[2].tag);
  EXPECT_EQ((*r)[3].lines.size(), 2u);
  EXPECT_EQ((*r)[3].mode, FeatureMode::kBreakline);
}

TEST(GeoJsonRequestTest, ReprojectsFromTheRequestsCrs) {
  // 9 E on the equator is the central meridian of UTM zone 32: easting 500000, northing 0.
  const nlohmann::json line = {{"type", "LineString"}, {"coordinates", {{9, 0}, {9, 1}}}};
  auto r = Parse(Feature(line), *Crs::FromUserInput("EPSG:4326"));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const auto& points = (*r)[0].lines[0];
  EXPECT_NEAR(points[0].x, 500000, 1e-6);
  EXPECT_NEAR(points[0].y, 0, 1e-6);
  EXPECT_NEAR(points[1].x, 500000, 1e-6);
  // The meridian arc of WGS 84 from 0 to 1 degree north (110574.389 m), times UTM's scale 0.9996.
  EXPECT_NEAR(points[1].y, 110530.159, 0.01);
  auto far = Parse(Feature({{"type", "LineString"}, {"coordinates", {{9, 0}, {9, 95}}}}),
                   *Crs::FromUserInput("EPSG:4326"));
  ASSERT_FALSE(far.ok());
  EXPECT_EQ(far.status().message().rfind("feature, line 0, vertex 1: (9, 95) cannot be reprojected "
                                         "from EPSG:4326 to EPSG:32632",
                                         0),
            0u)
      << far.status().message();
}

TEST(GeoJsonRequestTest, BadBodiesNameThePlace) {
  ExpectRefused(nlohmann::json("text"),
                "the body is string, not a GeoJSON Feature or FeatureCollection");
  ExpectRefused({{"features", nlohmann::json::array()}}, "the body: no \"type\" member");
  ExpectRefused({{"type", "FeatureCollection"}, {"features", 3}},
                "the FeatureCollection: \"features\" is number, not an array");
  ExpectRefused(Collection({Feature({{"type", "Polygon"}, {"coordinates", kSquare}}), 5}),
                "features[1] is number, not a Feature object");
  ExpectRefused(Collection({{{"type", "Polygon"}}}),
                "features[0]: type is \"Polygon\", not \"Feature\"");
  ExpectRefused(Feature(nullptr), "feature: the feature has no geometry");
  // Text from the request echoed in a message stays on one line (found by the fuzzer).
  ExpectRefused(Feature({{"type", "LineStri\ng"}, {"coordinates", nlohmann::json::array()}}),
                "feature: geometry is a LineStri\\ng; a Polygon");
  ExpectRefused(Feature({{"type", "Polygon"}}), "feature, geometry: no \"coordinates\" member");
  ExpectRefused(Feature({{"type", "GeometryCollection"}, {"coordinates", nlohmann::json::array()}}),
                "feature: geometry is a GeometryCollection; a Polygon, MultiPolygon, LineString "
                "or MultiLineString is needed");
  ExpectRefused(Feature({{"type", "MultiPolygon"}, {"coordinates", nlohmann::json::array()}}),
                "feature: the geometry is empty");
  ExpectRefused(Feature({{"type", "Polygon"}, {"coordinates", {{{0, 0}, {1}, {1, 1}, {0, 0}}}}}),
                "feature, ring 0, vertex 1: a position is an array of 2 or 3 numbers, got [1]");
  ExpectRefused(Feature({{"type", "MultiPolygon"},
                         {"coordinates", {kSquare, {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}}}}),
                "feature, polygon 1, ring 0: ring is not closed");
  ExpectRefused(
      Feature({{"type", "MultiLineString"}, {"coordinates", {{{0, 0}, {1, 1}}, {{2, 2}}}}}),
      "feature, line 1: a line needs at least 2 distinct points");
  ExpectRefused(Feature({{"type", "Polygon"}, {"coordinates", kSquare}}, {{"level", "high"}}),
                "feature: properties.level is \"high\", not a finite number");
  ExpectRefused(Feature({{"type", "Polygon"}, {"coordinates", kSquare}}, {1, 2}),
                "feature: properties are array, not an object");
  // A number beyond double's range is refused by the JSON reader itself (regression: it threw).
  auto huge = ParseGeoJsonFeatures(
      R"({"type":"Feature","geometry":{"type":"LineString","coordinates":[[0,0],[1e999,1]]}})",
      std::nullopt, Utm32());
  ASSERT_FALSE(huge.ok());
  EXPECT_EQ(huge.status().message(), "malformed JSON: number overflow parsing '1e999'");
}

// 3D lines: a line's z is kept when every vertex has one (a repeated point keeps the first z),
// reprojected with it; properties.z_from says whether the editor uses it.
TEST(GeoJsonRequestTest, KeepsTheZOfLinesAndReadsZFrom) {
  const nlohmann::json own_line = {{"type", "LineString"},
                                   {"coordinates", {{0, 0, 5.5}, {0, 0, 9}, {4, 3, 7.25}}}};
  const nlohmann::json mixed_lines = {
      {"type", "MultiLineString"}, {"coordinates", {{{0, 0, 1}, {1, 1}}, {{2, 2, 3}, {3, 3, 4}}}}};
  const nlohmann::json flat_line = {{"type", "LineString"}, {"coordinates", {{0, 0}, {1, 1}}}};
  auto r = Parse(Collection({Feature(own_line, {{"mode", "breakline"}, {"z_from", "feature"}}),
                             Feature(mixed_lines, {{"z_from", "dem"}}), Feature(flat_line)}));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  const MemoryFeature& own = (*r)[0];
  EXPECT_EQ(own.z_from, ZFrom::kFeature);
  EXPECT_FALSE(own.attributes.contains("z_from")) << own.attributes.dump();
  ASSERT_EQ(own.line_z.size(), 1u);
  EXPECT_EQ(own.line_z[0], (std::vector<double>{5.5, 7.25}));
  const MemoryFeature& mixed = (*r)[1];
  EXPECT_EQ(mixed.z_from, ZFrom::kDem);
  ASSERT_EQ(mixed.line_z.size(), 2u);
  EXPECT_TRUE(mixed.line_z[0].empty()) << "a line with a vertex without z has no z";
  EXPECT_EQ(mixed.line_z[1], (std::vector<double>{3, 4}));
  EXPECT_FALSE((*r)[2].z_from) << "no z_from: the request's or the editor's default";

  // From lon/lat to UTM 32 the heights stay as they are.
  const nlohmann::json lonlat_line = {{"type", "LineString"},
                                      {"coordinates", {{9, 0, 120.5}, {9, 0.01, 130.25}}}};
  auto lonlat = Parse(Feature(lonlat_line), *Crs::FromUserInput("EPSG:4326"));
  ASSERT_TRUE(lonlat.ok()) << lonlat.status().ToString();
  EXPECT_EQ((*lonlat)[0].line_z[0], (std::vector<double>{120.5, 130.25}));

  const nlohmann::json line = {{"type", "LineString"}, {"coordinates", {{0, 0, 1}, {1, 1, 2}}}};
  ExpectRefused(Feature(line, {{"z_from", "sky"}}),
                "feature: properties.z_from: unknown z source 'sky'");
  ExpectRefused(Feature(line, {{"z_from", 1}}), "feature: properties.z_from is number");
}

TEST(GeoJsonRequestTest, ReadsSurveyPointsWithTheirZ) {
  const auto points = [](const nlohmann::json& body) {
    return ParseGeoJsonPoints(body.dump(), std::nullopt, Utm32());
  };
  auto r = points(Collection(
      {Feature({{"type", "Point"}, {"coordinates", {1.5, 2.5, 3.5}}}),
       Feature({{"type", "MultiPoint"}, {"coordinates", {{4, 5, 6}, {7, 8, 9}}}}, {{"a", 1}})}));
  ASSERT_TRUE(r.ok()) << r.status().ToString();
  ASSERT_EQ(r->points.size(), 3u);
  EXPECT_EQ(r->points[0].z, 3.5);
  EXPECT_EQ(r->points[2].x, 7);
  EXPECT_EQ(r->labels, (std::vector<std::string>{"features[0], point 0", "features[1], point 0",
                                                 "features[1], point 1"}));
  const auto refused = [&](const nlohmann::json& body, const std::string& expected) {
    auto bad = points(body);
    ASSERT_FALSE(bad.ok()) << body.dump();
    EXPECT_EQ(bad.status().message().substr(0, expected.size()), expected);
  };
  refused(Feature({{"type", "MultiPoint"}, {"coordinates", {{4, 5, 6}, {7, 8}}}}),
          "feature, point 1: (7, 8) has no z (a survey point is x, y, z)");
  refused(Feature({{"type", "LineString"}, {"coordinates", {{0, 0, 1}, {1, 1, 2}}}}),
          "feature: geometry is a LineString; survey points are a Point or MultiPoint");
  refused(Feature({{"type", "MultiPoint"}, {"coordinates", nlohmann::json::array()}}),
          "feature: the geometry is empty");
  refused(Feature({{"type", "Point"}, {"coordinates", {1, 2, 3, 4}}}),
          "feature, vertex 0: a position is an array of 2 or 3 numbers");
  refused(Collection({}), "the FeatureCollection has no features");
}

}  // namespace
}  // namespace tinbase::service
