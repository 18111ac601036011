// `tinbase tiles build/export/info` end to end on real SRTM data: every exported tile (plain and
// gzipped) decodes with npm @here/quantized-mesh-decoder to exactly what tinbase's own reader
// reads; both readers agree on the public sample tiles in tests/data/terrain; bad requests are
// refused with one line and change nothing.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>

#include "core/tiles/quantized_mesh.h"
#include "db/surface_store.h"
#include "db/tiles/tile_store.h"
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

std::string ToolsDir() { return std::string(TINBASE_TEST_DATA_DIR) + "/../tools"; }

// What the npm decoder reads from `files`, by file name. Fails the test when node or the
// decoder is missing (scripts/install-test-tools.sh installs it).
nlohmann::json DecodeWithNpm(const std::vector<std::string>& files) {
  const std::string module = ToolsDir() + "/node_modules/@here/quantized-mesh-decoder";
  EXPECT_TRUE(std::filesystem::exists(module))
      << module << " is missing: run scripts/install-test-tools.sh";
  std::string command = "node ";
  command += Quote(ToolsDir() + "/decode_terrain.mjs");
  for (const std::string& f : files) {
    command += ' ';
    command += Quote(f);
  }
  FILE* pipe = popen(command.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  if (pipe == nullptr) return {};
  std::string out;
  char buf[65536];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  EXPECT_EQ(pclose(pipe), 0) << command;
  if (out.empty()) return {};
  return nlohmann::json::parse(out);
}

std::vector<uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<uint8_t> Gunzip(const std::string& path) {
  FILE* pipe = popen(("gzip -dc " + Quote(path)).c_str(), "r");
  std::vector<uint8_t> out;
  uint8_t buf[65536];
  size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, pipe)) > 0) out.insert(out.end(), buf, buf + n);
  EXPECT_EQ(pclose(pipe), 0) << path;
  return out;
}

// The npm decoder's reading of one tile equals ours.
void ExpectSameReading(const nlohmann::json& npm, const QuantizedMesh& ours, const std::string& f) {
  ASSERT_TRUE(npm.is_object()) << f;
  EXPECT_EQ(npm["vertices"], ours.vertex_count()) << f;
  EXPECT_EQ(npm["triangles"], ours.triangles.size() / 3) << f;
  EXPECT_EQ(npm["u"].get<std::vector<uint16_t>>(), ours.u) << f;
  EXPECT_EQ(npm["v"].get<std::vector<uint16_t>>(), ours.v) << f;
  EXPECT_EQ(npm["height"].get<std::vector<uint16_t>>(), ours.height) << f;
  EXPECT_EQ(npm["indices"].get<std::vector<uint32_t>>(), ours.triangles) << f;
  EXPECT_EQ(npm["west"].get<std::vector<uint32_t>>(), ours.west) << f;
  EXPECT_EQ(npm["east"].get<std::vector<uint32_t>>(), ours.east) << f;
  EXPECT_EQ(npm["south"].get<std::vector<uint32_t>>(), ours.south) << f;
  EXPECT_EQ(npm["north"].get<std::vector<uint32_t>>(), ours.north) << f;
  EXPECT_EQ(npm["header"]["minHeight"].get<float>(), ours.header.min_height) << f;
  EXPECT_EQ(npm["header"]["maxHeight"].get<float>(), ours.header.max_height) << f;
  EXPECT_EQ(npm["header"]["boundingSphereRadius"].get<double>(), ours.header.sphere_radius) << f;
  EXPECT_EQ(npm["header"]["horizonOcclusionPointZ"].get<double>(), ours.header.horizon_z) << f;
  EXPECT_EQ(npm["normals"].is_null(), !ours.normals.has_value()) << f;
  if (ours.normals) {
    EXPECT_EQ(npm["normals"].get<std::vector<uint8_t>>(), *ours.normals) << f;
  }
  EXPECT_EQ(npm["waterMask"].is_null(), !ours.water_mask.has_value()) << f;
  if (ours.water_mask) {
    EXPECT_EQ(npm["waterMask"].get<std::vector<uint8_t>>(), *ours.water_mask) << f;
  }
  EXPECT_EQ(npm["metadata"].is_null(), !ours.metadata.has_value()) << f;
  if (ours.metadata) {
    EXPECT_EQ(npm["metadata"], nlohmann::json::parse(*ours.metadata)) << f;
  }
}

TEST(TileReadersTest, BothReadersAgreeOnThePublicSampleTiles) {
  const std::vector<std::string> files = {DataPath("terrain/9_533_383.terrain"),
                                          DataPath("terrain/9_769_319_watermask.terrain")};
  const nlohmann::json npm = DecodeWithNpm(files);
  for (const std::string& f : files) {
    auto ours = DecodeQuantizedMesh(ReadBytes(f), f);
    ASSERT_TRUE(ours.ok()) << ours.status().ToString();
    ExpectSameReading(npm[f], *ours, f);
  }
}

class TilesCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    testing::CopyRecipeStore(testing::DemoRecipe(), store_);
  }
  TempDir dir_;
  std::string store_;
};

TEST_F(TilesCliTest, ExportedTilesDecodeWithTheNpmDecoderAsWithOurs) {
  const nlohmann::json built =
      Json(RunWrite(store_, "tiles build " + Quote(store_) +
                                " --surface t --max-zoom 9 --extensions octvertexnormals,metadata "
                                "--json"));
  EXPECT_EQ(built["max_zoom"], 9);
  ASSERT_EQ(built["levels"].size(), 10u);
  const nlohmann::json info =
      Json(RunCli("tiles info " + Quote(store_) + " --surface t --verify --json"));
  EXPECT_EQ(info["decoded"], info["tiles"]);
  EXPECT_EQ(info["tiles"], built["tiles"]);

  for (const bool gzip : {false, true}) {
    const std::string out = dir_.Path(gzip ? "gz" : "plain");
    std::string args = "tiles export " + Quote(store_) + " --surface t -o " + Quote(out);
    if (gzip) args += " --gzip";
    CliResult r = RunCli(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream layer_file(out + "/layer.json");
    const nlohmann::json layer = nlohmann::json::parse(layer_file);
    EXPECT_EQ(layer["format"], "quantized-mesh-1.0");
    EXPECT_EQ(layer["available"], info["layer"]["available"]);
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(out))
      if (entry.path().extension() == ".terrain") files.push_back(entry.path().string());
    EXPECT_EQ(static_cast<int64_t>(files.size()), built["tiles"].get<int64_t>());
    const nlohmann::json npm = DecodeWithNpm(files);
    for (const std::string& f : files) {
      const std::vector<uint8_t> bytes = gzip ? Gunzip(f) : ReadBytes(f);
      auto ours = DecodeQuantizedMesh(bytes, f);
      ASSERT_TRUE(ours.ok()) << ours.status().ToString();
      ExpectSameReading(npm[f], *ours, f);
    }
  }
}

// Every tile of the store's pyramid: key -> (bytes, transaction).
std::map<TileKey, std::pair<std::vector<uint8_t>, int64_t>> TilesOf(const std::string& path) {
  std::map<TileKey, std::pair<std::vector<uint8_t>, int64_t>> out;
  auto store = Store::Open(path, Store::Access::kReadOnly);
  EXPECT_TRUE(store.ok());
  auto surface = SurfaceStore(**store).Find("t");
  EXPECT_TRUE(surface.ok());
  TileStore tiles((*store)->db());
  auto keys = tiles.Keys(surface->id);
  EXPECT_TRUE(keys.ok());
  for (const TileKey& key : *keys) {
    auto tile = tiles.Tile(surface->id, key);
    EXPECT_TRUE(tile.ok() && tile->has_value());
    out.emplace(key, std::move(**tile));
  }
  return out;
}

TEST_F(TilesCliTest, UpdateRewritesOnlyTheTilesAnEditTouchedAndEqualsAFreshBuild) {
  const std::string build_args =
      " --surface t --max-zoom 11 --extensions octvertexnormals,metadata";
  RunWrite(store_, "tiles build " + Quote(store_) + build_args);
  const auto before = TilesOf(store_);
  // A 1 km square in the mountains (small triangles: the change's region stays small) flattened to
  // a level inside the surface's height range.
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const auto& bbox = info["dems"][0]["bbox"];
  const double x = bbox[0].get<double>() + 0.5 * (bbox[2].get<double>() - bbox[0].get<double>());
  const double y = bbox[1].get<double>() + 0.9 * (bbox[3].get<double>() - bbox[1].get<double>());
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":")" << info["crs"].get<std::string>()
                        << R"("}},"features":[{"type":"Feature","properties":{},)"
                        << R"("geometry":{"type":"Polygon","coordinates":[[)"
                        << "[" << x << "," << y << "],[" << x + 1000 << "," << y << "],["
                        << x + 1000 << "," << y + 1000 << "],[" << x << "," << y + 1000 << "],["
                        << x << "," << y << "]]]}}]}";
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(square) +
                       " --surface t --mode replace --level 1500");
  const nlohmann::json update =
      Json(RunWrite(store_, "tiles update " + Quote(store_) + " --surface t --json"));
  EXPECT_EQ(update["changes"], 1);
  EXPECT_FALSE(update["full_rebuild"].get<bool>()) << update.dump();
  EXPECT_GT(update["tiles_rewritten"].get<int64_t>(), 0);
  EXPECT_EQ(update["tiles_rewritten"].get<int64_t>() + update["tiles_deleted"].get<int64_t>(),
            update["tiles_meeting"].get<int64_t>());
  const auto after = TilesOf(store_);

  // A fresh build of the edited surface, in a copy of the store.
  const std::string fresh = StoreTarget(dir_, "fresh.tinbase");
  testing::CopyStore(store_, fresh);
  RunWrite(fresh, "tiles build " + Quote(fresh) + build_args);
  const auto rebuilt = TilesOf(fresh);
  ASSERT_EQ(after.size(), rebuilt.size());
  int untouched = 0;
  for (const auto& [key, tile] : after) {
    auto it = rebuilt.find(key);
    ASSERT_NE(it, rebuilt.end()) << key.ToString();
    EXPECT_EQ(tile.first, it->second.first) << key.ToString() << " differs from a fresh build";
    auto old = before.find(key);
    if (old != before.end() && tile.second == old->second.second) {
      EXPECT_EQ(tile.first, old->second.first) << key.ToString();
      ++untouched;
    }
  }
  EXPECT_EQ(untouched + update["tiles_rewritten"].get<int64_t>(),
            static_cast<int64_t>(after.size()));
  EXPECT_GT(untouched, update["tiles_rewritten"].get<int64_t>()) << "most tiles stay as they were";
  // Nothing left to do.
  const nlohmann::json again =
      Json(RunCli("tiles update " + Quote(store_) + " --surface t --json"));
  EXPECT_EQ(again["changes"], 0);
}

TEST_F(TilesCliTest, AnEditWithUpdateTilesLeavesNothingForTilesUpdate) {
  const std::string build_args = " --surface t --max-zoom 10";
  RunWrite(store_, "tiles build " + Quote(store_) + build_args);
  const nlohmann::json info = Json(RunCli("info --json " + Quote(store_)));
  const auto& bbox = info["dems"][0]["bbox"];
  const double x = bbox[0].get<double>() + 0.5 * (bbox[2].get<double>() - bbox[0].get<double>());
  const double y = bbox[1].get<double>() + 0.9 * (bbox[3].get<double>() - bbox[1].get<double>());
  const std::string square = dir_.Path("square.geojson");
  std::ofstream(square) << R"({"type":"FeatureCollection","crs":{"type":"name","properties":)"
                        << R"({"name":")" << info["crs"].get<std::string>()
                        << R"("}},"features":[{"type":"Feature","properties":{},)"
                        << R"("geometry":{"type":"Polygon","coordinates":[[)"
                        << "[" << x << "," << y << "],[" << x + 800 << "," << y << "],[" << x + 800
                        << "," << y + 800 << "],[" << x << "," << y + 800 << "],[" << x << "," << y
                        << "]]]}}]}";
  const CliResult add = RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(square) +
                                             " --surface t --mode erase --update-tiles");
  EXPECT_NE(add.out.find("tiles of 't': "), std::string::npos) << add.out;
  const nlohmann::json again =
      Json(RunCli("tiles update " + Quote(store_) + " --surface t --json"));
  EXPECT_EQ(again["changes"], 0) << "the edit brought the tiles up to date";
  const std::string fresh = StoreTarget(dir_, "fresh.tinbase");
  testing::CopyStore(store_, fresh);
  RunWrite(fresh, "tiles build " + Quote(fresh) + build_args);
  const auto edited = TilesOf(store_);
  const auto rebuilt = TilesOf(fresh);
  ASSERT_EQ(edited.size(), rebuilt.size());
  for (const auto& [key, tile] : edited)
    EXPECT_EQ(tile.first, rebuilt.at(key).first) << key.ToString() << " differs from a fresh build";
}

TEST_F(TilesCliTest, BadRequestsAreRefusedWithOneLine) {
  ExpectRejected(store_,
                 "tiles export " + Quote(store_) + " --surface t -o " + Quote(dir_.Path("x")),
                 "has no tiles");
  ExpectRejected(store_, "tiles build " + Quote(store_) + " --surface t --max-zoom 25",
                 "--max-zoom 25 is outside 0..24");
  ExpectRejected(store_, "tiles build " + Quote(store_) + " --surface t --extensions normals",
                 "unknown tile extension 'normals'");
  ExpectRejected(store_, "tiles build " + Quote(store_) + " --surface nope", "nope");
  ExpectRejected(store_, "tiles update " + Quote(store_) + " --surface t",
                 "has no tiles to update");
  ExpectRejected(store_, "tiles make " + Quote(store_) + " --surface t --tile 3/1",
                 "--tile '3/1': expected z/x/y");
  ExpectRejected(store_, "tiles make " + Quote(store_) + " --surface t --tile 25/0/0",
                 "level over 24");
  ExpectRejected(store_, "tiles make " + Quote(store_) + " --surface t --tile 3/0/0",
                 "has no tiles");
  ExpectRejected(store_, "tiles build " + Quote(store_) + " --surface t --window-triangles 0",
                 "--window-triangles must be positive");
  EXPECT_FALSE(std::filesystem::exists(dir_.Path("x")));
}

}  // namespace
}  // namespace tinbase
