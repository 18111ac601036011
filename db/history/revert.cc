#include "db/history/revert.h"

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <utility>

#include "db/change_log.h"
#include "db/history/exact_revert.h"

namespace tinbase {

namespace {

std::string Described(const Change& c) {
  return std::string("transaction ") + std::to_string(c.tx) + " (" + c.action + ")";
}

// Whether two versions of one feature describe the same feature row (both absent counts too).
bool SameState(const FeatureVersion& a, const FeatureVersion& b) {
  if (a.present != b.present) return false;
  return !a.present || (a.surface == b.surface && a.name == b.name && a.mode == b.mode &&
                        a.tag == b.tag && a.level == b.level && a.attributes == b.attributes &&
                        a.geometry == b.geometry && a.z_from == b.z_from);
}

// Conflict naming the transaction and the feature when a feature of `change` is no longer as
// `change` left it. Later edits that came to nothing (an edit and its revert, as when edits are
// reverted in reverse order) leave it as it was, and are no conflict.
Status CheckNoLaterEdits(Store& store, const Change& change) {
  for (int64_t f : change.features) {
    TB_ASSIGN_OR_RETURN(std::vector<FeatureVersion> versions, VersionsOfFeature(store, f));
    const FeatureVersion& now = versions.back();
    if (now.tx == change.tx) continue;
    const FeatureVersion* after = nullptr;
    for (const FeatureVersion& v : versions)
      if (v.tx <= change.tx) after = &v;
    if (after != nullptr && SameState(*after, now)) continue;
    TB_ASSIGN_OR_RETURN(Change later, ChangeOf(store, now.tx));
    return Status::Conflict("cannot revert " + Described(change) + ": feature " +
                            std::to_string(f) + " was changed again by " + Described(later) +
                            "; revert " + std::to_string(now.tx) +
                            " first, or give --cascade to revert both");
  }
  return Status::Ok();
}

// Transaction `tx` and every later transaction that touched one of their features, closed under
// that rule, with the features they touched.
Status CloseOverLaterEdits(Store& store, const Change& change, std::set<int64_t>* transactions,
                           std::set<int64_t>* features) {
  transactions->insert(change.tx);
  std::deque<int64_t> pending(change.features.begin(), change.features.end());
  features->insert(change.features.begin(), change.features.end());
  while (!pending.empty()) {
    const int64_t f = pending.front();
    pending.pop_front();
    TB_ASSIGN_OR_RETURN(std::vector<int64_t> later, LaterVersions(store, f, change.tx));
    for (int64_t t : later) {
      if (!transactions->insert(t).second) continue;
      TB_ASSIGN_OR_RETURN(std::vector<int64_t> touched, FeaturesTouchedBy(store, t));
      for (int64_t g : touched)
        if (features->insert(g).second) pending.push_back(g);
    }
  }
  return Status::Ok();
}

// Adds to `plan` what takes `feature` from its latest version back to its last version before
// transaction `first` (its state after first - 1).
Status PlanFeature(Store& store, int64_t feature, int64_t first, RevertPlan* plan) {
  TB_ASSIGN_OR_RETURN(std::vector<FeatureVersion> versions, VersionsOfFeature(store, feature));
  if (versions.empty())
    return Status::Corruption(std::string("feature ") + std::to_string(feature) +
                              " is touched by a transaction but has no version");
  const FeatureVersion& now = versions.back();
  const FeatureVersion* back = nullptr;
  for (const FeatureVersion& v : versions)
    if (v.tx < first) back = &v;
  const bool back_present = back != nullptr && back->present;
  // Back where it was (a revert of a revert inside the set): nothing to do.
  if (now.present && back_present && SameState(now, *back)) return Status::Ok();
  if (now.present) plan->remove.push_back(now);
  if (back_present) plan->restore.push_back(*back);
  return Status::Ok();
}

Result<SurfaceInfo> SurfaceOf(Store& store, const Change& change) {
  if (change.surface) return SurfaceStore(store).FindById(*change.surface);
  TB_ASSIGN_OR_RETURN(std::vector<FeatureVersion> versions,
                      VersionsOfFeature(store, change.features.front()));
  return SurfaceStore(store).FindById(versions.front().surface);
}

// The plan's features of `family` for one pass. The first takes out every feature that goes and
// puts back those whose id is free; the second puts back the features changed in place under one
// id, whose row had to go first. An ordinary revert is the first pass alone: one edit.
FeatureInverse InverseOf(const RevertPlan& plan, std::string_view family, bool second_pass) {
  std::set<int64_t> removed;
  for (const FeatureVersion& v : plan.remove) removed.insert(v.feature);
  FeatureInverse inverse;
  for (const FeatureVersion& v : plan.remove)
    if (!second_pass && InverseFamily(v.mode) == family) inverse.remove.push_back(v.feature);
  for (const FeatureVersion& v : plan.restore) {
    const bool in_place = removed.count(v.feature) > 0;
    if (InverseFamily(v.mode) == family && in_place == second_pass) inverse.restore.push_back(v);
  }
  return inverse;
}

}  // namespace

Result<RevertPlan> PlanRevert(Store& store, int64_t tx, const RevertOptions& options) {
  TB_ASSIGN_OR_RETURN(Change change, ChangeOf(store, tx));
  // An edit committed before the store had feature versions (migration 0015) left none.
  const bool old_edit = change.action.rfind("polygon ", 0) == 0;
  if (change.features.empty() && old_edit)
    return Status::InvalidArgument(Described(change) +
                                   " predates the feature versions of this store (migration "
                                   "0015): it cannot be reverted");
  if (change.features.empty())
    return Status::InvalidArgument(Described(change) +
                                   " is not an edit of features: only edits (polygon add, update, "
                                   "remove, points, revert) can be reverted");
  std::set<int64_t> transactions{tx};
  std::set<int64_t> features(change.features.begin(), change.features.end());
  if (options.cascade) {
    TB_RETURN_IF_ERROR(CloseOverLaterEdits(store, change, &transactions, &features));
  } else {
    TB_RETURN_IF_ERROR(CheckNoLaterEdits(store, change));
  }
  RevertPlan plan;
  TB_ASSIGN_OR_RETURN(plan.surface, SurfaceOf(store, change));
  plan.transactions.assign(transactions.begin(), transactions.end());
  plan.image_transactions = plan.transactions;
  // Each feature goes back to before the first undone transaction that touched it: every later
  // version of it is undone too (with --cascade the closure holds every transaction after tx that
  // touched it; without, the check made sure the later ones came to nothing).
  for (int64_t f : features) TB_RETURN_IF_ERROR(PlanFeature(store, f, change.tx, &plan));
  return plan;
}

Result<RevertPlan> PlanAsOf(Store& store, const SurfaceInfo& surface, int64_t tx) {
  TB_ASSIGN_OR_RETURN(const int64_t last, LastTransaction(store));
  if (tx > last)
    return Status::InvalidArgument(std::string("--as-of ") + std::to_string(tx) +
                                   ": that transaction is in the future (the store's last is " +
                                   std::to_string(last) + ")");
  TB_ASSIGN_OR_RETURN(std::optional<Change> built, FirstChangeOfSurface(store, surface.id));
  if (tx < 1 || (built && tx < built->tx))
    return Status::InvalidArgument(
        std::string("--as-of ") + std::to_string(tx) + ": surface '" + surface.name +
        "' did not exist yet" +
        (built ? " (it was built in transaction " + std::to_string(built->tx) + ")"
               : std::string()));
  TB_ASSIGN_OR_RETURN(std::optional<Change> other,
                      FirstChangeWithoutFeatures(store, surface.id, tx));
  if (other)
    return Status::InvalidArgument(std::string("--as-of ") + std::to_string(tx) + ": " +
                                   Described(*other) + " changed surface '" + surface.name +
                                   "' after it other than by a feature edit, so its feature "
                                   "versions cannot take it back");
  RevertPlan plan;
  plan.surface = surface;
  TB_ASSIGN_OR_RETURN(std::vector<Change> later, ChangesSince(store, tx));
  for (const Change& c : later)
    if (c.surface == surface.id) plan.image_transactions.push_back(c.tx);
  TB_ASSIGN_OR_RETURN(std::vector<int64_t> features, FeaturesChangedAfter(store, surface.id, tx));
  for (int64_t f : features) TB_RETURN_IF_ERROR(PlanFeature(store, f, tx + 1, &plan));
  return plan;
}

Result<RevertReport> ApplyRevertPlan(Store& store, const RevertPlan& plan,
                                     const std::string& action) {
  RevertReport report;
  report.reverted = plan.transactions;
  for (const FeatureVersion& v : plan.remove) report.removed_features.push_back(v.feature);
  for (const FeatureVersion& v : plan.restore) report.restored_features.push_back(v.feature);
  TB_ASSIGN_OR_RETURN(ExactRevertOutcome exact, TryExactRevert(store, plan, action));
  if (exact.exact) {
    report.exact = true;
    report.transactions.push_back(exact.done.tx);
    report.removed = exact.done.removed;
    report.added = exact.done.added;
    return report;
  }
  report.not_exact = exact.not_exact;
  std::set<std::string_view> families;
  for (const FeatureVersion& v : plan.remove) families.insert(InverseFamily(v.mode));
  for (const FeatureVersion& v : plan.restore) families.insert(InverseFamily(v.mode));
  for (const bool second_pass : {false, true}) {
    for (std::string_view family : families) {
      FeatureInverse inverse = InverseOf(plan, family, second_pass);
      if (inverse.remove.empty() && inverse.restore.empty()) continue;
      TB_ASSIGN_OR_RETURN(InverseApplier apply, InverseFor(family));
      TB_ASSIGN_OR_RETURN(InverseResult done, apply(store, plan.surface, inverse, action));
      report.transactions.push_back(done.tx);
      report.removed += done.removed;
      report.added += done.added;
    }
  }
  return report;
}

Result<RevertReport> RevertTransaction(Store& store, int64_t tx, const RevertOptions& options) {
  TB_ASSIGN_OR_RETURN(auto write, store.BeginWrite());
  TB_ASSIGN_OR_RETURN(RevertPlan plan, PlanRevert(store, tx, options));
  std::string action = "revert";
  for (int64_t t : plan.transactions) action += std::string(" ") + std::to_string(t);
  TB_ASSIGN_OR_RETURN(RevertReport report, ApplyRevertPlan(store, plan, action));
  if (options.before_commit && !report.transactions.empty())
    TB_RETURN_IF_ERROR(options.before_commit(store, report.transactions.back()));
  TB_RETURN_IF_ERROR(write->Commit());
  return report;
}

}  // namespace tinbase
