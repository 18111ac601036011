// `tinbase export` and `tinbase dem clip --faces` end to end on the Hamersley data: every format
// written from the same selection, each checked by a reader we did not write where one exists
// (the Khronos glTF validator for .glb, OGR for GeoJSON); the selection options narrow the output;
// bad input is one clear line, exit 1, and no file left behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "tests/core/export/gltf_check.h"
#include "tests/support/cli_support.h"
#include "tests/support/store_target.h"
#include "tests/support/store_template.h"
#include "tests/support/test_support.h"

namespace tinbase {
namespace {

using testing::CliResult;
using testing::DataPath;
using testing::ExpectRejected;
using testing::Json;
using testing::Quote;
using testing::RunCli;
using testing::RunWrite;
using testing::StoreTarget;
using testing::TempDir;

class ExportCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    out_ = dir_.Path("out");
    std::filesystem::create_directory(out_);
    testing::CopyRecipeStore(Recipe(), store_);
    bbox_ = DemBox(store_);
    cx_ = (bbox_[0] + bbox_[2]) / 2, cy_ = (bbox_[1] + bbox_[3]) / 2;
  }

  // The DEM's box in `store` (min x, min y, max x, max y).
  static std::array<double, 4> DemBox(const std::string& store) {
    auto info = Json(RunCli("info --json " + Quote(store)));
    const auto& b = info["dems"][0]["bbox"];
    std::array<double, 4> box{};
    for (int k = 0; k < 4; ++k) box[k] = b[k].get<double>();
    return box;
  }

  // The Hamersley surface "terrain" at 10 m with the geology filled in, tagged by unit name,
  // and an erase square in the middle, so some triangles are invisible.
  static const testing::StoreRecipe& Recipe() {
    static const testing::StoreRecipe recipe{
        "export_cli_test", [](const std::string& store, const TempDir& scratch) {
          testing::CopyRecipeStore(testing::HamersleyTerrainRecipe(10), store);
          RunWrite(store, "polygon add " + Quote(store) + " " +
                              Quote(DataPath("geology/hamersley/geology.geojson")) +
                              " --surface terrain --mode fill --tag-field unitname");
          const std::array<double, 4> box = DemBox(store);
          const double cx = (box[0] + box[2]) / 2, cy = (box[1] + box[3]) / 2;
          const std::string square = scratch.Path("square.geojson");
          std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name",)"
                                << R"("properties":{"name":"EPSG:28350"}},"features":[)"
                                << R"({"type":"Feature","properties":{},"geometry":)"
                                << R"({"type":"Polygon","coordinates":[[)"
                                << "[" << cx - 2000 << "," << cy - 2000 << "],[" << cx + 2000 << ","
                                << cy - 2000 << "],[" << cx + 2000 << "," << cy + 2000 << "],["
                                << cx - 2000 << "," << cy + 2000 << "],[" << cx - 2000 << ","
                                << cy - 2000 << "]]]}}]}";
          RunWrite(store, "polygon add " + Quote(store) + " " + Quote(square) +
                              " --surface terrain --mode erase");
        }};
    return recipe;
  }

  // Runs `export` with `args` (after the store); returns its --json report.
  nlohmann::json Export(const std::string& args) {
    const CliResult r = RunCli("export " + Quote(store_) + " --json " + args);
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
    return r.exit_code == 0 ? Json(r) : nlohmann::json();
  }

  // The files in out_ (to show nothing, not even a temporary, was left behind).
  size_t FilesInOut() const {
    return static_cast<size_t>(std::distance(std::filesystem::directory_iterator(out_),
                                             std::filesystem::directory_iterator()));
  }

  // The triangles of a GeoJSON export: tag (or "") per feature, and the features' boxes.
  struct Triangles {
    std::vector<std::string> tags;
    std::vector<bool> visible;
    std::vector<std::array<double, 4>> boxes;
  };
  Triangles ReadGeoJson(const std::string& path) {
    Triangles t;
    std::ifstream in(path);
    const auto doc = nlohmann::json::parse(in);
    for (const auto& f : doc["features"]) {
      t.tags.push_back(f["properties"]["tag"].is_string() ? f["properties"]["tag"] : "");
      t.visible.push_back(f["properties"]["visible"].get<bool>());
      std::array<double, 4> box = {1e300, 1e300, -1e300, -1e300};
      for (const auto& p : f["geometry"]["coordinates"][0]) {
        box[0] = std::min(box[0], p[0].get<double>()),
        box[1] = std::min(box[1], p[1].get<double>());
        box[2] = std::max(box[2], p[0].get<double>()),
        box[3] = std::max(box[3], p[1].get<double>());
      }
      t.boxes.push_back(box);
    }
    return t;
  }

  TempDir dir_;
  std::string store_, out_;
  std::array<double, 4> bbox_{};
  double cx_ = 0, cy_ = 0;
};

TEST_F(ExportCliTest, EveryFormatWritesTheSameSurface) {
  std::map<std::string, nlohmann::json> report;
  for (const char* ext : {"obj", "ply", "stl", "glb", "geojson"}) {
    // The format comes from the extension.
    report[ext] = Export("--surface terrain -o " + Quote(out_ + "/t." + ext));
    EXPECT_EQ(report[ext]["format"], ext);
    EXPECT_EQ(report[ext]["triangles"], report["obj"]["triangles"]) << ext;
    EXPECT_EQ(report[ext]["bytes"].get<uintmax_t>(),
              std::filesystem::file_size(out_ + "/t." + ext));
  }
  EXPECT_GT(report["obj"]["triangles"].get<int>(), 1000);
  testing::ExpectValidGltf(out_ + "/t.glb");
  EXPECT_LT(report["glb"]["bytes"].get<int64_t>(), report["obj"]["bytes"].get<int64_t>());
  EXPECT_EQ(ReadGeoJson(out_ + "/t.geojson").tags.size(), report["obj"]["triangles"].get<size_t>());
  // The GLB names the formations and holds the 62 features in its property table.
  const testing::GlbFile glb = testing::ParseGlb(out_ + "/t.glb");
  EXPECT_EQ(glb.gltf["extensions"]["EXT_structural_metadata"]["propertyTables"][0]["count"], 62);
  EXPECT_EQ(glb.gltf["asset"]["extras"]["tinbase"]["epsg"], 28350);
  std::set<std::string> materials;
  for (const auto& m : glb.gltf["materials"]) materials.insert(m["name"]);
  EXPECT_GT(materials.size(), 10u);
  EXPECT_EQ(materials.count("invisible"), 1u);
  EXPECT_EQ(FilesInOut(), 5u);
}

TEST_F(ExportCliTest, SelectionOptionsNarrowEveryFormat) {
  const auto all = Export("--surface terrain --format geojson -o " + Quote(out_ + "/all.json"));
  const Triangles every = ReadGeoJson(out_ + "/all.json");
  // The most common formation.
  std::map<std::string, int> count;
  for (const std::string& t : every.tags)
    if (!t.empty()) ++count[t];
  ASSERT_FALSE(count.empty());
  const std::string tag =
      std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) {
        return a.second < b.second;
      })->first;

  const auto visible =
      Export("--surface terrain --visible-only -o " + Quote(out_ + "/visible.geojson"));
  EXPECT_LT(visible["triangles"], all["triangles"]);
  for (bool v : ReadGeoJson(out_ + "/visible.geojson").visible) EXPECT_TRUE(v);

  const auto tagged =
      Export("--surface terrain --tag " + Quote(tag) + " -o " + Quote(out_ + "/tag.geojson"));
  EXPECT_LT(tagged["triangles"], all["triangles"]);
  for (const std::string& t : ReadGeoJson(out_ + "/tag.geojson").tags) EXPECT_EQ(t, tag);

  const double x0 = cx_ - 3000, y0 = cy_ - 3000, x1 = cx_ + 3000, y1 = cy_ + 3000;
  const std::string box = std::to_string(x0) + "," + std::to_string(y0) + "," + std::to_string(x1) +
                          "," + std::to_string(y1);
  const auto window =
      Export("--surface terrain --bbox " + box + " -o " + Quote(out_ + "/box.geojson"));
  EXPECT_LT(window["triangles"], all["triangles"]);
  for (const auto& b : ReadGeoJson(out_ + "/box.geojson").boxes)
    EXPECT_TRUE(b[0] <= x1 && b[2] >= x0 && b[1] <= y1 && b[3] >= y0);

  const auto feature = Export("--surface terrain --feature 1 -o " + Quote(out_ + "/f.geojson"));
  EXPECT_LT(feature["triangles"], all["triangles"]);

  // The same selections as GLB, each valid, each with the triangles the GeoJSON had.
  for (const auto& [name, args, want] :
       {std::tuple{"tag", "--tag " + Quote(tag), tagged},
        std::tuple{"box", "--bbox " + box + " --visible-only", nlohmann::json()},
        std::tuple{"feature", std::string("--feature 1"), feature}}) {
    const std::string path = out_ + "/" + name + ".glb";
    const auto r = Export("--surface terrain " + args + " -o " + Quote(path));
    if (!want.is_null()) {
      EXPECT_EQ(r["triangles"], want["triangles"]) << name;
    }
    testing::ExpectValidGltf(path);
  }
  const testing::GlbFile glb = testing::ParseGlb(out_ + "/tag.glb");
  // The tag's material, and the invisible one for its triangles under the erase square.
  std::set<std::string> materials;
  for (const auto& m : glb.gltf["materials"]) materials.insert(m["name"]);
  EXPECT_EQ(materials.count(tag), 1u);
  materials.erase("invisible");
  EXPECT_EQ(materials.size(), 1u);
}

TEST_F(ExportCliTest, BadInputIsOneLineAndLeavesNoFile) {
  const std::string s = Quote(store_);
  ExpectRejected(store_,
                 "export " + s + " --surface terrain --format dxf -o " + Quote(out_ + "/x.dxf"),
                 "unknown export format 'dxf' (expected one of: obj, ply, stl, glb, geojson, gpkg, "
                 "landxml, vdb)");
  ExpectRejected(store_, "export " + s + " --surface terrain -o " + Quote(out_ + "/x.dwg"),
                 "cannot tell the format from");
  const std::string unwritable = out_ + "/no/such/dir/t.glb";
  ExpectRejected(store_, "export " + s + " --surface terrain -o " + Quote(unwritable), unwritable);
  ExpectRejected(
      store_,
      "export " + s + " --surface terrain --bbox 0,0,10,10 -o " + Quote(out_ + "/empty.glb"),
      "nothing selected");
  ExpectRejected(store_,
                 "export " + s + " --surface terrain --bbox 1,2,x,4 -o " + Quote(out_ + "/bad.glb"),
                 "1,2,x,4");
  ExpectRejected(
      store_,
      "export " + s + " --surface terrain --tag 'no such unit' -o " + Quote(out_ + "/tag.ply"),
      "no such unit");
  ExpectRejected(store_, "export " + s + " --surface nosuch -o " + Quote(out_ + "/n.stl"),
                 "nosuch");
  EXPECT_EQ(FilesInOut(), 0u);

  // A failed export over an existing file leaves that file as it was.
  const std::string old = out_ + "/old.glb";
  std::ofstream(old) << "earlier";
  ExpectRejected(store_, "export " + s + " --surface terrain --bbox 0,0,10,10 -o " + Quote(old),
                 "nothing selected");
  std::ifstream in(old);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "earlier");
  EXPECT_EQ(FilesInOut(), 1u);
}

// Paper 002 in one command: a DEM window at the sampling step, edge-collapsed to N faces, GLB.
TEST_F(ExportCliTest, DemClipReducesTheWindowToTheFaceBudgetAsGlb) {
  const std::string box = std::to_string(bbox_[0] + 1000) + "," + std::to_string(bbox_[1] + 1000) +
                          "," + std::to_string(bbox_[2] - 1000) + "," +
                          std::to_string(bbox_[3] - 1000);
  const std::string path = out_ + "/clip.glb";
  const CliResult r = RunCli("dem clip --json " + Quote(store_) + " --bbox " + box +
                             " --max-cells 100000 --faces 800 --format glb -o " + Quote(path));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = Json(r);
  EXPECT_EQ(j["format"], "glb");
  EXPECT_LE(j["width"].get<int>() * j["height"].get<int>(), 100000);
  EXPECT_GT(j["faces_in"].get<int>(), 800);
  EXPECT_LE(j["faces"].get<int>(), 800);
  EXPECT_TRUE(j["budget_met"].get<bool>());
  EXPECT_GT(j["max_error"].get<double>(), 0);
  testing::ExpectValidGltf(path);
  const testing::GlbFile glb = testing::ParseGlb(path);
  size_t indices = 0;
  for (const auto& p : glb.gltf["meshes"][0]["primitives"])
    indices += glb.gltf["accessors"][p["indices"].get<int>()]["count"].get<size_t>();
  EXPECT_EQ(indices / 3, j["faces"].get<size_t>());

  ExpectRejected(
      store_,
      "dem clip " + Quote(store_) + " --bbox " + box + " --faces 1 -o " + Quote(out_ + "/one.glb"),
      "--faces must be at least 2");
  ExpectRejected(
      store_,
      "dem clip " + Quote(store_) + " --bbox " + box + " --faces 100 -o " + Quote(out_ + "/c.tif"),
      "--faces applies to mesh formats");
  ExpectRejected(
      store_,
      "dem clip " + Quote(store_) + " --bbox 0,0,10,10 --faces 100 -o " + Quote(out_ + "/far.glb"),
      "does not overlap");
  EXPECT_FALSE(std::filesystem::exists(out_ + "/one.glb"));
  EXPECT_FALSE(std::filesystem::exists(out_ + "/far.glb"));
}

}  // namespace
}  // namespace tinbase
