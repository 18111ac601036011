// The stored form of a mesh image (db/history/mesh_image.h, docs/format.md "Mesh images"): a
// round trip gives every row and key back, the digest sees every column, and bytes that are not an
// image (truncated, another zstd frame, a flipped flag) are Corruption naming the image.
#include "db/history/mesh_image.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace tinbase {
namespace {

MeshImage SampleImage() {
  MeshImage image;
  image.surface = 3;
  image.after_digest = 0x0123456789abcdefULL;
  TriangleRow t;
  t.v = {10, 11, 12};
  t.n = {std::optional<int64_t>(7), std::nullopt, std::optional<int64_t>(9)};
  t.visible = false;
  t.tag = 4;
  t.block = (int64_t{5} << 24) + 6;
  image.before.triangles[100] = t;
  image.before.triangles[101] = std::nullopt;  // made by the transaction
  image.before.vertices[10] =
      VertexRow{539300.25, 7497340.125, 612.0000000000001, VertexKind::kRing};
  image.before.vertices[13] = std::nullopt;
  image.before.constraints[{10, 11}] = {{std::nullopt, false}, {std::optional<int64_t>(2), true}};
  image.before.constraints[{11, 12}] = {};
  return image;
}

TEST(MeshImage, RoundTripGivesEveryRowBack) {
  const MeshImage image = SampleImage();
  const std::vector<uint8_t> bytes = EncodeMeshImage(image);
  auto back = DecodeMeshImage(bytes.data(), bytes.size(), "mesh image of transaction 5");
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  EXPECT_EQ(back->surface, 3);
  EXPECT_EQ(back->after_digest, image.after_digest);
  EXPECT_EQ(back->before.triangles, image.before.triangles);
  EXPECT_EQ(back->before.constraints, image.before.constraints);
  ASSERT_EQ(back->before.vertices.size(), 2u);
  const VertexRow& v = *back->before.vertices.at(10);
  EXPECT_EQ(v.x, 539300.25);
  EXPECT_EQ(v.z, 612.0000000000001);
  EXPECT_EQ(v.kind, VertexKind::kRing);
  EXPECT_FALSE(back->before.vertices.at(13).has_value());
  EXPECT_EQ(Digest(back->before), Digest(image.before));
}

TEST(MeshImage, TheDigestSeesEveryColumnAndKey) {
  const MeshRowSet base = SampleImage().before;
  std::vector<MeshRowSet> changed(6, base);
  changed[0].triangles[100]->n[1] = 8;
  changed[1].triangles[100]->tag.reset();
  changed[2].vertices[10]->z = 612;
  changed[3].vertices[13] = VertexRow{1, 2, 3, VertexKind::kDem};
  changed[4].constraints[{10, 11}][1].soft = false;
  changed[5].triangles.erase(101);
  for (size_t k = 0; k < changed.size(); ++k)
    EXPECT_NE(Digest(changed[k]), Digest(base)) << "change " << k;
}

TEST(MeshImage, BytesThatAreNotAnImageAreCorruption) {
  std::vector<uint8_t> bytes = EncodeMeshImage(SampleImage());
  const auto decode = [](const std::vector<uint8_t>& b) {
    return DecodeMeshImage(b.data(), b.size(), "mesh image of transaction 5");
  };
  std::vector<uint8_t> truncated(bytes.begin(), bytes.end() - 3);
  auto r = decode(truncated);
  EXPECT_EQ(r.status().code(), StatusCode::kCorruption);
  EXPECT_NE(r.status().message().find("mesh image of transaction 5: "), std::string::npos)
      << r.status().message();
  std::vector<uint8_t> header_only(bytes.begin(), bytes.begin() + 5);
  EXPECT_EQ(decode(header_only).status().code(), StatusCode::kCorruption);
  std::vector<uint8_t> wrong_size = bytes;
  wrong_size[0] ^= 1;
  EXPECT_EQ(decode(wrong_size).status().code(), StatusCode::kCorruption);
  EXPECT_EQ(decode({}).status().code(), StatusCode::kCorruption);
}

}  // namespace
}  // namespace tinbase
