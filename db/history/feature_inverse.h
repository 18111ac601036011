// FeatureInverse: how the features of one family of modes go back into a surface and out of it
// again when a revert (or `export --as-of`) undoes edits (docs/design.md, "Undo and history").
//
// A revert knows, from the feature versions, which features must go and which versions must come
// back; what it takes to put them back depends on how the features were drawn. Polygons and lines
// are draped on the DEM by the polygon editor; mass points (mode 'points') keep their own z and go
// through their own editor. Each family has one applier here, chosen by the stored mode, so a new
// family of edits plugs in with one line in InverseFor. Thread-safety: pure dispatch.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "db/history/feature_versions.h"
#include "db/store.h"
#include "db/surface_store.h"

namespace tinbase {

// One local edit of a surface that undoes others: the versions to put back, each under its own
// id (which no feature row holds), and the features to take out.
struct FeatureInverse {
  std::vector<FeatureVersion> restore;
  std::vector<int64_t> remove;
};

struct InverseResult {
  int64_t tx = 0;       // the transaction of the edit (its `changes` row says `action`)
  int64_t removed = 0;  // triangles
  int64_t added = 0;
};

// Applies `inverse` to `surface` as one edit with a `changes` row of `action` and the feature
// versions it makes. REQUIRES: inside a WriteTransaction the caller commits or drops; every
// feature of `inverse` of this applier's family. Errors as the family's editor.
using InverseApplier = Result<InverseResult> (*)(Store& store, const SurfaceInfo& surface,
                                                 const FeatureInverse& inverse,
                                                 const std::string& action);

// The family of a stored mode: "points" for mass points, "editor" for the polygon editor's modes
// (clip, erase, fill, replace, breakline and the line modes).
std::string_view InverseFamily(std::string_view mode);

// The applier of `family`; InvalidArgument naming it when that family has none wired.
Result<InverseApplier> InverseFor(std::string_view family);

}  // namespace tinbase
