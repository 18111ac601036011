// FeatureVersions: the `feature_versions` table (docs/format.md, "Feature versions"), the one
// owner of its rows. Every edit that adds, updates or removes a feature writes, in its own
// transaction, one row per feature it touched: the feature as it is after that transaction, or a
// tombstone (the feature as it was when it went). A feature's state at any transaction is its last
// version at or before it, so revert, `history` and `export --as-of` read the past from here
// without replaying anything. Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "db/feature_store.h"
#include "db/store.h"

namespace tinbase {

struct FeatureVersion {
  int64_t feature = 0;
  int64_t tx = 0;  // the transaction that made this version
  int64_t surface = 0;
  bool present = true;  // false: the feature went in tx (the row keeps what it was)
  std::string name;     // as stored: the tag, or the label of the feature's source
  std::string mode;     // as stored: the revert of each mode family is chosen by it
  std::optional<std::string> tag;
  std::optional<double> level;
  std::string attributes;  // JSON text, as stored
  std::vector<uint8_t> geometry;
  std::string z_from = "dem";  // 'dem' or 'feature' (a 3D line's own z), as stored
  std::string action;          // of tx's `changes` row
  std::string time;            // of tx's `changes` row
};

// Moves the feature row `f` just written by WriteFeature to the id it must have: `wanted` when it
// is not 0 (a revert putting a feature back under its own id); else, when f.id was used by a
// feature that is gone (SQLite and the PostgreSQL trigger hand out 1 + the largest id, so a freed
// largest id comes back), past every id any version names, so that one id is one feature's
// history. Sets f.id. REQUIRES: inside a WriteTransaction, before any constraint row names f.id.
Status SettleFeatureId(Store& store, int64_t wanted, EditorFeature& f);

// Writes the versions of transaction `tx`: each feature of `written` as its row is now, each of
// `removed` as a tombstone copied from its row. REQUIRES: inside the WriteTransaction of tx, the
// rows of `removed` not deleted yet.
Status RecordFeatureVersions(Store& store, int64_t tx, const std::vector<int64_t>& written,
                             const std::vector<int64_t>& removed);

// Every version of `feature`, oldest first; empty when it never existed.
Result<std::vector<FeatureVersion>> VersionsOfFeature(Store& store, int64_t feature);

// The features each transaction after `since` touched, in id order, by transaction.
Result<std::map<int64_t, std::vector<int64_t>>> FeaturesTouchedSince(Store& store, int64_t since);

// The features transaction `tx` touched, in id order.
Result<std::vector<int64_t>> FeaturesTouchedBy(Store& store, int64_t tx);

// The last version of `feature` made at or before transaction `tx`; nullopt when it had none
// then (it did not exist yet).
Result<std::optional<FeatureVersion>> VersionAt(Store& store, int64_t feature, int64_t tx);

// The transactions after `tx` that touched `feature`, oldest first.
Result<std::vector<int64_t>> LaterVersions(Store& store, int64_t feature, int64_t tx);

// The features of surface `surface` with a version after transaction `tx`, in id order.
Result<std::vector<int64_t>> FeaturesChangedAfter(Store& store, int64_t surface, int64_t tx);

// The editor's feature of a version (its geometry decoded by mode: polygons, lines, or the points
// of a `points` feature), labelled with its stored name (which WriteFeature writes back as it
// was). InvalidArgument for an unknown mode; Corruption when its geometry does not parse.
Result<EditorFeature> EditorFeatureOf(const FeatureVersion& version);

}  // namespace tinbase
