// Which quantized-mesh extensions a terrain tile is sent with, negotiated as CesiumJS asks:
// its CesiumTerrainProvider requests tiles with
//   Accept: application/vnd.quantized-mesh;extensions=octvertexnormals-watermask-metadata,
//           application/octet-stream;q=0.9,*/*;q=0.01
// naming, joined by '-', the extensions it wants among those layer.json lists (no parameter:
// none). A tile is sent with the extensions both the pyramid has and the client asked for, and
// the others are taken out of it (terrain_tile.h), since a client that did not ask may not expect
// them. Thread-safety: pure functions.
#pragma once

#include <httplib.h>

#include <string>

#include "db/tiles/tile_pyramid.h"

namespace tinbase::service {

// The extensions named in the request's Accept by a quantized-mesh media range with q > 0;
// unknown names are ignored (a client may know extensions this server has none of).
TileExtensions RequestedTileExtensions(const httplib::Request& req);

// Those in both.
TileExtensions CommonTileExtensions(const TileExtensions& a, const TileExtensions& b);

// "application/vnd.quantized-mesh;extensions=octvertexnormals-metadata", or without the parameter
// when `sent` has none.
std::string TerrainContentType(const TileExtensions& sent);

// A short code of the set for entity tags and logs: "n", "w", "m" for those set, in that order
// ("nwm"), "0" for none.
std::string TileExtensionsCode(const TileExtensions& set);

}  // namespace tinbase::service
