// The MultiPoint Z codec of `points` features (core/vector/point_wkb.h): a round trip keeps every
// coordinate to the bit, OGR reads what we write as a 3D MultiPoint, and bad blobs are refused.
#include <gtest/gtest.h>
#include <ogr_geometry.h>

#include <memory>
#include <vector>

#include "core/vector/point_wkb.h"

namespace tinbase {
namespace {

TEST(MassPointsWkb, RoundTripKeepsEveryBitAndOgrReadsAMultiPointZ) {
  const std::vector<TinVertex> points = {{539300.12345678901, 7497340.9876543211, 701.25},
                                         {-0.1, 1e-300, -12.5},
                                         {539300.12345678901, 7497340.9876543211, 0}};
  const std::vector<uint8_t> wkb = PointsToWkb(points);
  auto back = PointsFromWkb(wkb);
  ASSERT_TRUE(back.ok()) << back.status().ToString();
  ASSERT_EQ(back->size(), points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ((*back)[i].x, points[i].x);
    EXPECT_EQ((*back)[i].y, points[i].y);
    EXPECT_EQ((*back)[i].z, points[i].z);
    EXPECT_EQ((*back)[i].kind, VertexKind::kUser);
  }
  OGRGeometry* raw = nullptr;
  ASSERT_EQ(OGRGeometryFactory::createFromWkb(wkb.data(), nullptr, &raw, wkb.size()), OGRERR_NONE);
  std::unique_ptr<OGRGeometry> g(raw);
  EXPECT_EQ(g->getGeometryType(), wkbMultiPoint25D);
  EXPECT_EQ(g->toMultiPoint()->getNumGeometries(), 3);
  EXPECT_EQ(g->toMultiPoint()->getGeometryRef(0)->getZ(), 701.25);
}

TEST(MassPointsWkb, BadBlobsAreCorruption) {
  EXPECT_EQ(PointsFromWkb({1, 2, 3}).status().code(), StatusCode::kCorruption);
  OGRLineString line;
  line.addPoint(0, 0, 1);
  line.addPoint(1, 1, 1);
  std::vector<uint8_t> wkb(line.WkbSize());
  line.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
  auto r = PointsFromWkb(wkb);
  EXPECT_EQ(r.status().code(), StatusCode::kCorruption);
  EXPECT_NE(r.status().message().find("not a point geometry"), std::string::npos);
  OGRMultiPoint flat;
  OGRPoint p(1, 2);
  flat.addGeometry(&p);
  wkb.assign(flat.WkbSize(), 0);
  flat.exportToWkb(wkbNDR, wkb.data(), wkbVariantIso);
  EXPECT_NE(PointsFromWkb(wkb).status().message().find("no z"), std::string::npos);
}

}  // namespace
}  // namespace tinbase
