// A stored terrain tile as one client gets it: with only the extensions negotiated for it
// (terrain_negotiation.h). A tile whose pyramid has no extension the client refused is sent as
// stored, byte for byte; otherwise it is decoded, the refused extensions are dropped, and it is
// encoded again with tinbase's quantized-mesh codec, which writes the header, vertices, indices
// and edge lists exactly as they were read. Thread-safety: pure function.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase::service {

// `stored` (a tile of a pyramid built with `built`) with only the extensions of `keep`.
// Corruption naming `source` when the stored bytes do not decode (the store wrote them).
Result<std::string> TileKeeping(const std::string& stored, const TileExtensions& built,
                                const TileExtensions& keep, const std::string& source);

}  // namespace tinbase::service
