// Fuzzes the feature geometry decoders (core/vector/feature_wkb.h), which read
// `features.geometry` back from a store that may be damaged: any bytes end in polygons or lines,
// or an error; whatever is decoded encodes again and decodes to the same coordinates, to the bit.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/vector/feature_wkb.h"

namespace {

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool SameRing(const std::vector<tinbase::Point2>& a, const std::vector<tinbase::Point2>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!SameBits(a[i].x, b[i].x) || !SameBits(a[i].y, b[i].y)) return false;
  return true;
}

void CheckPolygons(const std::vector<uint8_t>& wkb) {
  auto polygons = tinbase::PolygonsFromWkb(wkb);
  if (!polygons.ok()) return;
  auto again = tinbase::PolygonsFromWkb(tinbase::PolygonsToWkb(*polygons));
  if (!again.ok() || again->size() != polygons->size()) std::abort();
  for (size_t p = 0; p < polygons->size(); ++p) {
    const tinbase::Polygon &a = (*polygons)[p], &b = (*again)[p];
    if (!SameRing(a.shell, b.shell) || a.holes.size() != b.holes.size()) std::abort();
    for (size_t h = 0; h < a.holes.size(); ++h)
      if (!SameRing(a.holes[h], b.holes[h])) std::abort();
  }
}

void CheckLines(const std::vector<uint8_t>& wkb) {
  auto lines = tinbase::LinesFromWkb(wkb);
  if (!lines.ok()) return;
  auto again = tinbase::LinesFromWkb(tinbase::LinesToWkb(*lines));
  if (!again.ok() || again->size() != lines->size()) std::abort();
  for (size_t l = 0; l < lines->size(); ++l)
    if (!SameRing((*lines)[l], (*again)[l])) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> wkb(data, data + size);
  CheckPolygons(wkb);
  CheckLines(wkb);
  return 0;
}
