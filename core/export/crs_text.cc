#include "core/export/crs_text.h"

#include <cpl_conv.h>
#include <ogr_spatialref.h>

namespace tinbase {

std::string OneLineWkt(const Crs& crs) {
  char* wkt = nullptr;
  const char* options[] = {"FORMAT=WKT2_2018", "MULTILINE=NO", nullptr};
  crs.ogr().exportToWkt(&wkt, options);
  std::string out = wkt != nullptr ? wkt : "";
  CPLFree(wkt);
  return out;
}

}  // namespace tinbase
