// The pieces of tile negotiation on their own: header lists, the extensions an Accept asks for,
// gzip from Accept-Encoding, If-None-Match, taking extensions out of a tile, and the answer cache.
#include <gtest/gtest.h>
#include <httplib.h>

#include <memory>
#include <string>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "service/body_cache.h"
#include "service/entity_tag.h"
#include "service/gzip_body.h"
#include "service/header_lists.h"
#include "service/terrain_negotiation.h"
#include "service/terrain_tile.h"

namespace tinbase::service {
namespace {

httplib::Request RequestWith(const std::string& name, const std::string& value) {
  httplib::Request req;
  req.headers.emplace(name, value);
  return req;
}

TEST(HeaderListsTest, SplitsElementsParametersAndWeights) {
  const auto list = ParseHeaderList(
      "Application/Vnd.Quantized-Mesh;extensions=\"a-b,c\";q=0.5, */*;q=0.01,  ,text/html;q=x");
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].value, "application/vnd.quantized-mesh");
  EXPECT_EQ(list[0].params.at("extensions"), "a-b,c");  // quoted: the comma does not split
  EXPECT_DOUBLE_EQ(list[0].q, 0.5);
  EXPECT_EQ(list[1].value, "*/*");
  EXPECT_DOUBLE_EQ(list[1].q, 0.01);
  EXPECT_DOUBLE_EQ(list[2].q, 1);  // a malformed weight counts as 1
}

TEST(TerrainNegotiationTest, ReadsTheExtensionsCesiumAsksFor) {
  const TileExtensions all = RequestedTileExtensions(
      RequestWith("Accept",
                  "application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,"
                  "application/octet-stream;q=0.9,*/*;q=0.01"));
  EXPECT_TRUE(all.normals && all.water_mask && all.metadata);
  const TileExtensions none = RequestedTileExtensions(
      RequestWith("Accept", "application/vnd.quantized-mesh,application/octet-stream;q=0.9"));
  EXPECT_FALSE(none.normals || none.water_mask || none.metadata);
  const TileExtensions refused = RequestedTileExtensions(
      RequestWith("Accept", "application/vnd.quantized-mesh;extensions=watermask;q=0"));
  EXPECT_FALSE(refused.water_mask);
  const TileExtensions unknown = RequestedTileExtensions(
      RequestWith("Accept", "application/vnd.quantized-mesh;extensions=vertexnormals-metadata"));
  EXPECT_FALSE(unknown.normals);
  EXPECT_TRUE(unknown.metadata);
  EXPECT_FALSE(RequestedTileExtensions(httplib::Request()).normals);

  TileExtensions built;
  built.normals = built.metadata = true;
  const TileExtensions sent = CommonTileExtensions(built, all);
  EXPECT_EQ(TerrainContentType(sent),
            "application/vnd.quantized-mesh;extensions=octvertexnormals-metadata");
  EXPECT_EQ(TileExtensionsCode(sent), "nm");
  EXPECT_EQ(TerrainContentType(TileExtensions()), "application/vnd.quantized-mesh");
  EXPECT_EQ(TileExtensionsCode(TileExtensions()), "0");
}

TEST(GzipBodyTest, AcceptsGzipAsRfc9110Says) {
  EXPECT_FALSE(AcceptsGzip(httplib::Request()));
  for (const char* yes : {"gzip", "GZIP", "deflate, gzip;q=0.2", "x-gzip", "*", "br, *;q=0.1"})
    EXPECT_TRUE(AcceptsGzip(RequestWith("Accept-Encoding", yes))) << yes;
  for (const char* no : {"identity", "br", "gzip;q=0", "*;q=0", "*, gzip;q=0", ""})
    EXPECT_FALSE(AcceptsGzip(RequestWith("Accept-Encoding", no))) << no;
}

TEST(GzipBodyTest, WritesAGzipMember) {
  const std::string text(10000, 'a');
  auto zipped = Gzip(text);
  ASSERT_TRUE(zipped.ok());
  ASSERT_GE(zipped->size(), 18u);
  EXPECT_EQ(zipped->substr(0, 2), "\x1f\x8b");
  EXPECT_LT(zipped->size(), text.size() / 10);
}

TEST(EntityTagTest, ChangesWithTheContentAndTheVariantAndMatchesWeakly) {
  const std::string a = EntityTag("tile bytes", "nwm");
  EXPECT_EQ(a, EntityTag("tile bytes", "nwm"));
  EXPECT_NE(a, EntityTag("tile bytez", "nwm"));
  EXPECT_NE(a, EntityTag("tile bytes", "nwm.gz"));
  EXPECT_EQ(a.front(), '"');
  EXPECT_EQ(a.back(), '"');
  EXPECT_TRUE(IfNoneMatchHits(RequestWith("If-None-Match", a), a));
  EXPECT_TRUE(IfNoneMatchHits(RequestWith("If-None-Match", "W/" + a), a));
  EXPECT_TRUE(IfNoneMatchHits(RequestWith("If-None-Match", "\"x\",  " + a + " "), a));
  EXPECT_TRUE(IfNoneMatchHits(RequestWith("If-None-Match", "*"), a));
  EXPECT_FALSE(IfNoneMatchHits(RequestWith("If-None-Match", "\"x\""), a));
  EXPECT_FALSE(IfNoneMatchHits(RequestWith("If-None-Match", ""), a));
  EXPECT_FALSE(IfNoneMatchHits(httplib::Request(), a));
}

// A one-triangle tile with every extension.
QuantizedMesh SmallTile() {
  QuantizedMesh mesh;
  mesh.header.max_height = 10;
  mesh.u = {0, 32767, 0};
  mesh.v = {0, 0, 32767};
  mesh.height = {0, 100, 200};
  mesh.triangles = {0, 1, 2};
  mesh.west = {0, 2};
  mesh.south = {0, 1};
  mesh.east = {1};
  mesh.north = {2};
  mesh.normals = std::vector<uint8_t>(6, 128);
  mesh.water_mask = std::vector<uint8_t>{255};
  mesh.metadata = R"({"available":[]})";
  return mesh;
}

TEST(TerrainTileTest, TakesOutOnlyTheRefusedExtensions) {
  auto bytes = EncodeQuantizedMesh(SmallTile());
  ASSERT_TRUE(bytes.ok());
  const std::string stored(bytes->begin(), bytes->end());
  TileExtensions built;
  built.normals = built.water_mask = built.metadata = true;
  // Nothing refused: the stored bytes as they are.
  auto same = TileKeeping(stored, built, built, "t");
  ASSERT_TRUE(same.ok());
  EXPECT_EQ(*same, stored);
  TileExtensions keep;
  keep.water_mask = true;
  auto less = TileKeeping(stored, built, keep, "t");
  ASSERT_TRUE(less.ok());
  auto mesh = DecodeQuantizedMesh(std::vector<uint8_t>(less->begin(), less->end()), "t");
  ASSERT_TRUE(mesh.ok());
  QuantizedMesh expected = SmallTile();
  expected.normals.reset();
  expected.metadata.reset();
  EXPECT_EQ(*mesh, expected);
  // Bytes that do not decode are damage in the store.
  auto broken = TileKeeping(stored.substr(0, 40), built, keep, "tile 1/2/3");
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.status().code(), StatusCode::kCorruption);
  EXPECT_NE(broken.status().message().find("tile 1/2/3"), std::string::npos);
}

TEST(BodyCacheTest, KeepsTheMostRecentlyUsedWithinItsBudget) {
  BodyCache cache(400);
  const auto body = [](char c) { return std::make_shared<const std::string>(90, c); };
  cache.Put("a", body('a'));
  cache.Put("b", body('b'));
  cache.Put("c", body('c'));
  ASSERT_NE(cache.Find("a"), nullptr);  // a is now the most recent
  cache.Put("d", body('d'));
  cache.Put("e", body('e'));  // over budget: b, the least recent, goes
  EXPECT_EQ(cache.Find("b"), nullptr);
  EXPECT_EQ(*cache.Find("a"), std::string(90, 'a'));
  EXPECT_NE(cache.Find("e"), nullptr);
  cache.Put("big", std::make_shared<const std::string>(200, 'x'));  // over a quarter: not kept
  EXPECT_EQ(cache.Find("big"), nullptr);
}

}  // namespace
}  // namespace tinbase::service
