// The tile routes through a real socket, as CesiumJS asks for tiles: layer.json, then every tile
// with Cesium's Accept header, decoded by the npm quantized-mesh decoder (a reader tinbase did
// not write) to what the store holds, less the extensions the client did not ask for; gzip only
// when accepted; entity tags that change when an edit rewrites a tile and only then; 304 on
// If-None-Match; bad tile coordinates 400, missing tiles 404.
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"
#include "db/store.h"
#include "db/surface_store.h"
#include "db/tiles/tile_store.h"
#include "tests/support/service_support.h"
#include "tests/support/store_target.h"

namespace tinbase::testing {
namespace {

// What CesiumTerrainProvider sends when it wants every extension.
constexpr const char* kCesiumAccept =
    "application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,"
    "application/octet-stream;q=0.9,*/*;q=0.01";

std::string ToolsDir() { return std::string(TINBASE_TEST_DATA_DIR) + "/../tools"; }

// What the npm decoder reads from each file (gunzipped first when gzipped), by file name. A
// missing node or decoder fails the test (scripts/install-test-tools.sh installs it).
nlohmann::json DecodeWithNpm(const std::vector<std::string>& files) {
  const std::string module = ToolsDir() + "/node_modules/@here/quantized-mesh-decoder";
  EXPECT_TRUE(std::filesystem::exists(module))
      << module << " is missing: run scripts/install-test-tools.sh";
  // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string here.
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
  for (size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  EXPECT_EQ(pclose(pipe), 0) << command;
  auto json = nlohmann::json::parse(out, nullptr, /*allow_exceptions=*/false);
  EXPECT_FALSE(json.is_discarded()) << "the decoder printed no JSON: " << out;
  return json;
}

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string Gunzip(const std::string& path) {
  FILE* pipe = popen(("gzip -dc " + Quote(path)).c_str(), "r");
  std::string out;
  char buf[65536];
  for (size_t n; (n = fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
  EXPECT_EQ(pclose(pipe), 0) << path;
  return out;
}

// The npm decoder read `mesh`'s geometry, and exactly the extensions `normals`, `water`,
// `metadata` of it.
void ExpectReading(const nlohmann::json& npm, const QuantizedMesh& mesh, bool normals, bool water,
                   bool metadata, const std::string& what) {
  ASSERT_TRUE(HasFields(npm, {"vertices", "u", "v", "height", "indices", "west", "north", "header",
                              "normals", "waterMask", "metadata"}))
      << what;
  ASSERT_TRUE(HasFields(npm["header"], {"maxHeight"})) << what;
  EXPECT_EQ(npm["vertices"], mesh.vertex_count()) << what;
  EXPECT_EQ(npm["u"].get<std::vector<uint16_t>>(), mesh.u) << what;
  EXPECT_EQ(npm["v"].get<std::vector<uint16_t>>(), mesh.v) << what;
  EXPECT_EQ(npm["height"].get<std::vector<uint16_t>>(), mesh.height) << what;
  EXPECT_EQ(npm["indices"].get<std::vector<uint32_t>>(), mesh.triangles) << what;
  EXPECT_EQ(npm["west"].get<std::vector<uint32_t>>(), mesh.west) << what;
  EXPECT_EQ(npm["north"].get<std::vector<uint32_t>>(), mesh.north) << what;
  EXPECT_EQ(npm["header"]["maxHeight"].get<float>(), mesh.header.max_height) << what;
  EXPECT_EQ(npm["normals"].is_null(), !(normals && mesh.normals)) << what;
  if (normals && mesh.normals) {
    EXPECT_EQ(npm["normals"].get<std::vector<uint8_t>>(), *mesh.normals) << what;
  }
  EXPECT_EQ(npm["waterMask"].is_null(), !(water && mesh.water_mask)) << what;
  if (water && mesh.water_mask) {
    EXPECT_EQ(npm["waterMask"].get<std::vector<uint8_t>>(), *mesh.water_mask) << what;
  }
  EXPECT_EQ(npm["metadata"].is_null(), !(metadata && mesh.metadata)) << what;
}

struct TileAnswer {
  int status = 0;
  std::string body;  // as sent: gzipped when Content-Encoding says so
  std::string content_type, encoding, etag, cache_control, vary;
};

class TileRoutesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = StoreTarget(dir_, "s.tinbase");
    ASSERT_NO_FATAL_FAILURE(CopyDemoStoreWithTiles(store_));
    service::ServiceOptions options;
    options.store_path = store_;
    service_ = std::make_unique<TestService>(options);
    ASSERT_TRUE(service_->running());
  }

  // GET `path` with the given request headers; the body is kept as sent (not gunzipped).
  TileAnswer Get(const std::string& path, const httplib::Headers& headers) {
    auto client = service_->Client();
    client->set_decompress(false);
    auto r = client->Get(path.c_str(), headers);
    TileAnswer a;
    if (!r) {
      ADD_FAILURE() << path << ": no answer: " << httplib::to_string(r.error());
      return a;
    }
    a.status = r->status;
    a.body = r->body;
    a.content_type = r->get_header_value("Content-Type");
    a.encoding = r->get_header_value("Content-Encoding");
    a.etag = r->get_header_value("ETag");
    a.cache_control = r->get_header_value("Cache-Control");
    a.vary = r->get_header_value("Vary");
    return a;
  }

  // Every tile key layer.json lists as available; none (and a failure) when it lists none.
  std::vector<TileKey> AvailableTiles() {
    const nlohmann::json layer =
        JsonAnswer(service_->Client()->Get("/surfaces/t/tiles/layer.json"));
    std::vector<TileKey> keys;
    if (!HasFields(layer, {"available"})) {
      ADD_FAILURE() << "layer.json: " << layer.dump();
      return keys;
    }
    for (size_t level = 0; level < layer["available"].size(); ++level)
      for (const auto& r : layer["available"][level])
        for (int64_t x = r["startX"]; x <= r["endX"].get<int64_t>(); ++x)
          for (int64_t y = r["startY"]; y <= r["endY"].get<int64_t>(); ++y)
            keys.push_back({static_cast<int>(level), x, y});
    EXPECT_FALSE(keys.empty()) << "layer.json lists no tile: " << layer.dump();
    return keys;
  }

  // Every tile the store holds; none (and a failure) when they cannot be read.
  std::vector<TileKey> StoredKeys() {
    auto store = Store::Open(store_, Store::Access::kReadOnly);
    EXPECT_TRUE(store.ok()) << store.status().ToString();
    if (!store.ok()) return {};
    auto surface = SurfaceStore(**store).Find("t");
    EXPECT_TRUE(surface.ok()) << surface.status().ToString();
    if (!surface.ok()) return {};
    auto keys = TileStore((*store)->db()).Keys(surface->id);
    EXPECT_TRUE(keys.ok()) << keys.status().ToString();
    if (!keys.ok()) return {};
    return {keys->begin(), keys->end()};
  }

  // The tile's bytes as the store holds them; empty (and a failure) when they cannot be read.
  std::string StoredBytes(const TileKey& key) {
    auto store = Store::Open(store_, Store::Access::kReadOnly);
    EXPECT_TRUE(store.ok()) << store.status().ToString();
    if (!store.ok()) return {};
    auto surface = SurfaceStore(**store).Find("t");
    EXPECT_TRUE(surface.ok()) << surface.status().ToString();
    if (!surface.ok()) return {};
    auto tile = TileStore((*store)->db()).Tile(surface->id, key);
    EXPECT_TRUE(tile.ok() && tile->has_value()) << key.ToString();
    if (!tile.ok() || !tile->has_value()) return {};
    return std::string((**tile).first.begin(), (**tile).first.end());
  }

  // The tile as the store holds it; an empty mesh (and a failure) when it cannot be read.
  QuantizedMesh Stored(const TileKey& key) {
    const std::string bytes = StoredBytes(key);
    if (bytes.empty()) return {};
    auto mesh =
        DecodeQuantizedMesh(std::vector<uint8_t>(bytes.begin(), bytes.end()), key.ToString());
    EXPECT_TRUE(mesh.ok()) << mesh.status().ToString();
    return mesh.ok() ? *mesh : QuantizedMesh{};
  }

  static std::string PathOf(const TileKey& key) {
    return "/surfaces/t/tiles/" + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" +
           std::to_string(key.y) + ".terrain";
  }

  TempDir dir_;
  std::string store_;
  std::unique_ptr<TestService> service_;
};

TEST_F(TileRoutesTest, LayerJsonDescribesThePyramidForCesium) {
  auto r = service_->Client()->Get("/surfaces/t/tiles/layer.json");
  const nlohmann::json layer = JsonAnswer(r);
  ASSERT_TRUE(r);
  ASSERT_TRUE(HasFields(layer, {"format", "scheme", "maxzoom", "extensions", "tiles"}));
  EXPECT_EQ(layer["format"], "quantized-mesh-1.0");
  EXPECT_EQ(layer["scheme"], "tms");
  EXPECT_EQ(layer["maxzoom"], kDemoTilesMaxZoom);
  EXPECT_EQ(layer["extensions"],
            nlohmann::json::array({"octvertexnormals", "watermask", "metadata"}));
  // Relative, so Cesium asks for tiles under the same path.
  EXPECT_EQ(layer["tiles"][0], "{z}/{x}/{y}.terrain?v={version}");
  EXPECT_EQ(r->get_header_value("Cache-Control"), "no-cache");
  EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), "*");
  const std::string etag = r->get_header_value("ETag");
  ASSERT_FALSE(etag.empty());
  auto again = service_->Client()->Get("/surfaces/t/tiles/layer.json", {{"If-None-Match", etag}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);
  EXPECT_TRUE(again->body.empty());
  // The pyramid may be named (after its surface, as GET /surfaces lists it).
  JsonAnswer(service_->Client()->Get("/surfaces/t/tiles/layer.json?pyramid=t"));
}

TEST_F(TileRoutesTest, EveryTileDecodesWithTheNpmDecoderAsStoredLessWhatWasNotAskedFor) {
  const std::vector<TileKey> keys = StoredKeys();
  ASSERT_GT(keys.size(), 10u);
  std::vector<std::string> files;
  std::map<std::string, std::pair<TileKey, bool>> asked_all;  // file -> key, all extensions
  for (const TileKey& key : keys) {
    for (const bool all : {true, false}) {
      httplib::Headers headers = {{"Accept-Encoding", "gzip, deflate, br"}};
      if (all) headers.emplace("Accept", kCesiumAccept);
      const TileAnswer a = Get(PathOf(key), headers);
      ASSERT_EQ(a.status, 200) << key.ToString() << " " << a.body;
      EXPECT_EQ(a.encoding, "gzip") << key.ToString();
      ASSERT_GE(a.body.size(), 2u);
      EXPECT_EQ(a.body.substr(0, 2), "\x1f\x8b") << key.ToString();
      EXPECT_EQ(a.cache_control, "no-cache");
      EXPECT_EQ(a.vary, "Accept, Accept-Encoding");
      const std::string file =
          dir_.Path(std::to_string(key.level) + "_" + std::to_string(key.x) + "_" +
                    std::to_string(key.y) + (all ? "_all" : "_none") + ".terrain");
      WriteFile(file, a.body);
      files.push_back(file);
      asked_all[file] = {key, all};
      // The content type names what the tile carries: at most what was asked.
      if (!all) {
        EXPECT_EQ(a.content_type, "application/vnd.quantized-mesh") << key.ToString();
      }
    }
  }
  const nlohmann::json npm = DecodeWithNpm(files);
  ASSERT_TRUE(HasFields(npm, files));
  int with_water_mask = 0, with_metadata = 0;
  for (const auto& [file, what] : asked_all) {
    const QuantizedMesh stored = Stored(what.first);
    ExpectReading(npm[file], stored, what.second, what.second, what.second, file);
    if (what.second && stored.water_mask && stored.water_mask->size() > 1) ++with_water_mask;
    if (what.second && stored.metadata) ++with_metadata;
  }
  // The fixture's lake gives some tiles a real mask; level 10 carries metadata.
  EXPECT_GT(with_water_mask, 0);
  EXPECT_GT(with_metadata, 0);
}

TEST_F(TileRoutesTest, SendsOnlyTheExtensionsBothThePyramidHasAndTheClientAskedFor) {
  // A tile of the finest level, where metadata is, with the lake's water mask.
  TileKey key;
  for (const TileKey& k : StoredKeys())
    if (k.level == kDemoTilesMaxZoom) {
      const QuantizedMesh mesh = Stored(k);
      if (mesh.water_mask && mesh.water_mask->size() > 1) key = k;
    }
  ASSERT_EQ(key.level, kDemoTilesMaxZoom);
  struct Case {
    std::string accept;
    bool normals, water, metadata;
    std::string content_type;
  };
  const std::string qm = "application/vnd.quantized-mesh";
  const std::vector<Case> cases = {
      {qm + ";extensions=octvertexnormals,application/octet-stream;q=0.9", true, false, false,
       qm + ";extensions=octvertexnormals"},
      // An extension the pyramid does not have (Cesium's old "vertexnormals") is not sent.
      {qm + ";extensions=watermask-vertexnormals", false, true, false,
       qm + ";extensions=watermask"},
      {kCesiumAccept, true, true, true, qm + ";extensions=octvertexnormals-watermask-metadata"},
      // Refused with q=0: nothing.
      {qm + ";extensions=octvertexnormals;q=0,*/*", false, false, false, qm},
      {"application/octet-stream", false, false, false, qm},
  };
  std::vector<std::string> files;
  std::set<std::string> etags;
  for (size_t i = 0; i < cases.size(); ++i) {
    const TileAnswer a = Get(PathOf(key), {{"Accept", cases[i].accept}});
    ASSERT_EQ(a.status, 200) << a.body;
    EXPECT_EQ(a.encoding, "") << "gzip only when accepted";
    EXPECT_EQ(a.content_type, cases[i].content_type) << cases[i].accept;
    files.push_back(dir_.Path("case" + std::to_string(i) + ".terrain"));
    WriteFile(files.back(), a.body);
    etags.insert(a.etag);
  }
  // Different representations, different tags (the last two are the same representation).
  EXPECT_EQ(etags.size(), cases.size() - 1);
  const nlohmann::json npm = DecodeWithNpm(files);
  ASSERT_TRUE(HasFields(npm, files));
  const QuantizedMesh stored = Stored(key);
  ASSERT_TRUE(stored.normals && stored.water_mask && stored.metadata);
  for (size_t i = 0; i < cases.size(); ++i)
    ExpectReading(npm[files[i]], stored, cases[i].normals, cases[i].water, cases[i].metadata,
                  cases[i].accept);
}

TEST_F(TileRoutesTest, GzipsOnlyWhenTheClientAcceptsIt) {
  const std::vector<TileKey> available = AvailableTiles();
  ASSERT_FALSE(available.empty());
  const std::string path = PathOf(available.back());
  const TileAnswer plain = Get(path, {{"Accept", kCesiumAccept}, {"Accept-Encoding", "identity"}});
  ASSERT_EQ(plain.status, 200);
  EXPECT_EQ(plain.encoding, "");
  for (const char* accept : {"gzip", "deflate, gzip;q=0.5", "*", "br, x-gzip"}) {
    const TileAnswer a = Get(path, {{"Accept", kCesiumAccept}, {"Accept-Encoding", accept}});
    EXPECT_EQ(a.encoding, "gzip") << accept;
    const std::string file = dir_.Path("t.gz");
    WriteFile(file, a.body);
    EXPECT_EQ(Gunzip(file), plain.body) << accept;
    EXPECT_NE(a.etag, plain.etag) << "a gzipped answer is another representation";
  }
  for (const char* refuse : {"gzip;q=0", "br", "*;q=0", "*, gzip;q=0"}) {
    const TileAnswer a = Get(path, {{"Accept", kCesiumAccept}, {"Accept-Encoding", refuse}});
    EXPECT_EQ(a.encoding, "") << refuse;
    EXPECT_EQ(a.body, plain.body) << refuse;
  }
}

TEST_F(TileRoutesTest, IfNoneMatchWithTheCurrentTagIsA304) {
  const std::vector<TileKey> available = AvailableTiles();
  ASSERT_FALSE(available.empty());
  const std::string path = PathOf(available.back());
  const httplib::Headers cesium = {{"Accept", kCesiumAccept}, {"Accept-Encoding", "gzip"}};
  const TileAnswer first = Get(path, cesium);
  ASSERT_EQ(first.status, 200);
  ASSERT_FALSE(first.etag.empty());
  std::vector<std::string> matches = {first.etag, std::string("*")};
  matches.push_back(std::string("W/").append(first.etag));
  matches.push_back(std::string("\"other\", ").append(first.etag));
  for (const std::string& match : matches) {
    httplib::Headers headers = cesium;
    headers.emplace("If-None-Match", match);
    const TileAnswer again = Get(path, headers);
    EXPECT_EQ(again.status, 304) << match;
    EXPECT_TRUE(again.body.empty()) << match;
    EXPECT_EQ(again.etag, first.etag) << match;
    EXPECT_EQ(again.cache_control, "no-cache") << match;
  }
  // The tag of another representation does not match this one.
  const TileAnswer plain =
      Get(path, {{"Accept-Encoding", "identity"}, {"If-None-Match", first.etag}});
  EXPECT_EQ(plain.status, 200);
  EXPECT_FALSE(plain.body.empty());
}

// Longitude and latitude of the store CRS point (x, y).
std::pair<double, double> LonLat(double x, double y) {
  OGRSpatialReference utm, wgs84;
  utm.importFromEPSG(32632);
  wgs84.importFromEPSG(4326);
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&utm, &wgs84));
  EXPECT_TRUE(t != nullptr && t->Transform(1, &x, &y));
  return {x, y};
}

TEST_F(TileRoutesTest, AnEditGivesTheTilesItRewroteNewTagsAndLeavesTheOthersAlone) {
  // A small fill polygon on land, away from the lake and inside one tile of level 9, added by
  // the CLI while the service runs.
  const double ex = 350000, ey = 4850000, er = 1500;
  const int level = 9;
  const auto [lon, lat] = LonLat(ex, ey);
  const double margin = 0.1;  // degrees: well beyond the polygon's 2 km
  std::vector<TileKey> touched, untouched;
  for (const TileKey& key : AvailableTiles()) {
    if (key.level != level) continue;
    const TileRect r = RectOf(key);
    if (lon > r.west && lon < r.east && lat > r.south && lat < r.north) touched.push_back(key);
    if (lon < r.west - margin || lon > r.east + margin || lat < r.south - margin ||
        lat > r.north + margin)
      untouched.push_back(key);
  }
  ASSERT_EQ(touched.size(), 1u);
  ASSERT_FALSE(untouched.empty());
  const httplib::Headers cesium = {{"Accept", kCesiumAccept}, {"Accept-Encoding", "gzip"}};
  std::map<TileKey, std::string> before;
  std::map<TileKey, std::string> body_before;
  for (const TileKey& key : touched) {
    const TileAnswer a = Get(PathOf(key), cesium);
    before[key] = a.etag;
    body_before[key] = a.body;
  }
  for (const TileKey& key : untouched) before[key] = Get(PathOf(key), cesium).etag;

  const std::string polygon = WritePolygons(dir_, "edit.geojson", {{Ngon(ex, ey, er, 12)}}, 32632);
  RunWrite(store_, "polygon add " + Quote(store_) + " " + Quote(polygon) +
                       " --surface t --mode fill --tag granite --update-tiles");

  for (const TileKey& key : touched) {
    httplib::Headers headers = cesium;
    headers.emplace("If-None-Match", before[key]);
    const TileAnswer a = Get(PathOf(key), headers);
    EXPECT_EQ(a.status, 200) << key.ToString() << ": the edit rewrote it";
    EXPECT_NE(a.etag, before[key]) << key.ToString();
    // The new tile, not the answer kept from before the edit: with every extension asked for,
    // the body is the stored tile, gzipped.
    EXPECT_NE(a.body, body_before[key]) << key.ToString();
    const std::string file = dir_.Path("after.gz");
    WriteFile(file, a.body);
    EXPECT_EQ(Gunzip(file), StoredBytes(key)) << key.ToString();
  }
  for (const TileKey& key : untouched) {
    httplib::Headers headers = cesium;
    headers.emplace("If-None-Match", before[key]);
    const TileAnswer a = Get(PathOf(key), headers);
    EXPECT_EQ(a.status, 304) << key.ToString() << ": the edit did not touch it";
    EXPECT_EQ(a.etag, before[key]) << key.ToString();
  }
}

TEST_F(TileRoutesTest, BadCoordinatesAre400AndMissingTiles404) {
  auto client = service_->Client();
  ExpectJsonError(client->Get("/surfaces/t/tiles/-1/0/0.terrain"), 400, "parameter 'z': '-1'");
  ExpectJsonError(client->Get("/surfaces/t/tiles/25/0/0.terrain"), 400, "out of range (0 to 24)");
  ExpectJsonError(client->Get("/surfaces/t/tiles/0/2/0.terrain"), 400, "'x': '2' is out of range");
  ExpectJsonError(client->Get("/surfaces/t/tiles/0/0/1.terrain"), 400, "'y': '1' is out of range");
  ExpectJsonError(client->Get("/surfaces/t/tiles/3/-4/0.terrain"), 400, "'x': '-4'");
  ExpectJsonError(client->Get("/surfaces/t/tiles/1/1/abc.terrain"), 400, "not a whole number");
  ExpectJsonError(client->Get("/surfaces/t/tiles/1/1/0.5.terrain"), 400, "not a whole number");
  ExpectJsonError(client->Get("/surfaces/t/tiles/9/99999999999999999999/0.terrain"), 400,
                  "out of range");
  // In the scheme but not in the pyramid: away from the surface, a level below the finest.
  ExpectJsonError(client->Get("/surfaces/t/tiles/10/0/0.terrain"), 404, "no tile 10/0/0");
  ExpectJsonError(client->Get("/surfaces/t/tiles/11/2130/1400.terrain"), 404,
                  "the finest level of surface 't' is 10");
  ExpectJsonError(client->Get("/surfaces/nope/tiles/0/1/0.terrain"), 404, "no surface named");
  ExpectJsonError(client->Get("/surfaces/t/tiles/0/1/0.terrain?pyramid=other"), 404,
                  "no tile pyramid 'other'");
  ExpectJsonError(client->Get("/surfaces/t/tiles/layer.json?pyramid=other"), 404,
                  "no tile pyramid 'other'");
  // The service still serves.
  const std::vector<TileKey> available = AvailableTiles();
  ASSERT_FALSE(available.empty());
  EXPECT_EQ(Get(PathOf(available.front()), {}).status, 200);
}

TEST_F(TileRoutesTest, FillerTilesAboveTheCoarsestStoredLevelLetCesiumStartAtTheRoots) {
  // The one-degree surface has no stored tile at the coarsest levels.
  int coarsest = kMaxTileLevel;
  for (const TileKey& key : StoredKeys()) coarsest = std::min(coarsest, key.level);
  ASSERT_GE(coarsest, 3);
  ASSERT_LE(coarsest, kDemoTilesMaxZoom) << "the store holds no tile";
  const nlohmann::json layer = JsonAnswer(service_->Client()->Get("/surfaces/t/tiles/layer.json"));
  ASSERT_TRUE(HasFields(layer, {"available"}));
  ASSERT_GT(layer["available"].size(), static_cast<size_t>(std::min(10, kDemoTilesMaxZoom)));
  for (int level = 0; level < coarsest; ++level) {
    const nlohmann::json whole = {{{"endX", TilesAcross(level) - 1},
                                   {"endY", TilesDown(level) - 1},
                                   {"startX", 0},
                                   {"startY", 0}}};
    EXPECT_EQ(layer["available"][level], whole) << level;
  }
  EXPECT_EQ(layer["available"][coarsest].size(), 1u);

  std::vector<std::string> files;
  const std::vector<TileKey> fillers = {{0, 0, 0}, {0, 1, 0}, {2, 1, 3}, {2, 4, 2}};
  for (const TileKey& key : fillers) {
    const TileAnswer a = Get(PathOf(key), {{"Accept", kCesiumAccept}});
    ASSERT_EQ(a.status, 200) << key.ToString() << " " << a.body;
    // Level 0 carries the metadata (the pyramid has it, Cesium asked); no filler a water mask.
    EXPECT_EQ(a.content_type, key.level == 0
                                  ? "application/vnd.quantized-mesh;extensions=octvertexnormals-"
                                    "metadata"
                                  : "application/vnd.quantized-mesh;extensions=octvertexnormals");
    EXPECT_FALSE(a.etag.empty());
    files.push_back(dir_.Path("filler_" + std::to_string(key.level) + "_" + std::to_string(key.x) +
                              "_" + std::to_string(key.y) + ".terrain"));
    WriteFile(files.back(), a.body);
  }
  const nlohmann::json npm = DecodeWithNpm(files);
  ASSERT_TRUE(HasFields(npm, files));
  for (size_t i = 0; i < files.size(); ++i) {
    const nlohmann::json& t = npm[files[i]];
    ASSERT_TRUE(HasFields(t, {"vertices", "triangles", "west", "north", "height", "normals",
                              "waterMask", "metadata"}))
        << files[i];
    // A 16 x 16 grid, flat at the pyramid's lowest height, with the ellipsoid's normals.
    EXPECT_EQ(t["vertices"], 17 * 17) << files[i];
    EXPECT_EQ(t["triangles"], 2 * 16 * 16) << files[i];
    EXPECT_EQ(t["west"].size(), 17u) << files[i];
    EXPECT_EQ(t["north"].size(), 17u) << files[i];
    for (const auto& h : t["height"]) EXPECT_EQ(h, 0) << files[i];
    EXPECT_EQ(t["normals"].size(), 2u * 17 * 17) << files[i];
    EXPECT_TRUE(t["waterMask"].is_null()) << files[i];
    EXPECT_EQ(t["metadata"].is_null(), fillers[i].level != 0) << files[i];
  }
  // The roots' metadata: the filler levels whole under each root, then (under the eastern root,
  // where the surface is) the stored tiles as layer.json lists them.
  ASSERT_TRUE(HasFields(npm[files[0]]["metadata"], {"available"}));
  ASSERT_TRUE(HasFields(npm[files[1]]["metadata"], {"available"}));
  const nlohmann::json& west = npm[files[0]]["metadata"]["available"];
  const nlohmann::json& east = npm[files[1]]["metadata"]["available"];
  ASSERT_EQ(west.size(), static_cast<size_t>(coarsest - 1));
  ASSERT_GE(east.size(), static_cast<size_t>(std::min(10, kDemoTilesMaxZoom)));
  ASSERT_FALSE(west[0].empty());
  const nlohmann::json level1_east = {{{"endX", 3}, {"endY", 1}, {"startX", 2}, {"startY", 0}}};
  EXPECT_EQ(east[0], level1_east);
  EXPECT_EQ(west[0][0]["startX"], 0);
  EXPECT_EQ(west[0][0]["endX"], 1);
  for (int level = coarsest; level <= std::min(10, kDemoTilesMaxZoom); ++level)
    EXPECT_EQ(east[level - 1], layer["available"][level]) << level;
}

TEST_F(TileRoutesTest, ConcurrentClientsGetTheSameTiles) {
  const std::vector<TileKey> keys = StoredKeys();
  const httplib::Headers cesium = {{"Accept", kCesiumAccept}, {"Accept-Encoding", "gzip"}};
  std::map<TileKey, std::string> reference;
  for (const TileKey& key : keys) reference[key] = Get(PathOf(key), cesium).body;
  constexpr int kClients = 16;
  std::vector<int> mismatches(kClients, 0);
  std::vector<std::thread> clients;
  for (int c = 0; c < kClients; ++c) {
    clients.emplace_back([&, c] {
      auto client = service_->Client();
      client->set_decompress(false);
      // Each client walks the tiles from another start, so cold and warm requests interleave.
      for (size_t i = 0; i < keys.size(); ++i) {
        const TileKey& key = keys[(i + static_cast<size_t>(c) * 7) % keys.size()];
        auto r = client->Get(PathOf(key).c_str(), cesium);
        if (!r || r->status != 200 || r->body != reference.at(key)) ++mismatches[c];
      }
    });
  }
  for (std::thread& t : clients) t.join();
  for (int c = 0; c < kClients; ++c) EXPECT_EQ(mismatches[c], 0) << "client " << c;
}

TEST(TileRoutesWithoutTilesTest, ASurfaceWithoutTilesSaysHowToBuildThem) {
  TempDir dir;
  const std::string store = StoreTarget(dir, "s.tinbase");
  ASSERT_NO_FATAL_FAILURE(CopyDemoStore(store));
  service::ServiceOptions options;
  options.store_path = store;
  TestService service(options);
  ASSERT_TRUE(service.running());
  ExpectJsonError(service.Client()->Get("/surfaces/t/tiles/layer.json"), 404,
                  "surface 't' has no tiles (build them with tinbase tiles build)");
  ExpectJsonError(service.Client()->Get("/surfaces/t/tiles/0/1/0.terrain"), 404, "has no tiles");
}

}  // namespace
}  // namespace tinbase::testing
