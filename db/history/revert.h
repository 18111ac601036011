// Revert: undoing committed edit transactions, and a surface as it was after a transaction
// (docs/design.md, "Undo and history").
//
// Both are one net inverse read from the feature versions (db/history/feature_versions.h): each
// feature the undone transactions touched goes back to its last version before the first of them
// (or goes, if it had none), and that inverse is applied locally by the editor of the features'
// family (db/history/feature_inverse.h) as a new transaction. Nothing is replayed, so the cost is
// that of the edit being undone. A plan is made and applied inside one write transaction, so no
// other writer can come between the conflict check and the edit. Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/history/feature_inverse.h"
#include "db/polygon_editor.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

struct RevertPlan {
  SurfaceInfo surface;
  std::vector<int64_t> transactions;  // undone, oldest first (empty for an as-of plan)
  // Features that go: present now, absent at the point the plan goes back to. A feature changed
  // in place (present at both, under one id) is in both lists.
  std::vector<FeatureVersion> remove;   // their current versions
  std::vector<FeatureVersion> restore;  // the versions that come back
  // The transactions whose mesh images take the surface back (db/history/exact_revert.h),
  // oldest first: the undone ones, or for an as-of plan every change of the surface after it.
  std::vector<int64_t> image_transactions;
};

struct RevertOptions {
  // Also revert every later transaction that touched a feature of the reverted ones (and so on),
  // all in the one new transaction.
  bool cascade = false;
  // Called inside the revert's write transaction once everything is written, just before the
  // commit, with the revert's (last) transaction (PolygonAddOptions::before_commit: `revert
  // --update-tiles` brings the tile pyramids up to date there, in the same transaction). An error
  // rolls the revert back and is its error. Empty: not called.
  BeforeCommit before_commit;
};

struct RevertReport {
  std::vector<int64_t> transactions;  // the new transactions (one per family and pass)
  std::vector<int64_t> reverted;      // the transactions undone, oldest first
  std::vector<int64_t> removed_features;
  std::vector<int64_t> restored_features;
  int64_t removed = 0;  // triangles
  int64_t added = 0;
  // Whether the exact mesh came back from the mesh images; when not, not_exact says why and the
  // features were put back by re-refining their regions locally.
  bool exact = false;
  std::string not_exact;
};

// The plan that undoes transaction `tx`. NotFound "no transaction 12"; InvalidArgument when tx
// wrote no feature version (a build, a DEM import: "transaction 3 (build) is not an edit of
// features"); Conflict naming the later transaction and the feature when a feature of tx is no
// longer as tx left it (a later edit changed it and was not reverted) and options.cascade is off.
// REQUIRES: inside a WriteTransaction (the plan holds only until another writer could come).
Result<RevertPlan> PlanRevert(Store& store, int64_t tx, const RevertOptions& options);

// The plan that takes `surface` back to the state after transaction `tx`. InvalidArgument for a
// transaction after the store's last ("from the future"), before the surface was built, or when a
// change after tx that is not a feature edit (a rebuild, new DEM data) came between.
Result<RevertPlan> PlanAsOf(Store& store, const SurfaceInfo& surface, int64_t tx);

// Applies `plan`, each family of features with its applier, every change row with `action`.
// REQUIRES: inside the WriteTransaction the plan was made in; the caller commits or drops it.
Result<RevertReport> ApplyRevertPlan(Store& store, const RevertPlan& plan,
                                     const std::string& action);

// Plans and applies the revert of `tx` in one write transaction and commits it (after
// options.before_commit); the store is unchanged on every error (those of PlanRevert, the
// editor's and before_commit's).
Result<RevertReport> RevertTransaction(Store& store, int64_t tx, const RevertOptions& options);

}  // namespace tinbase
