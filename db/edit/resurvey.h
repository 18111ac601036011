// Resurvey: new or corrected DEM sheets imported under the surfaces built on the DEM, each
// surface re-triangulated locally where its triangles no longer meet the new cells
// (`dem import --update-surfaces`; docs/design.md, "New survey data under existing surfaces").
//
// The import and every surface's update are one transaction (DemImportOptions::under_surfaces).
// For each surface on the DEM: the new cells of the blocks written are compared with the surface
// as stored; a cell it misses by more than its tolerance (a cell changed by more than the
// tolerance under a vertex always is one) is flagged, with the cells around it; the triangles over
// flagged cells seed the update engine's conflict region (LocalEdit::seed), their vertices take
// the new DEM's z (LocalEdit::resample) and the engine re-triangulates and refines R with the
// new cells as for any edit. Constraints, features, tags and visibility stay: paint is recomputed
// over the blocks written (a cell may have become nodata). One `changes` row per surface
// (action "dem resurvey"). Thread-safety: one Store.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/dem_store.h"
#include "db/store.h"

namespace tinbase {

struct SurfaceResurvey {
  std::string surface;
  int64_t tx = 0;            // its `changes` row
  int64_t cells_missed = 0;  // new cells the surface missed by more than its tolerance
  int64_t seeded = 0;        // triangles over them (and their neighbourhood of one cell)
  int64_t removed = 0;       // triangles
  int64_t added = 0;
  int64_t refinement_points = 0;
  bool whole_surface = false;  // R became the whole surface
};

struct ResurveyReport {
  DemImportReport import;
  std::vector<SurfaceResurvey> surfaces;  // of the DEM, in id order
};

// Imports `files` as DemStore::Import does into the DEM options.name (options.under_surfaces is
// set here) and brings every surface built on it up to date, all in one transaction. Sheets may
// grow the DEM's grid: the cells beyond a surface are stored, and the surface keeps its hull (it
// does not grow locally). Errors of Import; errors of the update engine (Corruption, DEM read
// errors); InvalidArgument naming the surface and the cell when a cell the surface misses lies
// within a cell of the surface's outer edge (its boundary, which a local edit cannot refine).
// The store is unchanged on every error.
Result<ResurveyReport> ImportUnderSurfaces(Store& store, const std::vector<std::string>& files,
                                           DemImportOptions options);

}  // namespace tinbase
