// ContourImport: a blocked DEM built from contour lines (paper 000's Singapore DEM), stored like
// any imported raster.
//
// Reads the lines of any OGR source (core/vector/polygon_source.h) in the store's CRS (the
// source's own when the store has none yet, which the DEM then gives the store), takes each
// line's elevation from a numeric field, builds the DEM with core/raster/contour_dem.h and
// imports it through DemStore (via an in-memory GeoTIFF, /vsimem, so the one import path also
// builds blocks and overviews). Everything is read and checked before the one write
// transaction, so on any error nothing is written. Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <string>

#include "core/base/status.h"
#include "core/raster/contour_dem.h"
#include "db/dem_store.h"
#include "db/store.h"

namespace tinbase {

struct ContourImportOptions {
  std::string path;      // any OGR vector source of LineString / MultiLineString features
  std::string layer;     // empty: the source's only layer
  std::string field;     // numeric field holding each line's elevation
  double cell = 0;       // cell size in the units of the CRS the DEM is made in; > 0
  std::string name;      // name of the new DEM
  int block_size = 256;  // as DemImportOptions::block_size
};

struct ContourImportReport {
  ContourDemReport contours;
  DemImportReport dem;
};

// Creates the DEM `options.name` from the contours of `options.path`. Errors, each naming the
// file, feature or DEM: Conflict when a DEM of that name exists; InvalidArgument for an empty
// name, a bad cell size, a missing field ("c.gpkg: no field 'ELEV' (fields: ...)"), a value that
// is empty or not a number ("c.gpkg feature 4: field 'ELEV' is not a number ('abc')"), a source
// without CRS when the store has none, contours that cross (naming both and the point); the
// errors of ReadLineFeatures and DemStore::Import. REQUIRES: no write transaction is open.
Result<ContourImportReport> ImportContourDem(Store& store, const ContourImportOptions& options);

}  // namespace tinbase
