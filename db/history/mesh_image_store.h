// MeshImageStore: the `mesh_images` table (docs/format.md, "Mesh images") and the reads and writes
// of mesh rows by key that the images need: capturing what an edit is about to change, reading a
// state back, and writing one (db/history/mesh_image.h). Everything goes through the db/sql seam,
// so both backends keep images. The edit path calls CaptureMeshBefore from its one writer
// (db/edit/mesh_delta_writer.h) and RecordMeshImage before its commit; exact reverts
// (db/history/exact_revert.h) load, read and write.
// Thread-safety: through one Store (its connection).
#pragma once

#include <cstdint>
#include <optional>

#include "core/base/status.h"
#include "db/edit/mesh_delta.h"
#include "db/history/mesh_image.h"
#include "db/sql/connection.h"
#include "db/store.h"

namespace tinbase {

// Adds to image->before the rows `delta` is about to change, as they are now, for every key the
// image has no row for yet (the first capture of a transaction wins). REQUIRES: inside the write
// transaction, before any row of `delta` is written.
Status CaptureMeshBefore(Connection& db, const MeshDelta& delta, MeshImage* image);

// Sets each key of `rows` to the row stored there now (nullopt or no constraints where none).
Status ReadMeshRows(Connection& db, int64_t surface, MeshRowSet* rows);

// Makes the stored rows at each key of `rows` what `rows` says: absent keys lose their row,
// present ones get it (under the key's id). REQUIRES: inside a WriteTransaction; every feature
// a constraint row names exists.
Status WriteMeshRows(Connection& db, int64_t surface, const MeshRowSet& rows);

// Completes `image` with the digest of its keys as they are now (the edit's rows all written) and
// stores it as the image of transaction `tx`. REQUIRES: inside tx's WriteTransaction.
Status RecordMeshImage(Store& store, int64_t tx, MeshImage image);

// Stores `image` as it is (its digest already set).
Status StoreMeshImage(Store& store, int64_t tx, const MeshImage& image);

// The image of transaction `tx`; nullopt when it has none (an edit made before migration 0016,
// or not an edit). Corruption when the stored bytes do not decode.
Result<std::optional<MeshImage>> LoadMeshImage(Store& store, int64_t tx);

}  // namespace tinbase
