// The geographic tiling scheme of Cesium's terrain (EPSG:4326, TMS y): level 0 is two tiles,
// west and east of the prime meridian, each 180 degrees square; each level splits every tile
// in four; y counts from the south.
//
// Tiles are addressed by TileKey; TileRect gives a tile's bounds in degrees. The bounds are
// computed from the key alone (exact binary fractions of 180), so two neighbouring tiles agree
// bit for bit on their shared edge, which crack-free cutting relies on. Plain functions.
#pragma once

#include <compare>
#include <cstdint>
#include <string>

namespace tinbase {

inline constexpr int kMaxTileLevel = 24;

struct TileKey {
  int level = 0;
  int64_t x = 0;
  int64_t y = 0;  // from the south (TMS)
  // NOLINTNEXTLINE(modernize-use-nullptr): a false finding on a defaulted <=>
  friend auto operator<=>(const TileKey&, const TileKey&) = default;
  std::string ToString() const;  // "level/x/y"
};

struct TileRect {
  double west = 0, south = 0, east = 0, north = 0;  // degrees
};

// Tiles across and down at `level`: 2^(level+1) by 2^level.
int64_t TilesAcross(int level);
int64_t TilesDown(int level);
// Size of a tile's side at `level`, degrees.
double TileDegrees(int level);
TileRect RectOf(const TileKey& key);

// The inclusive range of tiles at `level` whose closed rectangles meet the box (degrees).
struct TileRange {
  int level = 0;
  int64_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // empty when x1 < x0
  bool empty() const { return x1 < x0 || y1 < y0; }
  int64_t count() const { return empty() ? 0 : (x1 - x0 + 1) * (y1 - y0 + 1); }
};
TileRange TilesMeeting(int level, double west, double south, double east, double north);

}  // namespace tinbase
