// PointCloud: the points a LAS or XYZ reader returns, and the choice of classes to keep.
//
// Coordinates are already scaled (LAS integers times scale plus offset) and in the file's CRS,
// which travels with the cloud when the file names one. Plain data; not synchronised.
#pragma once

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/crs.h"

namespace tinbase {

// ASPRS LAS class "ground".
inline constexpr uint8_t kLasClassGround = 2;

struct CloudPoint {
  double x = 0;
  double y = 0;
  double z = 0;
  uint8_t classification = 0;  // ASPRS class; 0 ("never classified") for XYZ files
  uint8_t return_number = 0;   // 1-based in LAS; 0 when the file does not say
};

struct PointCloud {
  std::vector<CloudPoint> points;
  std::optional<Crs> crs;  // nullopt when the file names none
};

// Which classes a caller keeps, and what the default chose (for reports).
struct ClassSelection {
  std::set<uint8_t> classes;  // empty = every point
  std::string description;    // "classes 2", "ground (class 2)", "all points (no class 2)"

  bool Keeps(uint8_t classification) const {
    return classes.empty() || classes.count(classification) > 0;
  }
};

// The classes to keep: `requested` when given (non-empty); otherwise ground (class 2) when any
// point of `cloud` has class 2, else every point.
ClassSelection ChooseClasses(const PointCloud& cloud, const std::set<uint8_t>& requested);

// The points of `cloud` whose class is in `selection` (all points when it is empty), in order.
std::vector<CloudPoint> SelectPoints(const PointCloud& cloud, const ClassSelection& selection);

}  // namespace tinbase
