// Filler tiles: what Cesium needs above a pyramid's coarsest stored level.
//
// A pyramid holds no tile at the levels where its surface is too small to show (a one-degree
// surface has none at levels 0-2). CesiumJS cannot start without the two root tiles: it marks a
// tile that layer.json does not list as failed and upsamples its parent instead, and a root has
// no parent, so the globe never draws. The service therefore lists every tile of those levels
// (level 0 always) as available and answers them with a flat tile at the pyramid's lowest height:
// a 16 x 16 grid of cells on the ellipsoid, so even a hemisphere-wide root bends with the Earth.
// Cesium upsamples the missing tiles of finer levels from these as usual. Nothing is stored.
// Thread-safety: pure functions, plus a cache of each pyramid's coarsest stored level behind a
// mutex.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "core/base/status.h"
#include "core/tiles/quantized_mesh.h"
#include "core/tiles/tiling_scheme.h"
#include "db/store.h"
#include "db/tiles/tile_pyramid.h"

namespace tinbase::service {

// The coarsest level holding a stored tile of `pyramid` (max_zoom + 1 when none does), cached
// per store file, surface and pyramid state.
Result<int> CoarsestStoredLevel(Store& store, const std::string& store_path,
                                const TilePyramidInfo& pyramid);

// Whether `key` is a filler tile of a pyramid whose coarsest stored level is `coarsest`: it
// lies above that level, or on level 0. (The caller serves a stored tile first when there is one.)
bool IsFillerLevel(int level, int coarsest);

// The filler tile `key`: flat at the pyramid's lowest height, with vertex normals when
// `normals` (the ellipsoid's), the metadata extension when `metadata` is given, no water mask.
Result<QuantizedMesh> FillerTile(const TileKey& key, const TilePyramidInfo& pyramid, bool normals,
                                 const std::optional<std::string>& metadata);

// The metadata extension of a level-0 filler tile, for a pyramid built with metadata: the
// availability of the ten levels below it (as layer.json's metadataAvailability says), the filler
// levels whole and the others as `stored` holds them. Cesium learns which tiles exist from the
// level-0 tiles of such a pyramid. REQUIRES: root.level == 0.
std::string FillerMetadata(const TileKey& root, const std::set<TileKey>& stored, int coarsest);

// layer.json with the filler levels listed whole in `available`.
void AddFillerAvailability(nlohmann::json& layer, int coarsest);

}  // namespace tinbase::service
