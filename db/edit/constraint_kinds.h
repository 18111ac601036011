// Constraint kinds: `constraints.kind` is 'soft' for the rows of a softline feature and 'hard'
// for every other row (a breakline's, a polygon ring's, a row without feature), docs/design.md,
// "Soft lines and z from the feature". The kind follows from the owner's mode; it is stored so
// that exports and SQL users (the GeoPackage and PostGIS layers) read it without a join, and
// `tinbase check` verifies that it agrees (constraint-kind). Thread-safety: through one Store.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/base/status.h"
#include "db/mesh/mesh_edge.h"
#include "db/sql/connection.h"

namespace tinbase {

// Sets kind 'soft' on the rows `added` (edge, feature; 0 for none) of `surface` whose feature is a
// softline; the rows are written 'hard' (the column's default) and the others stay so.
// REQUIRES: inside a write transaction, after the rows were inserted.
Status MarkSoftConstraints(Connection& db, int64_t surface,
                           const std::vector<std::pair<MeshEdge, int64_t>>& added);

}  // namespace tinbase
