// The LAS reader on the real PDAL test files (LAS 1.2 and 1.4, formats 1, 3 and 7, CRS from the
// WKT record and from GeoKeys) and on broken copies of them made here.
#include "core/pointcloud/las_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <random>
#include <vector>

#include "core/geometry/reproject.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::DataPath;
using testing::TempDir;

std::vector<char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <typename T>
void Put(std::vector<char>& bytes, size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

LasFile ReadOrDie(const std::string& relative) {
  auto las = ReadLas(DataPath(relative));
  EXPECT_TRUE(las.ok()) << las.status().ToString();
  return las.ok() ? std::move(las).value() : LasFile{};
}

// Every point inside the header's bounds, and the bounds reached (to half a scale step, as
// writers round the bounds they store).
void ExpectBoundsMatchHeader(const LasFile& las) {
  ASSERT_FALSE(las.cloud.points.empty());
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const CloudPoint& p : las.cloud.points) {
    const double c[3] = {p.x, p.y, p.z};
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], c[i]);
      hi[i] = std::max(hi[i], c[i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    const double tol = las.header.scale[i] / 2 + 1e-9 * std::abs(las.header.max[i]);
    EXPECT_NEAR(lo[i], las.header.min[i], tol) << "axis " << i;
    EXPECT_NEAR(hi[i], las.header.max[i], tol) << "axis " << i;
  }
}

TEST(LasReader, AutzenLas12Format3) {
  const LasFile las = ReadOrDie("las/autzen_trim.las");
  EXPECT_EQ(las.header.version_major, 1);
  EXPECT_EQ(las.header.version_minor, 2);
  EXPECT_EQ(las.header.point_format, 3);
  EXPECT_EQ(las.header.record_length, 34);
  EXPECT_EQ(las.header.point_count, 110000u);
  EXPECT_EQ(las.cloud.points.size(), 110000u);
  ExpectBoundsMatchHeader(las);
  // Oregon GIC Lambert in feet, from the WKT record (the GeoKeys are user-defined).
  ASSERT_TRUE(las.cloud.crs.has_value());
  EXPECT_FALSE(las.cloud.crs->IsGeographic());
  EXPECT_NE(las.cloud.crs->Wkt().find("Lambert"), std::string::npos) << las.cloud.crs->Wkt();

  std::map<int, size_t> classes;
  for (const CloudPoint& p : las.cloud.points) {
    ++classes[p.classification];
    EXPECT_GE(p.return_number, 1);
  }
  EXPECT_GT(classes[2], 10000u) << "autzen has ground points";
}

TEST(LasReader, AutzenLas14Format7GivesTheSamePoints) {
  const LasFile las12 = ReadOrDie("las/autzen_trim.las");
  const LasFile las14 = ReadOrDie("las/autzen_trim_7.las");
  EXPECT_EQ(las14.header.version_minor, 4);
  EXPECT_EQ(las14.header.point_format, 7);
  EXPECT_EQ(las14.header.record_length, 36);
  EXPECT_EQ(las14.header.header_size, 375);
  ASSERT_EQ(las14.cloud.points.size(), 110000u);
  ASSERT_EQ(las12.cloud.points.size(), las14.cloud.points.size());
  ExpectBoundsMatchHeader(las14);
  size_t different_xyz = 0, different_class = 0, different_return = 0;
  for (size_t i = 0; i < las12.cloud.points.size(); ++i) {
    const CloudPoint& a = las12.cloud.points[i];
    const CloudPoint& b = las14.cloud.points[i];
    if (a.x != b.x || a.y != b.y || a.z != b.z) ++different_xyz;
    if (a.classification != b.classification) ++different_class;
    if (a.return_number != b.return_number) ++different_return;
  }
  EXPECT_EQ(different_xyz, 0u);
  EXPECT_EQ(different_class, 0u);
  EXPECT_EQ(different_return, 0u);
  // The two WKT records differ in the datum's name ("... Regional Network" / "... Reference
  // Network"), so OGR does not call them the same; they are the same projection, which is what
  // matters: a point moves by nothing from one to the other.
  ASSERT_TRUE(las12.cloud.crs && las14.cloud.crs);
  std::vector<TinVertex> corners = {{las12.header.min[0], las12.header.min[1], 0},
                                    {las12.header.max[0], las12.header.max[1], 0}};
  const std::vector<TinVertex> before = corners;
  ASSERT_TRUE(ReprojectXy(*las12.cloud.crs, *las14.cloud.crs, corners).ok());
  for (size_t i = 0; i < corners.size(); ++i) {
    EXPECT_NEAR(corners[i].x, before[i].x, 1e-6);
    EXPECT_NEAR(corners[i].y, before[i].y, 1e-6);
  }
}

TEST(LasReader, NewMexicoTileCrsFromGeoKeys) {
  const LasFile las = ReadOrDie("las/4_6_crop.las");
  EXPECT_EQ(las.header.point_format, 3);
  EXPECT_EQ(las.cloud.points.size(), 23875u);
  ExpectBoundsMatchHeader(las);
  ASSERT_TRUE(las.cloud.crs.has_value());
  EXPECT_EQ(las.cloud.crs->Epsg(), 2903);
}

TEST(LasReader, MississippiFormat1CrsFromGeoKeys) {
  const LasFile las = ReadOrDie("las/mvk-thin.las");
  EXPECT_EQ(las.header.point_format, 1);
  EXPECT_EQ(las.header.record_length, 28);
  EXPECT_EQ(las.cloud.points.size(), 6280u);
  ExpectBoundsMatchHeader(las);
  ASSERT_TRUE(las.cloud.crs.has_value());
  EXPECT_EQ(las.cloud.crs->Epsg(), 26995);
}

TEST(LasReader, HeaderAloneAgreesWithFullRead) {
  auto header = ReadLasHeader(DataPath("las/mvk-thin.las"));
  ASSERT_TRUE(header.ok()) << header.status().ToString();
  EXPECT_EQ(header->point_count, 6280u);
  EXPECT_EQ(header->point_format, 1);
}

TEST(LasReader, MinimumSizesFollowTheSpecification) {
  EXPECT_EQ(LasMinimumHeaderSize(0), 227);
  EXPECT_EQ(LasMinimumHeaderSize(2), 227);
  EXPECT_EQ(LasMinimumHeaderSize(3), 235);
  EXPECT_EQ(LasMinimumHeaderSize(4), 375);
  const uint16_t expected[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  for (uint8_t f = 0; f <= 10; ++f) EXPECT_EQ(LasMinimumRecordLength(f), expected[f]) << int(f);
}

// A broken copy of mvk-thin.las (LAS 1.2, format 1) is refused with a message naming the file
// and the problem.
class BrokenLas : public ::testing::Test {
 protected:
  void SetUp() override { bytes_ = ReadBytes(DataPath("las/mvk-thin.las")); }

  Status Read(const std::string& name) {
    const std::string path = dir_.Path(name);
    WriteBytes(path, bytes_);
    auto las = ReadLas(path);
    if (las.ok()) return Status::Ok();
    EXPECT_NE(las.status().message().find(path), std::string::npos) << las.status().ToString();
    return las.status();
  }

  static bool Says(const Status& s, const std::string& text) {
    return s.message().find(text) != std::string::npos;
  }

  TempDir dir_;
  std::vector<char> bytes_;
};

TEST_F(BrokenLas, UntouchedCopyReads) { EXPECT_TRUE(Read("copy.las").ok()); }

TEST_F(BrokenLas, WrongSignature) {
  std::memcpy(bytes_.data(), "LASX", 4);
  const Status s = Read("sig.las");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Says(s, "not a LAS file (signature 'LASX'")) << s.ToString();
}

TEST_F(BrokenLas, TruncatedPoints) {
  bytes_.resize(bytes_.size() - 1000);
  const Status s = Read("truncated.las");
  EXPECT_EQ(s.code(), StatusCode::kCorruption);
  EXPECT_TRUE(Says(s, "header promises 6280 points of 28 bytes")) << s.ToString();
  EXPECT_TRUE(Says(s, "truncated")) << s.ToString();
}

TEST_F(BrokenLas, TruncatedHeader) {
  bytes_.resize(100);
  const Status s = Read("short.las");
  EXPECT_EQ(s.code(), StatusCode::kCorruption);
  EXPECT_TRUE(Says(s, "truncated")) << s.ToString();
}

TEST_F(BrokenLas, HeaderSmallerThanItsVersion) {
  Put<uint16_t>(bytes_, 94, 200);
  const Status s = Read("header.las");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Says(s, "header size 200 is smaller than the 227 bytes LAS 1.2 requires"))
      << s.ToString();
}

TEST_F(BrokenLas, Las14HeaderSizeOfLas12) {
  Put<uint8_t>(bytes_, 25, 4);  // claims 1.4 but keeps the 227-byte header
  const Status s = Read("v14.las");
  EXPECT_TRUE(Says(s, "header size 227 is smaller than the 375 bytes LAS 1.4 requires"))
      << s.ToString();
}

TEST_F(BrokenLas, UnknownVersion) {
  Put<uint8_t>(bytes_, 25, 7);
  EXPECT_TRUE(Says(Read("v17.las"), "unsupported version LAS 1.7"));
}

TEST_F(BrokenLas, RecordLengthTooSmall) {
  Put<uint16_t>(bytes_, 105, 20);
  const Status s = Read("record.las");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Says(s, "point record length 20 is smaller than the 28 bytes point format 1 needs"))
      << s.ToString();
}

TEST_F(BrokenLas, UnknownPointFormat) {
  Put<uint8_t>(bytes_, 104, 11);
  EXPECT_TRUE(Says(Read("format.las"), "unknown point data format 11"));
}

const char kLazAdvice[] =
    "is LAZ (compressed); tinbase reads uncompressed LAS: decompress it "
    "with laszip or pdal translate first";

TEST_F(BrokenLas, CompressedFormatBit) {
  Put<uint8_t>(bytes_, 104, 1 | 0x80);
  const Status s = Read("flag.las");
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(Says(s, kLazAdvice)) << s.ToString();
}

TEST_F(BrokenLas, LazExtension) {
  const Status s = Read("points.laz");
  EXPECT_TRUE(Says(s, std::string("points.laz ") + kLazAdvice)) << s.ToString();
}

TEST_F(BrokenLas, LaszipVlr) {
  // Rename the first VLR (just after the 227-byte header) into laszip's.
  char user_id[16] = "laszip encoded";
  std::memcpy(bytes_.data() + 227 + 2, user_id, 16);
  Put<uint16_t>(bytes_, 227 + 18, 22204);
  EXPECT_TRUE(Says(Read("vlr.las"), kLazAdvice));
}

TEST_F(BrokenLas, VlrRunningIntoPoints) {
  Put<uint16_t>(bytes_, 227 + 20, 60000);
  const Status s = Read("vlr_long.las");
  EXPECT_EQ(s.code(), StatusCode::kCorruption);
  EXPECT_TRUE(Says(s, "variable length record 0 runs past the start of the point data"))
      << s.ToString();
}

TEST_F(BrokenLas, InfiniteAfterScaling) {
  Put<double>(bytes_, 131, 1e308);  // x scale: any |X| >= 2 overflows to infinity
  const Status s = Read("inf.las");
  EXPECT_EQ(s.code(), StatusCode::kCorruption);
  EXPECT_TRUE(Says(s, ": coordinate is not finite after scaling")) << s.ToString();
  EXPECT_TRUE(Says(s, ": point ")) << s.ToString();
}

TEST_F(BrokenLas, ZeroScale) {
  Put<double>(bytes_, 147, 0.0);
  EXPECT_TRUE(Says(Read("zero.las"), "z scale factor 0"));
}

// Random damage to the header and VLRs (and random truncation) never crashes the reader: it
// either reads the file or refuses it, and what it reads matches the header's count. A cheap
// stand-in for a fuzz target; the seed is printed so a failure reproduces.
TEST(LasReader, RandomDamageIsReadOrRefused) {
  const std::vector<char> original = ReadBytes(DataPath("las/mvk-thin.las"));
  const uint32_t seed = std::random_device{}();
  std::cout << "seed " << seed << "\n";
  std::mt19937 rng(seed);
  TempDir dir;
  const size_t point_offset = 3314;  // mvk-thin.las: header and VLRs end here
  int refused = 0;
  for (int round = 0; round < 300; ++round) {
    std::vector<char> bytes = original;
    const int flips = 1 + static_cast<int>(rng() % 8);
    for (int f = 0; f < flips; ++f) bytes[rng() % (point_offset + 64)] = static_cast<char>(rng());
    if (rng() % 4 == 0) bytes.resize(rng() % bytes.size());
    const std::string path = dir.Path("damaged.las");
    WriteBytes(path, bytes);
    auto las = ReadLas(path);
    if (!las.ok()) {
      ++refused;
      EXPECT_NE(las.status().message().find(path), std::string::npos)
          << "seed " << seed << ": " << las.status().ToString();
      continue;
    }
    EXPECT_EQ(las->cloud.points.size(), las->header.point_count) << "seed " << seed;
  }
  EXPECT_GT(refused, 0) << "seed " << seed;
}

TEST(LasReader, MissingFileIsAnIoError) {
  auto las = ReadLas("/nonexistent/dir/points.las");
  EXPECT_EQ(las.status().code(), StatusCode::kIOError);
  EXPECT_NE(las.status().message().find("/nonexistent/dir/points.las"), std::string::npos);
}

}  // namespace
}  // namespace tinbase
