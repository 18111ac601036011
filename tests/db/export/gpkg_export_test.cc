// ExportGpkg, judged by GDAL's own readers: ogrinfo finds every layer with the store's counts,
// triangle ids, neighbours, visibility and tags; gdalinfo/gdallocationinfo find the DEM as a
// Float32 gridded coverage with the stored cells; a failed export leaves no file behind.
#include "db/export/gpkg_export.h"

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "core/vector/gdal_session.h"
#include "db/dem_store.h"
#include "db/feature_store.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/store_target.h"
#include "tests/support/test_support.h"
#include "tests/support/tin_fixtures.h"

namespace tinbase {
namespace {

using testing::HaveTool;
using testing::RunTool;
using testing::TempDir;
using testing::ValueAfter;

constexpr int kDemSize = 48;
constexpr double kDemOrigin[2] = {599000, 5111000};
constexpr double kDemCell = 250;
constexpr float kNodata = -9999;

// Cell (col, row) of the test DEM: every value exact in float32 and different from the others.
float DemCell(int col, int row) { return 100.0f + static_cast<float>(col) + 1000.0f * row; }

// A float32 GeoTIFF over the fixture TIN's square, with cell (0, 0) nodata.
void WriteDem(const std::string& path) {
  RegisterGdalDriversOnce();
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  ASSERT_NE(gtiff, nullptr);
  GdalDatasetPtr ds(gtiff->Create(path.c_str(), kDemSize, kDemSize, 1, GDT_Float32, nullptr));
  ASSERT_TRUE(ds);
  std::vector<float> cells;
  for (int row = 0; row < kDemSize; ++row)
    for (int col = 0; col < kDemSize; ++col) cells.push_back(DemCell(col, row));
  cells[0] = kNodata;
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, kDemSize, kDemSize, cells.data(),
                                           kDemSize, kDemSize, GDT_Float32, 0, 0, nullptr),
            CE_None);
  ds->GetRasterBand(1)->SetNoDataValue(kNodata);
  double transform[6] = {kDemOrigin[0], kDemCell, 0, kDemOrigin[1], 0, -kDemCell};
  ds->SetGeoTransform(transform);
  OGRSpatialReference srs;
  srs.importFromEPSG(32632);
  ds->SetSpatialRef(&srs);
}

std::string Q(const std::string& s) { return "'" + s + "'"; }

class GpkgExportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = Store::Create(testing::StoreTarget(dir_, "s.tinbase"), "EPSG:32632");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(*store);
    WriteDem(dir_.Path("dem.tif"));
    DemImportOptions dem_options;
    dem_options.name = "ground";
    auto dem = DemStore(*store_).Import({dir_.Path("dem.tif")}, dem_options);
    ASSERT_TRUE(dem.ok()) << dem.status().ToString();

    testing::RandomTinOptions options;
    options.points = 400;
    options.ring = true;
    Tin tin = testing::RandomDelaunayTin(options);
    for (size_t t = 0; t < tin.triangles.size(); t += 7) tin.triangles[t].visible = false;
    auto tx = store_->BeginWrite();
    ASSERT_TRUE(tx.ok());
    SurfaceInfo spec;
    spec.name = "terrain";
    spec.method = "test";
    spec.dem = dem->dem.id;
    auto info = SurfaceStore(*store_).Create(spec, tin);
    ASSERT_TRUE(info.ok()) << info.status().ToString();
    surface_ = *info;
    EditorFeature unit;
    unit.mode = FeatureMode::kFill;
    unit.tag = "basalt";
    unit.attributes = {{"unit", "B1"}, {"age_ma", 12.5}};
    unit.polygons = {Polygon{{{604500, 5104500}, {605500, 5104500}, {605500, 5105500}}, {}}};
    ASSERT_TRUE(WriteFeature(*store_, surface_, 1, unit).ok());
    EditorFeature fault;
    fault.mode = FeatureMode::kBreakline;
    fault.level = 250;
    fault.lines = {{{601000, 5101000}, {604000, 5104000}}};
    ASSERT_TRUE(WriteFeature(*store_, surface_, 1, fault).ok());
    unit_ = unit.id;
    fault_ = fault.id;
    ASSERT_TRUE((*tx)->Commit().ok());
    auto all = SurfaceStore(*store_).Load(surface_);
    ASSERT_TRUE(all.ok());
    all_ = std::move(*all);
    ASSERT_TRUE(HaveTool("ogrinfo") && HaveTool("gdalinfo") && HaveTool("gdallocationinfo"));
  }

  Result<GpkgExportReport> Export(const GpkgExportOptions& options, const std::string& path) {
    return ExportGpkg(*store_, surface_, options, path);
  }

  // ogrinfo's summary of one layer.
  static std::string Summary(const std::string& path, const std::string& layer) {
    auto r = RunTool("ogrinfo -ro -so " + Q(path) + " " + layer);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return r.out;
  }
  static int64_t Count(const std::string& path, const std::string& layer) {
    const std::string value = ValueAfter(Summary(path, layer), "Feature Count: ");
    return value.empty() ? -1 : std::stoll(value);
  }
  // ogrinfo's dump of feature `fid` of `layer`.
  static std::string Feature(const std::string& path, const std::string& layer, int64_t fid) {
    auto r = RunTool("ogrinfo -ro " + Q(path) + " " + layer + " -fid " + std::to_string(fid));
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return r.out;
  }

  // The store's row of triangle `id` as ogrinfo prints its fields.
  std::string ExpectedFields(int64_t id) {
    auto row = SurfaceStore(*store_).Triangle(surface_, id);
    EXPECT_TRUE(row.ok());
    std::string out;
    for (int k = 0; k < 3; ++k)
      out += "n" + std::to_string(k) +
             " (Integer64) = " + (row->n[k] ? std::to_string(*row->n[k]) : "(null)") + "\n";
    out += "visible (Integer(Boolean)) = " + std::string(row->visible ? "1" : "0") + "\n";
    out += "tag (String) = " +
           (row->tag ? *SurfaceStore(*store_).TagValue(surface_, *row->tag) : "(null)") + "\n";
    return out;
  }

  // ogrinfo's field lines of a feature dump, without indentation.
  static std::string FieldLines(const std::string& dump) {
    std::string out;
    size_t at = 0;
    while (at < dump.size()) {
      size_t end = dump.find('\n', at);
      if (end == std::string::npos) end = dump.size();
      std::string line = dump.substr(at, end - at);
      at = end + 1;
      if (line.rfind("  ", 0) != 0 || line.find(" = ") == std::string::npos) continue;
      out += line.substr(2) + "\n";
    }
    return out;
  }

  TempDir dir_;
  std::unique_ptr<Store> store_;
  SurfaceInfo surface_;
  LoadedSurface all_;
  int64_t unit_ = 0;
  int64_t fault_ = 0;
};

TEST_F(GpkgExportTest, OgrinfoReadsEveryLayerWithTheStoreCounts) {
  const std::string path = dir_.Path("all.gpkg");
  auto report = Export({}, path);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto counts = SurfaceStore(*store_).Count(surface_);
  ASSERT_TRUE(counts.ok());
  ASSERT_GT(counts->constraints, 0);

  auto listing = RunTool("ogrinfo -ro " + Q(path));
  EXPECT_NE(listing.out.find("using driver `GPKG'"), std::string::npos) << listing.out;
  EXPECT_NE(listing.out.find("triangles (3D Polygon)"), std::string::npos) << listing.out;
  EXPECT_NE(listing.out.find("features (Multi Polygon)"), std::string::npos) << listing.out;
  EXPECT_NE(listing.out.find("breaklines (Multi Line String)"), std::string::npos);
  EXPECT_NE(listing.out.find("constraints (3D Line String)"), std::string::npos);

  EXPECT_EQ(Count(path, "triangles"), counts->triangles);
  EXPECT_EQ(report->triangles, counts->triangles);
  EXPECT_EQ(Count(path, "constraints"), counts->constraints);
  EXPECT_EQ(Count(path, "features"), 1);
  EXPECT_EQ(Count(path, "breaklines"), 1);
  const std::string summary = Summary(path, "triangles");
  EXPECT_EQ(ValueAfter(summary, "FID Column = "), "id");
  EXPECT_NE(summary.find("ID[\"EPSG\",32632]"), std::string::npos) << summary;
}

TEST_F(GpkgExportTest, TriangleIdsNeighboursVisibilityAndTagsAreTheStores) {
  const std::string path = dir_.Path("rows.gpkg");
  ASSERT_TRUE(Export({}, path).ok());
  // The first, a middle and the last triangle, a hidden one and one with a boundary edge.
  std::vector<int64_t> ids = {all_.triangle_ids.front(),
                              all_.triangle_ids[all_.triangle_ids.size() / 2],
                              all_.triangle_ids.back(), all_.triangle_ids[7]};
  for (size_t t = 0; t < all_.tin.triangles.size(); ++t) {
    const auto& n = all_.tin.triangles[t].n;
    if (n[0] == kNoNeighbour || n[1] == kNoNeighbour || n[2] == kNoNeighbour) {
      ids.push_back(all_.triangle_ids[t]);
      break;
    }
  }
  for (size_t t = 0; t < all_.tin.triangles.size(); ++t) {
    if (all_.tin.triangles[t].tag != kNoTag) {
      ids.push_back(all_.triangle_ids[t]);
      break;
    }
  }
  ASSERT_EQ(ids.size(), 6u);
  for (int64_t id : ids) {
    const std::string dump = Feature(path, "triangles", id);
    EXPECT_NE(dump.find("OGRFeature(triangles):" + std::to_string(id) + "\n"), std::string::npos)
        << dump;
    EXPECT_EQ(FieldLines(dump), ExpectedFields(id)) << "triangle " << id;
    // The ring's first corner is the store's v0 (ogrinfo prints 15 significant digits).
    auto row = SurfaceStore(*store_).Triangle(surface_, id);
    auto v0 = SurfaceStore(*store_).Vertex(surface_, row->v[0]);
    char corner[128];
    std::snprintf(corner, sizeof(corner), "POLYGON Z ((%.15g %.15g %.15g,", v0->x, v0->y, v0->z);
    EXPECT_NE(dump.find(corner), std::string::npos) << corner << "\n" << dump;
  }
}

TEST_F(GpkgExportTest, FeaturesKeepModeTagLevelAndAttributes) {
  const std::string path = dir_.Path("features.gpkg");
  ASSERT_TRUE(Export({}, path).ok());
  const std::string unit = FieldLines(Feature(path, "features", unit_));
  EXPECT_EQ(unit,
            "mode (String) = fill\ntag (String) = basalt\nlevel (Real) = (null)\n"
            "attributes (String(JSON)) = {\"age_ma\":12.5,\"unit\":\"B1\"}\n");
  const std::string fault = Feature(path, "breaklines", fault_);
  EXPECT_NE(fault.find("level (Real) = 250"), std::string::npos) << fault;
  EXPECT_NE(fault.find("MULTILINESTRING ((601000 5101000,604000 5104000))"), std::string::npos)
      << fault;
}

TEST_F(GpkgExportTest, DemIsAFloat32GriddedCoverageWithTheStoredCells) {
  const std::string path = dir_.Path("dem.gpkg");
  auto report = Export({}, path);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  ASSERT_TRUE(report->raster.has_value());
  EXPECT_EQ(report->dem, "ground");
  const GridGeometry& g = *report->raster;
  auto info = RunTool("gdalinfo -stats " + Q(path));
  std::filesystem::remove(path + ".aux.xml");
  ASSERT_EQ(info.exit_code, 0) << info.out;
  EXPECT_NE(info.out.find("Driver: GPKG/GeoPackage"), std::string::npos) << info.out;
  EXPECT_EQ(ValueAfter(info.out, "Size is "),
            std::to_string(g.width) + ", " + std::to_string(g.height));
  EXPECT_NE(info.out.find("Type=Float32"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("NoData Value=-9999"), std::string::npos) << info.out;
  // The window is whole cells of the DEM and covers every vertex.
  const double col0 = (g.origin_x - kDemOrigin[0]) / kDemCell;
  const double row0 = (kDemOrigin[1] - g.origin_y) / kDemCell;
  ASSERT_EQ(col0, std::floor(col0));
  ASSERT_EQ(row0, std::floor(row0));
  ASSERT_GE(col0, 1) << "the test DEM's nodata cell lies outside the window";
  for (const TinVertex& v : all_.tin.vertices) ASSERT_TRUE(g.Contains(v.x, v.y));
  const int c0 = static_cast<int>(col0), r0 = static_cast<int>(row0);
  const auto w = static_cast<int>(g.width), h = static_cast<int>(g.height);
  EXPECT_EQ(std::stod(ValueAfter(info.out, "STATISTICS_MINIMUM=")), DemCell(c0, r0));
  EXPECT_EQ(std::stod(ValueAfter(info.out, "STATISTICS_MAXIMUM=")),
            DemCell(c0 + w - 1, r0 + h - 1));
  auto coverage =
      RunTool("ogrinfo -ro " + Q(path) +
              " -sql \"SELECT datatype, data_null FROM "
              "gpkg_2d_gridded_coverage_ancillary WHERE tile_matrix_set_name = 'dem'\"");
  EXPECT_NE(coverage.out.find("datatype (String) = float"), std::string::npos) << coverage.out;
  EXPECT_NE(coverage.out.find("data_null (Real) = -9999"), std::string::npos) << coverage.out;
  for (const auto& [col, row] : {std::pair{0, 0}, std::pair{17, 5}, std::pair{w - 1, h - 1}}) {
    auto value = RunTool("gdallocationinfo -valonly " + Q(path) + " " + std::to_string(col) + " " +
                         std::to_string(row));
    ASSERT_EQ(value.exit_code, 0) << value.out;
    EXPECT_EQ(std::stof(value.out), DemCell(col + c0, row + r0)) << col << ", " << row;
  }
}

TEST_F(GpkgExportTest, FiltersSelectWhatSelectSurfaceSelects) {
  GpkgExportOptions visible;
  visible.filter.visible_only = true;
  visible.with_dem = false;
  const std::string a = dir_.Path("visible.gpkg");
  auto report = Export(visible, a);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto counts = SurfaceStore(*store_).Count(surface_);
  EXPECT_EQ(Count(a, "triangles"), counts->visible_triangles);
  EXPECT_EQ(RunTool("gdalinfo " + Q(a)).out.find("Size is"), std::string::npos)
      << "no raster asked for";

  GpkgExportOptions window;
  window.filter.bbox = Box{604000, 5104000, 606000, 5106000};
  window.filter.tag = "granite";
  const std::string b = dir_.Path("window.gpkg");
  report = Export(window, b);
  ASSERT_TRUE(report.ok()) << report.status().ToString();
  auto expected = SelectSurface(*store_, surface_, window.filter);
  ASSERT_TRUE(expected.ok());
  EXPECT_EQ(Count(b, "triangles"), static_cast<int64_t>(expected->triangle_ids.size()));
  EXPECT_EQ(Count(b, "features"), 1) << "the unit meets the window";
  auto tags = RunTool("ogrinfo -ro " + Q(b) +
                      " -sql \"SELECT count(*) AS n FROM triangles WHERE tag <> 'granite'\"");
  EXPECT_NE(tags.out.find("n (Integer) = 0"), std::string::npos) << tags.out;
}

TEST_F(GpkgExportTest, FailuresLeaveNoFileBehind) {
  GpkgExportOptions nothing;
  nothing.filter.bbox = Box{0, 0, 10, 10};
  const std::string path = dir_.Path("empty.gpkg");
  auto report = Export(nothing, path);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kNotFound);
  EXPECT_NE(report.status().message().find("terrain"), std::string::npos)
      << report.status().message();

  GpkgExportOptions unknown_dem;
  unknown_dem.dem = "nope";
  report = Export(unknown_dem, path);
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("nope"), std::string::npos) << report.status().message();

  report = Export({}, dir_.Path("missing/out.gpkg"));
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().code(), StatusCode::kIOError);

  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir()))
    EXPECT_EQ(entry.path().extension().string().find(".gpkg"), std::string::npos)
        << "left behind: " << entry.path();
  for (const auto& entry : std::filesystem::directory_iterator(dir_.dir()))
    EXPECT_EQ(entry.path().filename().string().find("partial"), std::string::npos)
        << "left behind: " << entry.path();
}

}  // namespace
}  // namespace tinbase
