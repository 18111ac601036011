// The terrain tiles of a surface's stored pyramid, as CesiumJS's CesiumTerrainProvider asks for
// them: layer.json, then z/x/y.terrain with the extensions negotiated through Accept, gzipped
// when the client accepts it, with an entity tag from the stored tile (a tile an edit rewrote
// gets a new one) so a repeated request is a cheap 304. docs/api.md, "Tiles".
#include <string>

#include "core/tiles/tiling_scheme.h"
#include "db/tiles/tile_pyramid.h"
#include "service/entity_tag.h"
#include "service/gzip_body.h"
#include "service/json_reply.h"
#include "service/request_params.h"
#include "service/routes.h"
#include "service/terrain_negotiation.h"
#include "service/terrain_pyramids.h"
#include "service/terrain_tile.h"

namespace tinbase::service {

namespace {

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
  const std::string text = layer->dump();
  AllowAnyOrigin(res);
  res.set_header("Vary", "Accept-Encoding");
  // Weak: the HTTP layer may compress the JSON, and every coding of it is the same document.
  if (ReplyNotModified(req, res, "W/" + EntityTag(text, "layer"), kRevalidate)) return;
  res.set_content(text, "application/json");
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
  auto tile = TileStore(lease->store().db()).Tile(surface->id, *key);
  if (!tile.ok()) return ReplyStatus(res, tile.status());
  if (!*tile)
    return ReplyError(res, 404, "no_tile",
                      "no tile " + key->ToString() + " in the pyramid of surface '" +
                          surface->name + "' (layer.json lists the tiles there are)");
  auto built = ParseTileExtensions(pyramid->extensions);
  if (!built.ok()) return ReplyStatus(res, built.status());
  const TileExtensions keep = CommonTileExtensions(*built, RequestedTileExtensions(req));
  const bool gzip = AcceptsGzip(req);
  const std::string stored((*tile)->first.begin(), (*tile)->first.end());
  AllowAnyOrigin(res);
  // The answer depends on both, so a shared cache must key on them.
  res.set_header("Vary", "Accept, Accept-Encoding");
  const std::string variant = TileExtensionsCode(keep) + (gzip ? ".gz" : "");
  if (ReplyNotModified(req, res, EntityTag(stored, variant), kRevalidate)) return;
  auto body = TileKeeping(stored, *built, keep, "tile " + key->ToString());
  if (!body.ok()) return ReplyStatus(res, body.status());
  if (gzip) {
    auto zipped = Gzip(*body);
    if (!zipped.ok()) return ReplyStatus(res, zipped.status());
    *body = std::move(*zipped);
    res.set_header("Content-Encoding", "gzip");
  }
  res.set_content(*body, TerrainContentType(keep));
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
