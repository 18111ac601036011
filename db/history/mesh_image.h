// MeshImage: the before-image of the mesh rows one edit transaction changed, so that a revert can
// write the exact mesh back (docs/design.md, "Undo and history"; docs/format.md, "Mesh images").
//
// The rows are keyed as the tables know them: triangles and vertices by id, constraints by edge
// (a constraint row has no id; all rows of one edge go and come together). For each key the image
// holds the row as it was before the transaction, or nothing when the transaction made it. With
// it goes a digest of the same keys as the transaction left them: a revert writes the image back
// only when the rows there still give that digest (no later edit replaced them), so it never
// undoes someone else's rows. A MeshRowSet is also the form in which a revert reads, computes and
// writes a state. Encode/Decode is the stored form (zstd of a little-endian record).
// Plain values and pure functions; thread-safety as any value.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "core/base/status.h"
#include "db/mesh/mesh_edge.h"
#include "db/mesh/mesh_rows.h"

namespace tinbase {

// One row of `constraints` on a known edge.
struct EdgeConstraint {
  std::optional<int64_t> feature;  // nullopt: a constraint of the surface itself
  bool soft = false;               // kind 'soft' (a softline), else 'hard'

  friend bool operator==(const EdgeConstraint&, const EdgeConstraint&) = default;
  friend bool operator<(const EdgeConstraint& a, const EdgeConstraint& b) {
    return std::tie(a.feature, a.soft) < std::tie(b.feature, b.soft);
  }
};

// Mesh rows of one surface at a set of keys; nullopt (or no constraint row) where the key has
// no row. The keys are the maps' keys; edges are (va, vb) with va < vb, each edge's rows sorted.
struct MeshRowSet {
  std::map<int64_t, std::optional<TriangleRow>> triangles;
  std::map<int64_t, std::optional<VertexRow>> vertices;
  std::map<MeshEdge, std::vector<EdgeConstraint>> constraints;

  bool empty() const { return triangles.empty() && vertices.empty() && constraints.empty(); }
  // The keys of `other` this set lacks get `other`'s values; keys this set has stay as they are
  // (the earlier of two captures of one transaction wins).
  void AddMissing(const MeshRowSet& other);
  // Every key of `other` takes `other`'s value.
  void Overwrite(const MeshRowSet& other);
  // This set's values at the keys of `keys` (a key this set lacks is a bug: asserted).
  MeshRowSet At(const MeshRowSet& keys) const;
  // The keys whose value differs from `other`'s at the same key (REQUIRES: the same keys), with
  // this set's values: what must be written to turn `other` into this.
  MeshRowSet DifferentFrom(const MeshRowSet& other) const;
};

struct MeshImage {
  int64_t surface = 0;
  MeshRowSet before;
  uint64_t after_digest = 0;  // Digest of the same keys as the transaction left them
};

// A 64-bit digest (FNV-1a) of the rows and keys of `rows`, in key order.
uint64_t Digest(const MeshRowSet& rows);

// The stored form of `image`. Decode: Corruption naming `what` ("mesh image of transaction 12")
// when the bytes are not one.
std::vector<uint8_t> EncodeMeshImage(const MeshImage& image);
Result<MeshImage> DecodeMeshImage(const uint8_t* data, size_t size, const std::string& what);

}  // namespace tinbase
