// LandXML import into a store: a LandXmlSurface read from a file (core/import/landxml_reader.h)
// becomes a new surface with its features and constraint rows, in one write transaction that is
// committed only when the new surface passes the full integrity check (db/integrity_check.h), so
// a rejected file leaves the store as it was. Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/export/landxml_surface.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct LandXmlImportOptions {
  std::string surface;  // the new surface's name; empty: the file's
  // Drape on this DEM of the store (its nodata hides triangles; the tolerance applies). Default:
  // the file's tb:dem when the store has a DEM of that name, else none.
  std::optional<std::string> dem;
};

struct LandXmlImportReport {
  SurfaceInfo surface;
  int64_t vertices = 0;
  int64_t triangles = 0;
  int64_t features = 0;
  int64_t constraints = 0;
  int64_t tx = 0;  // the `changes` row
};

// Writes `file` as a new surface. The store takes the file's CRS when it has none; a file in
// another CRS than the store's is rejected. InvalidArgument naming the problem when: the name is
// missing or taken (Conflict), the CRS differs or does not parse, two points share x and y, a
// feature's attributes are not a JSON object, or the new surface fails the integrity check (the
// message names the first problem, e.g. a triangle hidden by no feature). NotFound for an
// unknown DEM.
Result<LandXmlImportReport> ImportLandXml(Store& store, const LandXmlSurface& file,
                                          const LandXmlImportOptions& options);

}  // namespace tinbase
