// Geographic tiling scheme: see tiling_scheme.h.
#include "core/tiles/tiling_scheme.h"

#include <algorithm>
#include <cmath>

namespace tinbase {

std::string TileKey::ToString() const {
  return std::to_string(level) + "/" + std::to_string(x) + "/" + std::to_string(y);
}

int64_t TilesAcross(int level) { return int64_t{2} << level; }
int64_t TilesDown(int level) { return int64_t{1} << level; }
double TileDegrees(int level) { return std::ldexp(180.0, -level); }

TileRect RectOf(const TileKey& key) {
  const double size = TileDegrees(key.level);
  TileRect r;
  r.west = -180.0 + static_cast<double>(key.x) * size;
  r.east = -180.0 + static_cast<double>(key.x + 1) * size;
  r.south = -90.0 + static_cast<double>(key.y) * size;
  r.north = -90.0 + static_cast<double>(key.y + 1) * size;
  return r;
}

TileRange TilesMeeting(int level, double west, double south, double east, double north) {
  TileRange range;
  range.level = level;
  if (!(west <= east && south <= north)) return range;
  const double size = TileDegrees(level);
  const auto column = [&](double lon) {
    return std::clamp<int64_t>(static_cast<int64_t>(std::floor((lon + 180.0) / size)), 0,
                               TilesAcross(level) - 1);
  };
  const auto row = [&](double lat) {
    return std::clamp<int64_t>(static_cast<int64_t>(std::floor((lat + 90.0) / size)), 0,
                               TilesDown(level) - 1);
  };
  range.x0 = column(west);
  range.x1 = column(east);
  range.y0 = row(south);
  range.y1 = row(north);
  // A box that ends exactly on a tile edge also meets the tile before it (closed rectangles).
  if (range.x0 > 0 && RectOf({level, range.x0, 0}).west == west) --range.x0;
  if (range.y0 > 0 && RectOf({level, 0, range.y0}).south == south) --range.y0;
  return range;
}

}  // namespace tinbase
