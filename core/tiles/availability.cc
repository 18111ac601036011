// Tile availability: see availability.h.
#include "core/tiles/availability.h"

#include <map>

namespace tinbase {

std::vector<TileRectangle> RectanglesOf(const std::set<TileKey>& tiles, int level) {
  // Runs of x per row, in row order.
  std::map<int64_t, std::vector<std::pair<int64_t, int64_t>>> runs;
  for (const TileKey& k : tiles) {
    if (k.level != level) continue;
    auto& row = runs[k.y];
    if (!row.empty() && row.back().second + 1 == k.x) {
      row.back().second = k.x;
    } else {
      row.emplace_back(k.x, k.x);
    }
  }
  // A run extends the rectangle that ended on the row below with the same x span.
  std::vector<TileRectangle> done;
  std::map<std::pair<int64_t, int64_t>, TileRectangle> open;
  for (const auto& [y, row] : runs) {
    std::map<std::pair<int64_t, int64_t>, TileRectangle> next;
    for (const auto& span : row) {
      auto it = open.find(span);
      if (it != open.end() && it->second.end_y + 1 == y) {
        TileRectangle r = it->second;
        r.end_y = y;
        next.emplace(span, r);
        open.erase(it);
      } else {
        next.emplace(span, TileRectangle{span.first, y, span.second, y});
      }
    }
    for (const auto& [span, r] : open) done.push_back(r);
    open = std::move(next);
  }
  for (const auto& [span, r] : open) done.push_back(r);
  return done;
}

nlohmann::json AvailableJson(const std::set<TileKey>& tiles, int first_level, int last_level) {
  nlohmann::json levels = nlohmann::json::array();
  for (int level = first_level; level <= last_level; ++level) {
    nlohmann::json list = nlohmann::json::array();
    for (const TileRectangle& r : RectanglesOf(tiles, level))
      list.push_back(
          {{"startX", r.start_x}, {"startY", r.start_y}, {"endX", r.end_x}, {"endY", r.end_y}});
    levels.push_back(std::move(list));
  }
  return levels;
}

std::set<TileKey> SubtreeOf(const std::set<TileKey>& tiles, const TileKey& root, int depth) {
  std::set<TileKey> out;
  for (const TileKey& k : tiles) {
    const int down = k.level - root.level;
    if (down <= 0 || down > depth) continue;
    if ((k.x >> down) == root.x && (k.y >> down) == root.y) out.insert(k);
  }
  return out;
}

}  // namespace tinbase
