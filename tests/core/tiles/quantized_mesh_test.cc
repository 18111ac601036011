// QuantizedMesh: the two public sample tiles decode with the counts their publisher states and
// re-encode to the same bytes; generated tiles with every extension round-trip; truncated and
// hostile bytes are refused naming the part and the offset; oct normals survive encoding.
#include "core/tiles/quantized_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>

#include "tests/support/test_support.h"

namespace tinbase {
namespace {

std::vector<uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(QuantizedMeshTest, SampleTilesDecodeAndReencodeByteForByte) {
  const std::string plain = testing::DataPath("terrain/9_533_383.terrain");
  const std::vector<uint8_t> bytes = ReadBytes(plain);
  ASSERT_FALSE(bytes.empty()) << plain;
  auto mesh = DecodeQuantizedMesh(bytes, plain);
  ASSERT_TRUE(mesh.ok()) << mesh.status().ToString();
  EXPECT_EQ(mesh->vertex_count(), 103u);
  EXPECT_EQ(mesh->triangles.size(), 127u * 3);
  EXPECT_EQ(mesh->west.size(), 30u);
  EXPECT_FALSE(mesh->water_mask.has_value());
  EXPECT_NEAR(mesh->header.min_height, 206.34, 0.01);
  EXPECT_NEAR(mesh->header.max_height, 787.94, 0.01);
  auto again = EncodeQuantizedMesh(*mesh);
  ASSERT_TRUE(again.ok()) << again.status().ToString();
  EXPECT_EQ(*again, bytes);

  const std::string water = testing::DataPath("terrain/9_769_319_watermask.terrain");
  const std::vector<uint8_t> water_bytes = ReadBytes(water);
  auto water_mesh = DecodeQuantizedMesh(water_bytes, water);
  ASSERT_TRUE(water_mesh.ok()) << water_mesh.status().ToString();
  EXPECT_EQ(water_mesh->vertex_count(), 4u);
  EXPECT_EQ(water_mesh->triangles.size(), 6u);
  ASSERT_TRUE(water_mesh->water_mask.has_value());
  EXPECT_EQ(water_mesh->water_mask->size(), 65536u);
  auto water_again = EncodeQuantizedMesh(*water_mesh);
  ASSERT_TRUE(water_again.ok());
  EXPECT_EQ(*water_again, water_bytes);
}

// A regular grid of n x n vertices over the tile, two triangles per cell, with heights from a
// bowl, in first-use order.
QuantizedMesh GridMesh(int n) {
  QuantizedMesh mesh;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh.u.push_back(static_cast<uint16_t>(i * kQuantizedMax / (n - 1)));
      mesh.v.push_back(static_cast<uint16_t>(j * kQuantizedMax / (n - 1)));
      const double dx = i - (n - 1) / 2.0, dy = j - (n - 1) / 2.0;
      mesh.height.push_back(static_cast<uint16_t>(std::lround(
          kQuantizedMax * (dx * dx + dy * dy) / (2 * ((n - 1) / 2.0) * ((n - 1) / 2.0)))));
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const auto at = [n](int x, int y) { return static_cast<uint32_t>(y * n + x); };
      mesh.triangles.insert(mesh.triangles.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.insert(mesh.triangles.end(), {at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int k = 0; k < n; ++k) {
    mesh.west.push_back(static_cast<uint32_t>(k * n));
    mesh.east.push_back(static_cast<uint32_t>(k * n + n - 1));
    mesh.south.push_back(static_cast<uint32_t>(k));
    mesh.north.push_back(static_cast<uint32_t>((n - 1) * n + k));
  }
  OrderVerticesByFirstUse(mesh);
  mesh.header.min_height = 100;
  mesh.header.max_height = 250.5f;
  mesh.header.center_x = 4492197.25;
  mesh.header.horizon_z = 0.5;
  return mesh;
}

TEST(QuantizedMeshTest, GeneratedTilesWithEveryExtensionRoundTrip) {
  for (int n : {2, 17, 300}) {  // 300 x 300 vertices needs 32-bit indices
    QuantizedMesh mesh = GridMesh(n);
    mesh.normals.emplace(2 * mesh.vertex_count());
    for (size_t i = 0; i < mesh.vertex_count(); ++i)
      OctEncodeNormal(0.1, -0.2, 0.97, &(*mesh.normals)[2 * i]);
    mesh.water_mask.emplace(65536, 0);
    (*mesh.water_mask)[1234] = 255;
    mesh.metadata = R"({"available":[[{"startX":0,"startY":0,"endX":1,"endY":1}]]})";
    auto bytes = EncodeQuantizedMesh(mesh);
    ASSERT_TRUE(bytes.ok()) << bytes.status().ToString();
    auto back = DecodeQuantizedMesh(*bytes, "generated");
    ASSERT_TRUE(back.ok()) << back.status().ToString();
    EXPECT_EQ(*back, mesh) << n << " x " << n;
  }
}

TEST(QuantizedMeshTest, EncoderRefusesMeshesItCannotWrite) {
  QuantizedMesh mesh = GridMesh(3);
  std::swap(mesh.triangles[0], mesh.triangles[1]);  // vertex 1 used before vertex 0
  EXPECT_NE(EncodeQuantizedMesh(mesh).status().message().find("first-use order"),
            std::string::npos);
  mesh = GridMesh(3);
  mesh.v.pop_back();
  EXPECT_EQ(EncodeQuantizedMesh(mesh).status().code(), StatusCode::kInvalidArgument);
  mesh = GridMesh(3);
  mesh.west.push_back(99);
  EXPECT_NE(EncodeQuantizedMesh(mesh).status().message().find("edge vertex 99"), std::string::npos);
  mesh = GridMesh(3);
  mesh.water_mask.emplace(10, 0);
  EXPECT_EQ(EncodeQuantizedMesh(mesh).status().code(), StatusCode::kInvalidArgument);
}

TEST(QuantizedMeshTest, DecoderRefusesEveryTruncationNamingTheOffset) {
  QuantizedMesh mesh = GridMesh(5);
  mesh.metadata = "{}";
  auto bytes = EncodeQuantizedMesh(mesh);
  ASSERT_TRUE(bytes.ok());
  for (size_t keep = 0; keep < bytes->size(); ++keep) {
    std::vector<uint8_t> cut(bytes->begin(), bytes->begin() + static_cast<ptrdiff_t>(keep));
    auto r = DecodeQuantizedMesh(cut, "cut.terrain");
    // Cutting exactly between the edge lists and the extensions leaves a valid tile.
    if (r.ok()) {
      EXPECT_FALSE(r->metadata.has_value()) << keep;
      continue;
    }
    EXPECT_NE(r.status().message().find("cut.terrain: "), std::string::npos);
    EXPECT_NE(r.status().message().find("(at byte "), std::string::npos) << r.status().message();
  }
}

TEST(QuantizedMeshTest, DecoderRefusesHostileCounts) {
  QuantizedMesh mesh = GridMesh(3);
  auto bytes = EncodeQuantizedMesh(mesh);
  ASSERT_TRUE(bytes.ok());
  std::vector<uint8_t> huge = *bytes;
  const uint32_t lots = 0x7fffffff;
  std::memcpy(huge.data() + 88, &lots, 4);  // the vertex count
  auto r = DecodeQuantizedMesh(huge, "huge.terrain");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("vertex count says 2147483647 items"), std::string::npos)
      << r.status().message();
  std::vector<uint8_t> bad_index = *bytes;
  // The first triangle index code sits after the vertex columns and the triangle count.
  const size_t first_code = 88 + 4 + 6 * mesh.vertex_count() + 4;
  bad_index[first_code] = 7;
  r = DecodeQuantizedMesh(bad_index, "bad.terrain");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("above the high-water mark"), std::string::npos)
      << r.status().message();
  std::vector<uint8_t> gz = {0x1f, 0x8b, 8, 0};
  EXPECT_NE(DecodeQuantizedMesh(gz, "z.terrain").status().message().find("gzipped"),
            std::string::npos);
}

TEST(QuantizedMeshTest, OctNormalsComeBackWithinAFewDegrees) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int i = 0; i < 2000; ++i) {
    double x = g(rng), y = g(rng), z = g(rng);
    const double l = std::sqrt(x * x + y * y + z * z);
    x /= l, y /= l, z /= l;
    uint8_t code[2];
    OctEncodeNormal(x, y, z, code);
    double dx = 0, dy = 0, dz = 0;
    OctDecodeNormal(code, &dx, &dy, &dz);
    EXPECT_GT(x * dx + y * dy + z * dz, std::cos(2.0 * M_PI / 180)) << x << " " << y << " " << z;
  }
}

}  // namespace
}  // namespace tinbase
