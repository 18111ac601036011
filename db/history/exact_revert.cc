#include "db/history/exact_revert.h"

#include <algorithm>
#include <set>
#include <utility>
#include <vector>

#include "db/change_log.h"
#include "db/feature_store.h"
#include "db/history/feature_versions.h"
#include "db/history/mesh_image_store.h"

namespace tinbase {

namespace {

// The images of `txs`, newest first; nullopt with the reason when one is missing or is not of
// `surface`.
Result<std::optional<std::vector<MeshImage>>> ImagesNewestFirst(Store& store,
                                                                const std::vector<int64_t>& txs,
                                                                int64_t surface,
                                                                std::string* not_exact) {
  std::vector<MeshImage> images;
  for (auto t = txs.rbegin(); t != txs.rend(); ++t) {
    TB_ASSIGN_OR_RETURN(std::optional<MeshImage> image, LoadMeshImage(store, *t));
    if (!image || image->surface != surface) {
      *not_exact = "transaction " + std::to_string(*t) +
                   " kept no mesh image (it predates migration 0016 or is not an edit)";
      return std::optional<std::vector<MeshImage>>();
    }
    images.push_back(std::move(*image));
  }
  return std::optional<std::vector<MeshImage>>(std::move(images));
}

// The rows the images give when applied newest first to `now`; nullopt with the reason when an
// image finds its rows other than its transaction left them.
std::optional<MeshRowSet> Unwind(const MeshRowSet& now, const std::vector<MeshImage>& images,
                                 const std::vector<int64_t>& txs, std::string* not_exact) {
  MeshRowSet state = now;
  for (size_t k = 0; k < images.size(); ++k) {
    if (Digest(state.At(images[k].before)) != images[k].after_digest) {
      *not_exact = "the mesh rows transaction " + std::to_string(txs[txs.size() - 1 - k]) +
                   " wrote were changed since by another edit";
      return std::nullopt;
    }
    state.Overwrite(images[k].before);
  }
  return state;
}

// The feature rows of `plan` put back as they were: tombstones for the features that go, their
// rows deleted (a feature changed in place too), the restored versions written under their own
// ids with their versions in transaction `tx`.
Status RestoreFeatures(Store& store, const RevertPlan& plan, int64_t tx) {
  std::set<int64_t> restored;
  for (const FeatureVersion& v : plan.restore) restored.insert(v.feature);
  std::vector<int64_t> gone;
  for (const FeatureVersion& v : plan.remove)
    if (restored.count(v.feature) == 0) gone.push_back(v.feature);
  TB_RETURN_IF_ERROR(RecordFeatureVersions(store, tx, {}, gone));
  for (const FeatureVersion& v : plan.remove) TB_RETURN_IF_ERROR(DeleteFeature(store, v.feature));
  std::vector<int64_t> written;
  for (const FeatureVersion& v : plan.restore) {
    TB_ASSIGN_OR_RETURN(EditorFeature f, EditorFeatureOf(v));
    TB_RETURN_IF_ERROR(WriteFeature(store, plan.surface, tx, f));
    TB_RETURN_IF_ERROR(SettleFeatureId(store, v.feature, f));
    written.push_back(f.id);
  }
  return RecordFeatureVersions(store, tx, written, {});
}

// Fills the `changes` row of `tx`: the first feature restored (else removed), the triangles
// that went and came, and the extent of the undone changes.
Status RecordExactChange(Store& store, int64_t tx, const RevertPlan& plan, const MeshRowSet& now,
                         const MeshRowSet& after) {
  int64_t removed = 0, added = 0;
  for (const auto& [id, row] : now.triangles) {
    const bool before = row.has_value(), later = after.triangles.at(id).has_value();
    removed += before && !later;
    added += later && !before;
  }
  Box box;
  for (int64_t t : plan.image_transactions) {
    TB_ASSIGN_OR_RETURN(Change c, ChangeOf(store, t));
    box.Add(Point2{c.min_x, c.min_y});
    box.Add(Point2{c.max_x, c.max_y});
  }
  int64_t feature = 0;
  if (!plan.restore.empty()) feature = plan.restore.front().feature;
  if (feature == 0 && !plan.remove.empty()) feature = plan.remove.front().feature;
  TB_ASSIGN_OR_RETURN(Statement * update,
                      store.db().Cached("UPDATE changes SET feature = ?, removed = ?, added = ?, "
                                        "min_x = ?, min_y = ?, max_x = ?, max_y = ? WHERE tx = ?"));
  if (feature != 0) {
    update->Bind(1, feature);
  } else {
    update->BindNull(1);
  }
  update->Bind(2, removed).Bind(3, added);
  update->Bind(4, box.min_x).Bind(5, box.min_y).Bind(6, box.max_x).Bind(7, box.max_y);
  return update->Bind(8, tx).Run();
}

}  // namespace

Result<ExactRevertOutcome> TryExactRevert(Store& store, const RevertPlan& plan,
                                          const std::string& action) {
  ExactRevertOutcome out;
  const std::vector<int64_t>& txs = plan.image_transactions;
  if (txs.empty()) {
    out.not_exact = "no transaction to take back";
    return out;
  }
  TB_ASSIGN_OR_RETURN(std::optional<std::vector<MeshImage>> images,
                      ImagesNewestFirst(store, txs, plan.surface.id, &out.not_exact));
  if (!images) return out;
  MeshRowSet now;
  for (const MeshImage& image : *images) now.AddMissing(image.before);
  TB_RETURN_IF_ERROR(ReadMeshRows(store.db(), plan.surface.id, &now));
  std::optional<MeshRowSet> after = Unwind(now, *images, txs, &out.not_exact);
  if (!after) return out;

  Change change;
  change.surface = plan.surface.id;
  change.action = action;
  TB_ASSIGN_OR_RETURN(out.done.tx, AppendChange(store, change));
  TB_RETURN_IF_ERROR(RestoreFeatures(store, plan, out.done.tx));
  // Rows the images leave as they are now (a repaint that came to nothing) are not rewritten.
  TB_RETURN_IF_ERROR(WriteMeshRows(store.db(), plan.surface.id, after->DifferentFrom(now)));
  // Its own image: what it replaced, and how it left those rows (undoing it redoes exactly).
  TB_RETURN_IF_ERROR(StoreMeshImage(store, out.done.tx, {plan.surface.id, now, Digest(*after)}));
  TB_RETURN_IF_ERROR(RecordExactChange(store, out.done.tx, plan, now, *after));
  for (const auto& [id, row] : now.triangles) out.done.removed += row && !after->triangles.at(id);
  for (const auto& [id, row] : after->triangles) out.done.added += row && !now.triangles.at(id);
  out.exact = true;
  return out;
}

}  // namespace tinbase
