// ExactRevert: undoing edit transactions by writing back the mesh rows they replaced, so the
// surface returns to exactly the mesh it had (docs/design.md, "Undo and history").
//
// Each edit keeps the before-image of its mesh rows and a digest of how it left them
// (db/history/mesh_image.h). The images of the transactions being undone are applied newest
// first to the rows as they are now, in memory: each must find its rows as its transaction left
// them (the digest), else a later edit replaced them and the revert falls back to the local
// re-refinement (db/history/revert.h) and says why. When every image fits, the result is written
// in one step, with the features of the plan put back from their versions, as one new transaction
// that keeps its own image (so reverting the revert is exact too).
// Thread-safety: through one Store.
#pragma once

#include <string>

#include "core/base/status.h"
#include "db/history/feature_inverse.h"
#include "db/history/revert.h"
#include "db/store.h"

namespace tinbase {

struct ExactRevertOutcome {
  bool exact = false;
  std::string not_exact;  // why the images could not be used (when !exact)
  InverseResult done;     // the new transaction (when exact)
};

// Applies `plan` from the mesh images of plan.image_transactions when they all fit; otherwise
// changes nothing and says why in not_exact. Errors of the store, and Corruption for an image
// that does not decode. REQUIRES: inside the WriteTransaction the plan was made in.
Result<ExactRevertOutcome> TryExactRevert(Store& store, const RevertPlan& plan,
                                          const std::string& action);

}  // namespace tinbase
