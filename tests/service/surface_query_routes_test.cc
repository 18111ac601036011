// The surface's query and export routes through a real socket: profile and measures answer the
// JSON the CLI prints for the same request; exports are the bytes `tinbase export` writes for
// the same selection (the GLB also passes the Khronos validator, the GeoJSON is read by ogrinfo,
// the LandXML by xmllint), and an answer over the result limit is a 413 naming it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "tests/core/export/gltf_check.h"
#include "tests/support/gdal_tools.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

// A window on land around the "granite" feature.
constexpr const char* kWindow = "355000,4855000,365000,4868000";

class SurfaceQueryRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    CopyDemoStoreWithFeature(store_);
    Start(service::ServiceOptions());
  }
  void Start(service::ServiceOptions options) {
    service_.reset();
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }
  nlohmann::json Get(const std::string& path, int status = 200) {
    return JsonAnswer(service_->Client()->Get(path), status);
  }
  std::string Surface() const { return Quote(store_) + " --surface t --json"; }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

TEST_F(SurfaceQueryRoutesTest, TheProfileIsTheClis) {
  const nlohmann::json cli = Json(
      RunCli("profile " + Surface() + " --line '356000,4858000 363000,4866000 364000,4857000'"));
  const nlohmann::json a =
      Get("/surfaces/t/profile?line=356000,4858000,363000,4866000,364000,4857000");
  EXPECT_EQ(a, cli);
  EXPECT_GT(a["stations"].size(), 20u);
  bool granite = false;
  for (const auto& s : a["stretches"]) granite |= s["tag"] == "granite";
  EXPECT_TRUE(granite);
}

TEST_F(SurfaceQueryRoutesTest, AProfileInLonLatFollowsTheSameLine) {
  const nlohmann::json xy = Get("/surfaces/t/profile?line=356000,4858000,363000,4866000");
  const nlohmann::json start = Get("/surfaces/t/locate?x=356000&y=4858000")["triangle"];
  // The line's ends in lon/lat, read back from a located triangle's corner to stay exact enough:
  // a corner of the first triangle to a corner of the last.
  const nlohmann::json end = Get("/surfaces/t/locate?x=363000&y=4866000")["triangle"];
  std::ostringstream line;
  line.precision(17);
  line << start["lonlat"][0][0].get<double>() << "," << start["lonlat"][0][1].get<double>() << ","
       << end["lonlat"][0][0].get<double>() << "," << end["lonlat"][0][1].get<double>();
  const nlohmann::json a = Get("/surfaces/t/profile?crs=EPSG:4326&line=" + line.str());
  EXPECT_NEAR(a["stations"][0]["x"].get<double>(), start["vertices"][0][0].get<double>(), 1e-3);
  EXPECT_NEAR(a["stations"][0]["y"].get<double>(), start["vertices"][0][1].get<double>(), 1e-3);
  EXPECT_NEAR(a["length"].get<double>(), xy["length"].get<double>(), 2000);
}

TEST_F(SurfaceQueryRoutesTest, ABadProfileLineIsA400NamingIt) {
  ExpectJsonError(service_->Client()->Get("/surfaces/t/profile"), 400, "missing parameter 'line'");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/profile?line=1,2,3"), 400,
                  "at least two points (got 3 numbers)");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/profile?line=1,2,x,4"), 400,
                  "parameter 'line', number 3: 'x' is not a finite number");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/profile?line=1,2,nan,4"), 400,
                  "number 3: 'nan'");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/profile?line=0,0,1,1"), 404,
                  "outside surface 't'");
}

TEST_F(SurfaceQueryRoutesTest, TheMeasuresAreTheClis) {
  const std::string sel = std::string(" --bbox ") + kWindow;
  EXPECT_EQ(Get(std::string("/surfaces/t/measures/area?bbox=") + kWindow),
            Json(RunCli("measure area " + Surface() + sel)));
  EXPECT_EQ(Get(std::string("/surfaces/t/measures/area?tag=granite&bbox=") + kWindow),
            Json(RunCli("measure area " + Surface() + sel + " --tag granite")));
  EXPECT_EQ(Get(std::string("/surfaces/t/measures/volume?level=600&bbox=") + kWindow),
            Json(RunCli("measure volume " + Surface() + sel + " --level 600")));
  EXPECT_EQ(Get("/surfaces/t/measures/volume?level=600&feature=1"),
            Json(RunCli("measure volume " + Surface() + " --feature 1 --level 600")));
  // slope: the CLI's JSON lines, gathered.
  const nlohmann::json slope = Get(std::string("/surfaces/t/measures/slope?bbox=") + kWindow);
  const CliResult cli = RunCli("measure slope " + Surface() + sel);
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  std::istringstream lines(cli.out);
  std::string line;
  size_t n = 0;
  while (std::getline(lines, line)) {
    ASSERT_LT(n, slope["triangles"].size());
    EXPECT_EQ(slope["triangles"][n++], nlohmann::json::parse(line));
  }
  EXPECT_EQ(n, slope["triangles"].size());
  EXPECT_GT(n, 100u);
  EXPECT_EQ(slope["surface"], "t");
}

TEST_F(SurfaceQueryRoutesTest, BadMeasureParametersAre400s) {
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/volume"), 400,
                  "missing parameter 'level'");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/volume?level=nan"), 400,
                  "parameter 'level': 'nan' is not a finite number");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/area?feature=0"), 400,
                  "parameter 'feature': '0' is out of range");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/area?feature=77"), 404, "77");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/area?bbox=0,0,1,1"), 404,
                  "bbox 0,0,1,1");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/measures/curvature"), 404, "no route");
}

// `tinbase export` of the same selection to a file, read back.
std::string CliExport(const TempDir& dir, const std::string& store, const std::string& format,
                      const std::string& selection) {
  const std::string out = dir.Path("cli." + format);
  const CliResult r = RunCli("export " + Quote(store) + " --surface t --format " + format +
                             selection + " -o " + Quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return ReadBytes(out);
}

TEST_F(SurfaceQueryRoutesTest, ExportsAreTheFilesTheCliWrites) {
  const struct {
    const char* format;
    const char* type;
  } formats[] = {{"glb", "model/gltf-binary"},
                 {"obj", "model/obj"},
                 {"ply", "application/octet-stream"},
                 {"stl", "model/stl"},
                 {"geojson", "application/geo+json"}};
  for (const auto& f : formats) {
    SCOPED_TRACE(f.format);
    auto r = service_->Client()->Get(std::string("/surfaces/t/export?format=") + f.format +
                                     "&visible_only=true&bbox=" + kWindow);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
    EXPECT_EQ(r->get_header_value("Content-Type"), f.type);
    EXPECT_EQ(r->get_header_value("Content-Disposition"),
              std::string("attachment; filename=\"t.") + f.format + "\"");
    EXPECT_EQ(r->body,
              CliExport(dir_, store_, f.format, std::string(" --visible-only --bbox ") + kWindow));
    const std::string file = dir_.Path(std::string("served.") + f.format);
    std::ofstream(file, std::ios::binary) << r->body;
    if (std::string(f.format) == "glb") ExpectValidGltf(file);
    if (std::string(f.format) == "geojson") {
      ASSERT_TRUE(HaveTool("ogrinfo")) << "ogrinfo is missing (apt-get install gdal-bin)";
      const ToolResult info = RunTool("ogrinfo -al -so " + Quote(file));
      EXPECT_EQ(info.exit_code, 0) << info.out;
      EXPECT_NE(info.out.find("Geometry: 3D Polygon"), std::string::npos) << info.out;
    }
  }
}

TEST_F(SurfaceQueryRoutesTest, TheLandXmlExportIsTheClisUpToItsTimestamp) {
  auto r = service_->Client()->Get("/surfaces/t/export?format=landxml&tag=granite");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body.substr(0, 300);
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/xml");
  const std::regex stamp(R"( date="[^"]*" time="[^"]*")");
  EXPECT_EQ(std::regex_replace(r->body, stamp, ""),
            std::regex_replace(CliExport(dir_, store_, "landxml", " --tag granite"), stamp, ""));
  ASSERT_TRUE(HaveTool("xmllint", "libxml2-utils")) << "xmllint is missing";
  const std::string file = dir_.Path("served.xml");
  std::ofstream(file) << r->body;
  const ToolResult lint = RunTool("xmllint --noout " + Quote(file));
  EXPECT_EQ(lint.exit_code, 0) << lint.out;
}

TEST_F(SurfaceQueryRoutesTest, BadExportsAreRefusedAndLargeOnesAre413NamingTheLimit) {
  ExpectJsonError(service_->Client()->Get("/surfaces/t/export"), 400, "missing parameter 'format'");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/export?format=../../etc/passwd"), 400,
                  "is not one of glb, obj, geojson, landxml, ply, stl");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/export?format=obj&bbox=0,0,1,1"), 404,
                  "bbox 0,0,1,1");
  ExpectJsonError(service_->Client()->Get("/surfaces/t/export?format=obj&visible_only=yes"), 400,
                  "parameter 'visible_only': 'yes' is not true, false, 1 or 0");
  service::ServiceOptions small;
  small.max_result_bytes = 1000;
  Start(small);
  const nlohmann::json e = Get(std::string("/surfaces/t/export?format=obj&bbox=") + kWindow, 413);
  EXPECT_EQ(e["error"]["code"], "result_too_large");
  EXPECT_NE(e["error"]["message"].get<std::string>().find("result limit of 1000 bytes"),
            std::string::npos);
  // JSON answers too.
  ExpectJsonError(service_->Client()->Get(std::string("/surfaces/t/triangles?bbox=") + kWindow),
                  413, "result limit of 1000 bytes");
  ExpectJsonError(
      service_->Client()->Get(std::string("/surfaces/t/measures/slope?bbox=") + kWindow), 413,
      "result limit of 1000 bytes");
  // A small answer still goes through.
  Get("/surfaces/t/locate?x=360000&y=4862000");
}

}  // namespace
}  // namespace tinbase::testing
