// The surface the export tests write: a 12 x 9 grid in UTM 32N (EPSG:32632) with
// irrational-looking coordinates (so exact printing matters), a band of invisible triangles and
// two tags. Header-only.
#pragma once

#include <cmath>

#include "tests/support/grid_tin.h"

namespace tinbase::testing {

inline Tin SampleExportTin() {
  Tin tin = MakeGridTin(
      12, 9, 30.123456789012345, 612345.678901234, 5171234.56789012, [](double x, double y) {
        return 1000.0 + std::sin(x / 77.7) * 123.456789 + std::cos(y / 51.3) / 3.0;
      });
  tin.tags = {"granite", "schist"};
  for (size_t t = 0; t < tin.triangles.size(); ++t) {
    if (t % 7 == 3 || (t >= 40 && t < 70)) tin.triangles[t].visible = false;
    if (t % 5 == 0) tin.triangles[t].tag = static_cast<int32_t>((t / 5) % 2);
  }
  return tin;
}

}  // namespace tinbase::testing
