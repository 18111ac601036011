// The one writer of an edit's mesh rows: applies a MeshDelta (db/edit/mesh_delta.h) to the
// triangles, vertices and constraints tables of a store in seven steps, each through the edit
// writes of MeshTables (db/mesh/mesh_tables.h, which holds their SQL). This file decides what
// goes in which step and in which statements (runs of ids, batches of one paint); the edit path
// writes mesh rows nowhere else.
//
// Ownership: borrows the connection. Not thread-safe.
#pragma once

#include <functional>

#include "core/base/status.h"
#include "db/edit/mesh_delta.h"
#include "db/sql/connection.h"

namespace tinbase {

struct SurfaceInfo;  // db/surface_store.h
struct MeshImage;    // db/history/mesh_image.h

// Called before each of the seven write steps with its number; a non-OK Status stops the write
// with it.
using WriteStepHook = std::function<Status(int step)>;

// Writes `delta`. Returns the number of stored triangles whose paint changed (the repaints'
// rows that did not have it already). Corruption when the rows deleted or numbered are not the
// ones the delta names (another writer came between); any error of the store; the hook's Status.
// On error some steps may have run: the caller's transaction rolls them back.
// When `image` is given, the rows the delta changes are added to its before-image first, as they
// are stored (db/history/mesh_image_store.h CaptureMeshBefore), for an exact revert.
// REQUIRES: inside a write transaction; the delta built in it from the rows as stored;
// delta.surface == surface.id.
Result<int64_t> WriteMeshDelta(Connection& db, const SurfaceInfo& surface, const MeshDelta& delta,
                               const WriteStepHook& step, MeshImage* image = nullptr);

}  // namespace tinbase
