// The integrity checks of line kinds (db/integrity_check.h, docs/design.md "Invariants" 4 and
// 9): every constraint row's kind agrees with its feature's mode (constraint-kind), and every
// vertex of a 3D line's constraints lies at the z the 3D lines give it (line-z). Each returns the
// problems found as (code, text) pairs for the checker to report without a triangle, in a stable
// order. Thread-safety: reads through one Store.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "db/feature_store.h"
#include "db/store.h"

namespace tinbase {

using LineProblem = std::pair<std::string, std::string>;  // code, text

// constraint-kind: a row whose kind is not 'soft' for a softline's and 'hard' for any other
// (by constraint, in (va, vb, feature) order).
Result<std::vector<LineProblem>> CheckConstraintKinds(Store& store, const SurfaceInfo& surface);

// line-z: a vertex of a constraint of a 3D line feature (z from the feature) whose z differs from
// the z `lines` (the surface's 3D lines) give its plan position (by vertex id, once each).
Result<std::vector<LineProblem>> CheckLineZ(Store& store, const SurfaceInfo& surface,
                                            const LineElevation& lines);

}  // namespace tinbase
