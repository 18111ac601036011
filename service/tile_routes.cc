// The terrain tiles of a surface's stored pyramid, as CesiumJS's CesiumTerrainProvider asks for
// them: layer.json, then z/x/y.terrain with the extensions negotiated through Accept, gzipped
// when the client accepts it, with an entity tag from the stored tile (a tile an edit rewrote
// gets a new one) so a repeated request is a cheap 304; the levels above the pyramid's coarsest
// stored one answered with filler tiles (filler_tiles.h). docs/api.md, "Tiles".
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"
#include "db/tiles/tile_pyramid.h"
#include "service/body_cache.h"
#include "service/entity_tag.h"
#include "service/filler_tiles.h"
#include "service/gzip_body.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"
#include "service/terrain_negotiation.h"
#include "service/terrain_pyramids.h"
#include "service/terrain_tile.h"

namespace tinbase::service {

namespace {

// Answers made from stored tiles, by store, tile and entity tag (which changes with the tile):
// the bytes a warm request sends without decoding, encoding or deflating again. A fixed budget;
// a tile is a few to a few hundred kilobytes.
BodyCache& TileBodies() {
  static BodyCache cache(size_t{64} << 20);
  return cache;
}

// Tiles and layer.json are static data to a Cesium app on another origin; let it read them.
void AllowAnyOrigin(httplib::Response& res) { res.set_header("Access-Control-Allow-Origin", "*"); }

// z/x/y from the path: z within the tiling scheme's levels, x and y within level z's tiles
// (y counted from the south, TMS); InvalidArgument naming the part otherwise.
Result<TileKey> TileKeyFromPath(const httplib::Request& req) {
  TileKey key;
  TB_ASSIGN_OR_RETURN(const int64_t z, IntegerPathPart(req, 2, "z", 0, kMaxTileLevel));
  key.level = static_cast<int>(z);
  TB_ASSIGN_OR_RETURN(key.x, IntegerPathPart(req, 3, "x", 0, TilesAcross(key.level) - 1));
  TB_ASSIGN_OR_RETURN(key.y, IntegerPathPart(req, 4, "y", 0, TilesDown(key.level) - 1));
  return key;
}

void GetLayer(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  auto snapshot = ReadSnapshot::Begin(lease->store());
  if (!snapshot.ok()) return ReplyStatus(res, snapshot.status());
  auto surface = SurfaceFromPath(lease->store(), req);
  if (!surface.ok()) return ReplyStatus(res, surface.status());
  auto pyramid = RequestedPyramid(lease->store(), *surface, req);
  if (!pyramid.ok()) return ReplyStatus(res, pyramid.status());
  auto layer = LayerJson(lease->store(), *surface);
  if (!layer.ok()) return ReplyStatus(res, layer.status());
  auto coarsest = CoarsestStoredLevel(lease->store(), context.stores().path(), *pyramid);
  if (!coarsest.ok()) return ReplyStatus(res, coarsest.status());
  AddFillerAvailability(*layer, *coarsest);
  const std::string text = layer->dump();
  AllowAnyOrigin(res);
  res.set_header("Vary", "Accept-Encoding");
  // Weak: the HTTP layer may compress the JSON, and every coding of it is the same document.
  if (ReplyNotModified(req, res, "W/" + EntityTag(text, "layer"), kRevalidate)) return;
  res.set_content(text, "application/json");
}

// The bytes a tile is made from and the extensions they hold: the stored tile, else a filler
// tile (filler_tiles.h) when the level is one Cesium needs filled, else nullopt (404).
Result<std::optional<std::pair<std::string, TileExtensions>>> TileSource(
    ServiceContext& context, Store& store, const SurfaceInfo& surface,
    const TilePyramidInfo& pyramid, const TileKey& key, const TileExtensions& keep) {
  using Source = std::optional<std::pair<std::string, TileExtensions>>;
  TB_ASSIGN_OR_RETURN(auto tile, TileStore(store.db()).Tile(surface.id, key));
  if (tile) {
    TB_ASSIGN_OR_RETURN(const TileExtensions built, ParseTileExtensions(pyramid.extensions));
    return Source({std::string(tile->first.begin(), tile->first.end()), built});
  }
  TB_ASSIGN_OR_RETURN(const int coarsest,
                      CoarsestStoredLevel(store, context.stores().path(), pyramid));
  if (!IsFillerLevel(key.level, coarsest)) return Source();
  TileExtensions has;
  has.normals = keep.normals;
  std::optional<std::string> metadata;
  if (keep.metadata && key.level == 0) {
    TB_ASSIGN_OR_RETURN(const std::set<TileKey> stored, TileStore(store.db()).Keys(surface.id));
    metadata = FillerMetadata(key, stored, coarsest);
    has.metadata = true;
  }
  TB_ASSIGN_OR_RETURN(const QuantizedMesh mesh, FillerTile(key, pyramid, keep.normals, metadata));
  TB_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, EncodeQuantizedMesh(mesh));
  return Source({std::string(bytes.begin(), bytes.end()), has});
}

// The body of a tile answer: `stored` with only `sent` of its extensions, gzipped when asked.
Result<std::string> MakeTileBody(const std::string& stored, const TileExtensions& has,
                                 const TileExtensions& sent, bool gzip, const std::string& source) {
  TB_ASSIGN_OR_RETURN(std::string body, TileKeeping(stored, has, sent, source));
  if (!gzip) return body;
  return Gzip(body);
}

void GetTile(ServiceContext& context, const httplib::Request& req, httplib::Response& res) {
  auto key = TileKeyFromPath(req);
  if (!key.ok()) return ReplyStatus(res, key.status());
  auto lease = context.stores().Reader();
  if (!lease.ok()) return ReplyStatus(res, lease.status());
  // One snapshot: the pyramid's extensions and the tile's bytes from the same build.
  auto snapshot = ReadSnapshot::Begin(lease->store());
  if (!snapshot.ok()) return ReplyStatus(res, snapshot.status());
  auto surface = SurfaceFromPath(lease->store(), req);
  if (!surface.ok()) return ReplyStatus(res, surface.status());
  auto pyramid = RequestedPyramid(lease->store(), *surface, req);
  if (!pyramid.ok()) return ReplyStatus(res, pyramid.status());
  if (key->level > pyramid->max_zoom)
    return ReplyError(res, 404, "no_tile",
                      "no tile " + key->ToString() + ": the finest level of surface '" +
                          surface->name + "' is " + std::to_string(pyramid->max_zoom));
  auto built = ParseTileExtensions(pyramid->extensions);
  if (!built.ok()) return ReplyStatus(res, built.status());
  const TileExtensions keep = CommonTileExtensions(*built, RequestedTileExtensions(req));
  auto source = TileSource(context, lease->store(), *surface, *pyramid, *key, keep);
  if (!source.ok()) return ReplyStatus(res, source.status());
  if (!*source)
    return ReplyError(res, 404, "no_tile",
                      "no tile " + key->ToString() + " in the pyramid of surface '" +
                          surface->name + "' (layer.json lists the tiles there are)");
  const std::string& stored = (*source)->first;
  const TileExtensions& has = (*source)->second;
  const bool gzip = AcceptsGzip(req);
  AllowAnyOrigin(res);
  // The answer depends on both, so a shared cache must key on them.
  res.set_header("Vary", "Accept, Accept-Encoding");
  const TileExtensions sent = CommonTileExtensions(has, keep);
  const std::string variant = TileExtensionsCode(sent) + (gzip ? ".gz" : "");
  const std::string tag = EntityTag(stored, variant);
  if (ReplyNotModified(req, res, tag, kRevalidate)) return;
  const std::string cache_key =
      context.stores().path() + "\n" + surface->name + "\n" + key->ToString() + "\n" + tag;
  std::shared_ptr<const std::string> body = TileBodies().Find(cache_key);
  if (body == nullptr) {
    auto made = MakeTileBody(stored, has, sent, gzip, "tile " + key->ToString());
    if (!made.ok()) return ReplyStatus(res, made.status());
    body = std::make_shared<const std::string>(std::move(*made));
    TileBodies().Put(cache_key, body);
  }
  if (gzip) res.set_header("Content-Encoding", "gzip");
  res.set_content(*body, TerrainContentType(sent));
}

}  // namespace

void RegisterTileRoutes(httplib::Server& server, ServiceContext& context) {
  server.Get(R"(/surfaces/([^/]+)/tiles/layer\.json)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetLayer(context, req, res);
             });
  server.Get(R"(/surfaces/([^/]+)/tiles/([^/]+)/([^/]+)/([^/]+)\.terrain)",
             [&context](const httplib::Request& req, httplib::Response& res) {
               GetTile(context, req, res);
             });
}

}  // namespace tinbase::service
