// WriteProfilePlot: the PNG GDAL reads back has the asked size, the profile line where the frame
// puts it, each tag in its colour, and bad sizes are refused.
#include "core/query/profile_plot.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "core/vector/gdal_session.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::TempDir;

std::array<uint8_t, 3> PixelAt(GDALDataset& ds, int x, int y) {
  std::array<uint8_t, 3> rgb{};
  for (int b = 0; b < 3; ++b)
    EXPECT_EQ(ds.GetRasterBand(b + 1)->RasterIO(GF_Read, x, y, 1, 1, &rgb[b], 1, 1, GDT_Byte, 0, 0,
                                                nullptr),
              CE_None);
  return rgb;
}

// Whether a pixel of colour `c` lies within `radius` rows of `row` in `column`.
bool ColourNear(GDALDataset& ds, int column, double row, int radius,
                const std::array<uint8_t, 3>& c) {
  for (int y = static_cast<int>(row) - radius; y <= static_cast<int>(row) + radius; ++y)
    if (PixelAt(ds, column, y) == c) return true;
  return false;
}

TEST(ProfilePlot, TheLineIsWhereTheFrameSaysInItsTagsColours) {
  TempDir dir;
  // A ramp from z 100 to 300 over 1000 m: tag 0 on the first half, tag 1 on the second.
  const std::vector<Station> stations = {{0, 0, 0, 100, StationKind::kStart},
                                         {500, 500, 0, 200, StationKind::kEdge},
                                         {1000, 1000, 0, 300, StationKind::kEnd}};
  const std::vector<ProfilePlotStretch> stretches = {{0, true}, {1, true}};
  const std::string path = dir.Path("p.png");
  ProfilePlotOptions options;
  options.width = 600;
  options.height = 300;
  ASSERT_TRUE(WriteProfilePlot(stations, stretches, path, options).ok());

  RegisterGdalDriversOnce();
  GdalDatasetPtr ds(static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly)));
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetDriver()->GetDescription(), "PNG");
  EXPECT_EQ(ds->GetRasterXSize(), 600);
  EXPECT_EQ(ds->GetRasterYSize(), 300);
  ASSERT_EQ(ds->GetRasterCount(), 3);
  const ProfilePlotFrame f = PlotFrameFor(stations, options);
  EXPECT_LE(f.min_z, 100);
  EXPECT_GE(f.max_z, 300);
  for (double d : {100.0, 250.0, 400.0}) {
    const int column = static_cast<int>(std::lround(f.Column(d)));
    EXPECT_TRUE(ColourNear(*ds, column, f.Row(100 + d / 5), 2, SeriesColour(0))) << d;
  }
  for (double d : {600.0, 750.0, 900.0}) {
    const int column = static_cast<int>(std::lround(f.Column(d)));
    EXPECT_TRUE(ColourNear(*ds, column, f.Row(100 + d / 5), 2, SeriesColour(1))) << d;
  }
  // Above the line the plot is not painted in either colour.
  const int column = static_cast<int>(std::lround(f.Column(500)));
  EXPECT_FALSE(ColourNear(*ds, column, f.Row(260), 5, SeriesColour(0)));
  EXPECT_FALSE(ColourNear(*ds, column, f.Row(260), 5, SeriesColour(1)));
}

TEST(ProfilePlot, TooSmallOrMismatchedIsRefusedAndWritesNothing) {
  TempDir dir;
  const std::vector<Station> stations = {{0, 0, 0, 1, StationKind::kStart},
                                         {1, 1, 0, 1, StationKind::kEnd}};
  const std::string path = dir.Path("p.png");
  ProfilePlotOptions tiny;
  tiny.width = 50;
  Status s = WriteProfilePlot(stations, {{-1, true}}, path, tiny);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("200 x 100 to 16384 x 16384 pixels, not 50 x 400"), std::string::npos)
      << s.message();
  ProfilePlotOptions huge;
  huge.height = 100000;
  EXPECT_EQ(WriteProfilePlot(stations, {{-1, true}}, path, huge).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(WriteProfilePlot(stations, {}, path).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(std::filesystem::exists(path));
  // A flat profile still gets a z range to draw in.
  EXPECT_TRUE(WriteProfilePlot(stations, {{-1, false}}, path).ok());
}

}  // namespace
}  // namespace tinbase
